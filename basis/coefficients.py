"""Coefficients of a target Fresnel curve in the eigen-basis: the Python API engines call.

Public objects: ``coefficients_from_samples``, ``coefficients_from_curve``, ``coefficients_from_table``,
``coefficients_from_nk``, ``coefficients_from_gulbrandsen``, ``reconstruct``, ``fit_matrix``,
``fit_condition_number``.

The four-point scheme of Belcour et al. 2020 ("Coefficients"): the target is sampled at the basis'
fit angles θ0 = 0, θ1 = π/2, θ2, θ3 and the K × K system Σ_k c_k b_k(θ_i) = F(θ_i) is solved. Because
b_k(0) = 0 for k ≥ 1 and b_k(π/2) = 0 for k ≥ 2 (see :mod:`basis.svd`), this gives c0 = F(0) and
c1 = F(π/2) − F(0) exactly, and c2, c3 from a 2 × 2 solve. Shapes: a target of shape (...) gives
coefficients (..., K); an RGB material (..., 3) gives (..., 3, 4).

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4 and "Coefficients".
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from scipy.interpolate import CubicSpline

from .eigenbasis import Basis, default_basis
from .fresnel import ETA_RANGE, KAPPA_RANGE, _fresnel
from .gulbrandsen import gulbrandsen_to_nk
from .validation import ParameterError, as_float_array, check_range

__all__ = [
    "coefficients_from_curve",
    "coefficients_from_gulbrandsen",
    "coefficients_from_nk",
    "coefficients_from_samples",
    "coefficients_from_table",
    "fit_condition_number",
    "fit_matrix",
    "reconstruct",
]


def _basis(basis: Basis | None) -> Basis:
    if basis is None:
        return default_basis()
    if not isinstance(basis, Basis):
        raise ParameterError(f"basis must be a fresnel basis.Basis or None, got {type(basis).__name__}")
    return basis


def fit_matrix(basis: Basis | None = None) -> np.ndarray:
    """B[i, k] = b_k(θ_i) at the fit angles: the system the four-point solver inverts."""
    basis = _basis(basis)
    return basis.evaluate(basis.fit_angles)


def fit_condition_number(basis: Basis | None = None) -> float:
    """2-norm condition number of :func:`fit_matrix` (amplification of errors in the samples)."""
    return float(np.linalg.cond(fit_matrix(basis)))


def coefficients_from_samples(samples, basis: Basis | None = None) -> np.ndarray:
    """Coefficients from the target's values at the fit angles.

    Parameters
    ----------
    samples : array_like
        (..., K): F(θ_i) at ``basis.fit_angles``, finite.

    Returns
    -------
    numpy.ndarray
        (..., K) coefficients c with Σ_k c_k b_k(θ_i) = F(θ_i).
    """
    basis = _basis(basis)
    samples = as_float_array("samples", samples)
    if samples.ndim == 0 or samples.shape[-1] != basis.n_terms:
        raise ParameterError(
            f"samples must have a trailing axis of length {basis.n_terms} (one value per fit angle), "
            f"got shape {samples.shape}"
        )
    return samples @ np.linalg.inv(fit_matrix(basis)).T


def coefficients_from_curve(curve: Callable, variable: str = "theta", basis: Basis | None = None) -> np.ndarray:
    """Coefficients of a callable F(θ) (``variable="theta"``) or F(cos θ) (``variable="mu"``).

    The callable receives a 1-D array of the K fit angles (or their cosines) and must return an array
    whose last axis has length K (any leading material axes are kept).
    """
    basis = _basis(basis)
    if not callable(curve):
        raise ParameterError(f"curve must be callable, got {type(curve).__name__}")
    if variable == "theta":
        argument = basis.fit_angles.copy()
    elif variable == "mu":
        argument = np.cos(basis.fit_angles)
        argument[basis.fit_angles == 0.5 * np.pi] = 0.0
    else:
        raise ParameterError(f"variable must be 'theta' or 'mu', got {variable!r}")
    return coefficients_from_samples(as_float_array("curve(angles)", curve(argument)), basis)


def coefficients_from_table(theta, values, basis: Basis | None = None) -> np.ndarray:
    """Coefficients of a tabulated curve: ``values`` (..., M) at increasing angles ``theta`` (M,).

    The table must cover [0, π/2]; it is interpolated by a cubic spline in θ at the fit angles.
    """
    basis = _basis(basis)
    theta = check_range("theta", theta, 0.0, 0.5 * np.pi)
    values = as_float_array("values", values)
    if theta.ndim != 1 or theta.size < 4 or np.any(np.diff(theta) <= 0):
        raise ParameterError("theta must be a strictly increasing 1-D array of at least 4 angles")
    if theta[0] > 1e-12 or theta[-1] < 0.5 * np.pi - 1e-12:
        raise ParameterError(f"theta must cover [0, pi/2], got [{theta[0]}, {theta[-1]}]")
    if values.ndim == 0 or values.shape[-1] != theta.size:
        raise ParameterError(f"values must have a trailing axis of length {theta.size}, got shape {values.shape}")
    spline = CubicSpline(theta, values, axis=-1, bc_type=((1, np.zeros(values.shape[:-1])), "not-a-knot"))
    return coefficients_from_samples(spline(basis.fit_angles), basis)


def coefficients_from_nk(eta, kappa, basis: Basis | None = None) -> np.ndarray:
    """Coefficients of the exact Fresnel curve of η + iκ, e.g. per RGB channel: (..., 3) → (..., 3, K).

    Parameters
    ----------
    eta : array_like
        In [1e-8, 1e6]. η < 1 with κ = 0 (internal reflection) is accepted, but its curve has a kink at the
        critical angle that four smooth terms can only approximate.
    kappa : array_like
        In [0, 1e6].

    Examples
    --------
    >>> c = coefficients_from_nk([0.27, 0.68, 1.32], [3.61, 2.64, 1.81])  # gold-like RGB
    >>> c.shape
    (3, 4)
    """
    basis = _basis(basis)
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    mu = np.cos(basis.fit_angles)
    mu[basis.fit_angles == 0.5 * np.pi] = 0.0
    return coefficients_from_samples(_fresnel(mu, eta[..., None], kappa[..., None]), basis)


def coefficients_from_gulbrandsen(reflectivity, edge_tint, basis: Basis | None = None) -> np.ndarray:
    """Coefficients of the exact Fresnel curve of Gulbrandsen's (r, g), e.g. per RGB channel.

    r in [0, 1), g in [0, 1]; shapes broadcast; (..., 3) → (..., 3, K).
    """
    eta, kappa = gulbrandsen_to_nk(reflectivity, edge_tint)
    return coefficients_from_nk(eta, kappa, basis)


def reconstruct(coefficients, mu, basis: Basis | None = None) -> np.ndarray:
    """Σ_k c_k b_k(arccos μ): coefficients (..., K) and μ broadcast over the leading axes → (...)."""
    basis = _basis(basis)
    coefficients = as_float_array("coefficients", coefficients)
    if coefficients.ndim == 0 or coefficients.shape[-1] != basis.n_terms:
        raise ParameterError(
            f"coefficients must have a trailing axis of length {basis.n_terms}, got shape {coefficients.shape}"
        )
    return np.sum(coefficients * basis.evaluate_mu(mu), axis=-1)
