"""Angles of incidence: cos θ, the θ grids of the basis, their trapezoid weights and the θ spline.

Public objects: ``cos_theta``, ``GRID_KINDS``, ``angle_grid``, ``check_theta_grid``, ``trapezoid_weights``,
``theta_spline``.

Every curve of this project is a function of θ ∈ [0, π/2] (radians) or of μ = cos θ. A curve tabulated
on a θ grid is interpolated by one cubic spline in θ with zero slope at θ = 0 (a Fresnel curve is a
smooth function of cos θ, hence even in θ) and not-a-knot at π/2.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4 (curves of θ) and the authors' notebook (uniform in cos θ).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .validation import ParameterError, check_choice, check_positive_int, check_range

if TYPE_CHECKING:
    from scipy.interpolate import CubicSpline

__all__ = ["GRID_KINDS", "angle_grid", "check_theta_grid", "cos_theta", "theta_spline", "trapezoid_weights"]

#: θ sampling of the basis: uniform in θ, or uniform in μ = cos θ (denser near normal incidence).
GRID_KINDS = ("theta", "mu")


def cos_theta(theta) -> np.ndarray:
    """μ = cos θ with cos(π/2) exactly 0 (floating point gives 6e-17, which is not grazing)."""
    mu = np.cos(np.asarray(theta, dtype=np.float64))
    return np.where(np.asarray(theta) == 0.5 * np.pi, 0.0, mu)


def angle_grid(size: int, kind: str = "theta") -> np.ndarray:
    """θ samples in [0, π/2], both ends included, increasing.

    ``kind="theta"`` is uniform in θ (resolves the grazing region as well as normal incidence);
    ``kind="mu"`` is uniform in cos θ, as the authors' notebook does.
    """
    size = check_positive_int("size", size, low=16)
    if kind == "theta":
        return np.linspace(0.0, 0.5 * np.pi, size)
    if kind == "mu":
        return np.arccos(np.linspace(1.0, 0.0, size))
    check_choice("grid kind", kind, GRID_KINDS)
    raise AssertionError("unreachable: GRID_KINDS are the two kinds above")


def trapezoid_weights(theta: np.ndarray) -> np.ndarray:
    """Trapezoid-rule weights of the grid ``theta`` (the inner product of the SVD and of least squares)."""
    steps = np.diff(theta)
    weights = np.zeros_like(theta)
    weights[:-1] += 0.5 * steps
    weights[1:] += 0.5 * steps
    return weights


def theta_spline(theta: np.ndarray, values: np.ndarray, axis: int = -1) -> CubicSpline:
    """Cubic spline in θ of curves ``values`` sampled at ``theta`` (M,) along ``axis``: zero slope at
    θ = 0, not-a-knot at π/2. Unchecked: callers validate the grid."""
    from scipy.interpolate import CubicSpline  # scipy loads in 0.25 s: when a spline is first needed

    values = np.asarray(values, dtype=np.float64)
    slope = np.zeros(np.delete(values.shape, axis))
    return CubicSpline(theta, values, axis=axis, bc_type=((1, slope), "not-a-knot"))


def check_theta_grid(name: str, theta) -> np.ndarray:
    """A tabulation grid: a strictly increasing 1-D array of at least 4 angles covering [0, π/2]."""
    theta = check_range(name, theta, 0.0, 0.5 * np.pi)
    if theta.ndim != 1 or theta.size < 4 or np.any(np.diff(theta) <= 0):
        raise ParameterError(f"{name} must be a strictly increasing 1-D array of at least 4 angles")
    if theta[0] > 1e-12 or theta[-1] < 0.5 * np.pi - 1e-12:
        raise ParameterError(f"{name} must cover [0, pi/2], got [{theta[0]}, {theta[-1]}]")
    return theta
