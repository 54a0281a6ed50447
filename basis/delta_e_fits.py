"""Coefficient fits in colour: minimise CIEDE2000 between a fitted RGB curve and its ground truth.

Public objects: ``minimise_delta_e``, ``fit_summary``, ``delta_e_coefficients``.

The measure is Hoffman's: ΔE2000 over incidence angles, here on a 0.25° grid so that a fit is not fitted
to the scoring samples (0°, 1°, …, 90°). Used by the ``delta-e`` fits of
:data:`basis.coefficients.COEFFICIENT_FITS` and by the report's Gulbrandsen fits; loads colour-science.

References
----------
:cite:`Hoffman2020` SIGGRAPH 2020 course notes, ΔE2000 tables.
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4–5.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import scipy.optimize

from .angles import cos_theta
from .colorimetry import delta_E_2000_components, rgb_to_Lab
from .eigenbasis import Basis

__all__ = ["delta_e_coefficients", "fit_summary", "minimise_delta_e"]

#: The grid the ``delta-e`` fits minimise on (0.25°).
FIT_DEGREES = np.linspace(0.0, 90.0, 361)


def minimise_delta_e(
    reference_Lab: np.ndarray,
    rgb_of: Callable[[np.ndarray], np.ndarray],
    initial: np.ndarray,
    space: str,
    bounds=(-np.inf, np.inf),
) -> scipy.optimize.OptimizeResult:
    """Parameters p minimising Σ ΔE2000(reference, rgb_of(p))² over the curve's samples.

    The residuals are the three components of :func:`basis.colorimetry.delta_E_2000_components` at every
    sample, whose squares sum to ΔE2000² exactly and which, unlike ΔE, are smooth at the optimum: a
    Levenberg–Marquardt fit (``method="lm"``; trust-region reflective with ``bounds``) then converges in
    a few Jacobians. ``rgb_of`` maps parameters (..., P) to RGB curves (..., A, 3) and must accept a stack
    of parameter vectors: the forward-difference Jacobian evaluates all P perturbations in one call.

    Returns scipy's result: ``x``, ``status`` (> 0: converged), ``nfev``, ``optimality`` (‖∇‖∞), ``cost``.
    """

    def residuals(parameters: np.ndarray) -> np.ndarray:
        return delta_E_2000_components(reference_Lab, rgb_to_Lab(rgb_of(parameters), space)).reshape(
            *np.shape(parameters)[:-1], -1
        )

    upper = np.broadcast_to(bounds[1], np.shape(initial))

    def jacobian(parameters: np.ndarray) -> np.ndarray:
        step = 1e-7 * np.maximum(1.0, np.abs(parameters))
        step = np.where(np.isfinite(upper) & (parameters + step > upper), -step, step)  # stay inside an upper bound
        return ((residuals(parameters + np.diag(step)) - residuals(parameters)) / step[:, None]).T

    bounded = np.any(np.isfinite(bounds[0])) or np.any(np.isfinite(bounds[1]))
    return scipy.optimize.least_squares(
        residuals,
        initial,
        jac=jacobian,
        bounds=bounds,
        method="trf" if bounded else "lm",
        xtol=1e-12,
        ftol=1e-12,
        gtol=1e-12,
    )


def fit_summary(result: scipy.optimize.OptimizeResult) -> dict:
    """What a preset records of its fit: converged or not, scipy's status, evaluations, final gradient."""
    return {
        "converged": bool(result.status > 0),
        "status": int(result.status),
        "evaluations": int(result.nfev),
        "gradient": float(f"{result.optimality:.3g}"),
    }


def delta_e_coefficients(
    values_of: Callable, space: str, basis: Basis, start: np.ndarray, free_f0: bool, report: dict | None = None
) -> np.ndarray:
    """(3, K): minimise Σ_θ ΔE2000² over c2 … c_{K−1} (and c0 if ``free_f0``) from the coefficients
    ``start`` (3, K), with c0 + c1 = F90 kept exact (and c0 = F0 unless ``free_f0``).

    ``values_of`` maps μ (A,) to the RGB curve (3, A); the ``delta-e`` entries of
    :data:`basis.coefficients.COEFFICIENT_FITS` call this. ``report``, if given, receives
    :func:`fit_summary` of the minimisation.
    """
    theta = np.deg2rad(FIT_DEGREES)
    truth = values_of(cos_theta(theta)).T
    reference = rgb_to_Lab(truth, space)
    curves = basis.evaluate(theta)  # (A, K)
    f90 = truth[-1]
    # F = c0 (b0 − b1) + F90 b1 + Σ_{k≥2} c_k b_k once c1 = F90 − c0
    fixed = f90[:, None] * curves[:, 1] + (0.0 if free_f0 else start[:, :1] * (curves[:, 0] - curves[:, 1]))
    shapes = [curves[:, 0] - curves[:, 1]] if free_f0 else []
    if not shapes and curves.shape[1] == 2:  # two terms with F0 and F90 exact: nothing is left to fit
        return np.array(start, dtype=np.float64)
    shape = np.stack([*shapes, *curves[:, 2:].T], axis=1)  # (A, free terms)
    initial = np.concatenate([start[:, :1], start[:, 2:]], axis=1) if free_f0 else start[:, 2:]

    def rgb_of(free: np.ndarray) -> np.ndarray:
        return fixed.T + np.einsum("...cj,aj->...ac", free.reshape(*free.shape[:-1], 3, -1), shape)

    result = minimise_delta_e(reference, rgb_of, initial.ravel(), space)
    if report is not None:
        report.update(fit_summary(result))
    free = result.x.reshape(3, -1)
    c0 = free[:, :1] if free_f0 else start[:, :1]
    return np.concatenate([c0, f90[:, None] - c0, free[:, 1:] if free_f0 else free], axis=1)
