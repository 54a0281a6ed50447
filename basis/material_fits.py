"""Measured materials as basis coefficients: their ground-truth RGB curves and the fits of those curves.

Public objects: ``ANGLES_DEGREES``, ``rms_delta_E_2000``, ``material_curve``, ``fit_rgb_curve``,
``fit_material``. The presets themselves are written and read by :mod:`basis.presets`, which needs none
of this to read them.

A material's ground truth is its RGB Fresnel curve by Hoffman's spectral procedure
(:func:`basis.spectral.rgb_fresnel`). Its error is Hoffman's measure: the RMS over θ = 0°, 1°, …, 90° of
CIEDE2000 between the approximation and the ground truth (with this sampling his dielectric Schlick
column is reproduced to 0.01; ``tests/basis/test_material_fits.py``).

Coefficient fits (:data:`basis.coefficients.COEFFICIENT_FITS`); all keep F(90°) = c0 + c1 exact (white):

==================  ==============================================================================
``four-point``      the talk's scheme: the curve at the basis' fit angles (Belcour 2020, eq. 5)
``least-squares``   L2 over θ on the basis grid, c0 = F0 exact
                    (:func:`basis.coefficients_least_squares_from_table`)
``minimax``         the max norm over θ on the basis grid (Lawson's reweighting), c0 = F0 exact
``delta-e-exact-f0`` c2, c3 minimising Σ_θ ΔE2000² on a 0.25° grid, c0 = F0 exact, from the
                    least-squares start (:mod:`basis.delta_e_fits`)
``delta-e``         c0, c2, c3 minimising the same, c1 = F90 − c0: F0 may move by an invisible ΔE
                    (the presets report it as ``delta_e2000_at_0``); what the presets use
==================  ==============================================================================

The shader cost is the same for all of them: four multiply-adds per channel. Presets
(``luts/materials.json``) store the ``delta-e`` coefficients for ACEScg and sRGB, with F0, F82, the
data source and the achieved errors; they are tied to the basis by its content hash.

References
----------
:cite:`Hoffman2020` SIGGRAPH 2020 course notes, ΔE2000 tables and "Computing RGB Parameter Values From
    Spectral IOR Data".
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4–5.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import numpy as np

from .coefficients import coefficients_from_function
from .colorimetry import delta_E_2000, working_space
from .eigenbasis import Basis, resolve_basis
from .spectral import rgb_fresnel, spectral_ior

__all__ = [
    "ANGLES_DEGREES",
    "fit_material",
    "fit_rgb_curve",
    "material_curve",
    "rms_delta_E_2000",
]

#: Hoffman's angle sampling of "ΔE2000 averaged over all incidence angles": 0°, 1°, …, 90°.
ANGLES_DEGREES = np.arange(0.0, 91.0)

Curve = Callable[[np.ndarray], np.ndarray]


def rms_delta_E_2000(reference, approximation, space: str) -> float | np.ndarray:
    """RMS over the angle axis (second to last) of ΔE2000 between two RGB curves (..., A, 3) → (...)."""
    difference = delta_E_2000(reference, approximation, space)
    return np.sqrt(np.mean(difference**2, axis=-1))


def material_curve(name: str, space: str = "ACEScg") -> Curve:
    """The ground-truth RGB curve μ (...) → (..., 3) of a measured material in ``space``."""
    material = spectral_ior(name)
    working_space(space)
    return functools.partial(rgb_fresnel, material, space=space)


def fit_rgb_curve(
    curve: Curve,
    space: str = "ACEScg",
    fit: str = "delta-e",
    basis: Basis | None = None,
    start=None,
    report: dict | None = None,
) -> np.ndarray:
    """(3, K) coefficients of an RGB curve μ → (..., 3) by a fit of :data:`basis.coefficients.COEFFICIENT_FITS`
    (``start`` and ``report`` as in :func:`basis.coefficients.coefficients_from_function`)."""
    working_space(space)
    return coefficients_from_function(lambda mu: curve(mu).T, fit, basis, space, start, report)


_FITS: dict[tuple, tuple[np.ndarray, dict]] = {}


def fit_material(
    name: str, space: str = "ACEScg", fit: str = "delta-e", basis: Basis | None = None, report: dict | None = None
) -> np.ndarray:
    """(3, K) coefficients of a measured material by a fit of :data:`basis.coefficients.COEFFICIENT_FITS`
    (memoised per basis hash); ``report``, if given, receives the fit's convergence (iterative fits).

    Unlike :func:`basis.presets.material_coefficients` this always fits; the presets, the tables and the
    report share the fits through the memo, and the ``delta-e`` fit starts from the memoised
    ``delta-e-exact-f0`` one instead of computing it again.
    """
    basis = resolve_basis(basis)
    key = (name, space, fit, basis.content_hash)
    if key not in _FITS:
        start = fit_material(name, space, "delta-e-exact-f0", basis) if fit == "delta-e" else None
        summary: dict = {}
        coefficients = fit_rgb_curve(material_curve(name, space), space, fit, basis, start, summary)
        _FITS[key] = coefficients, summary
    coefficients, summary = _FITS[key]
    if report is not None:
        report.update(summary)
    return coefficients.copy()
