"""The report: measured studies of error against run time, their tables and plots. No product module
imports this package; the CLI's ``report``, ``materials`` and ``render`` commands do.

Public objects: ``write_report``.

Modules: ``readme`` (``write_report``: runs the studies, writes ``report/README.md``), ``lut_error`` (LUT
error against generation time), ``model_error`` (Fresnel representations: curve and preintegrated
error), ``approximation_error`` (the references' models projected onto the basis), ``basis_build``
(cost and convergence of the basis build), ``material_error`` (measured materials in ΔE2000),
``renders`` (pictures), ``figures`` (matplotlib, atomic PNG writes).
"""

from .readme import write_report

__all__ = ["write_report"]
