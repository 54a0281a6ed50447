"""Minimax refinement of an eigen-basis: curves and fit angles that minimise the worst four-point error.

Public objects: ``refine_basis``.

The iterative SVD (:mod:`.svd`) minimises the mean square of the *normalised* residual; the product is
judged by the worst error in F of the four-point fit (Belcour et al. 2020, "Coefficients"). The four-point
reconstruction c = B(θ_fit)⁻¹ F(θ_fit), F ≈ Σ_k c_k b_k depends only on the span of b0 … b_{K−1} and on
the fit angles, so the refinement moves b1 … b_{K−1} within a dictionary of further SVD curves d_j of the
training curves (each vanishes at 0 and π/2, so c0 = F(0) and c1 = F(π/2) − F(0) stay exact) and moves the
fit angles θ2 … θ_{K−1}. It minimises the p-norm of the error scaled by each curve's tolerance τ_n,

    L_p = ( mean_{n,j} | (Σ_k c_nk b_k(θ_j) − F_n(θ_j)) / τ_n |^p )^{1/p},

for increasing p (a continuation towards the max norm, which L_p approaches as p grows), by L-BFGS-B with
the analytic gradient: with C = S A⁻ᵀ (S the curves at the fit angles, A = B(θ_fit)) and G = ∂L/∂(C Bᵀ),
∂L/∂B = Gᵀ C, ∂L/∂C = G B, ∂L/∂A = −A⁻ᵀ (∂L/∂C)ᵀ C and ∂L/∂S = (∂L/∂C) A⁻¹.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4 and "Coefficients".
"""

from __future__ import annotations

from collections.abc import Callable, Mapping

import numpy as np

from ..angles import check_theta_grid, theta_spline, trapezoid_weights
from ..eigenbasis import Basis, default_basis
from ..parallel import one_blas_thread
from ..validation import ParameterError, as_float_array, check_positive_int
from .svd import build_curves

__all__ = ["refine_basis"]

#: Fit angles stay in [ANGLE_BOUNDS]: away from 0 and π/2, whose rows the four-point system already holds.
ANGLE_BOUNDS = (0.2, 0.5 * np.pi - 0.005)

#: An SVD element whose residual RMS before it is below this share of the first one's is noise, not shape.
RANK_TOLERANCE = 1e-9

#: Most SVD elements computed (basis terms and dictionary together), as :func:`.svd.build_curves` allows.
MAX_ELEMENTS = 16


class _Objective:
    """L_p of the four-point error and its gradient in (dictionary weights, fit angles).

    ``blocks`` are (rows of ``curves``, operator): the error of those curves is measured as it is, or, with
    an operator W (P, M), as W applied to it (e.g. texel weights: the error of F̄ instead of F).
    """

    def __init__(self, theta, curves, tolerances, start, dictionary, blocks):
        self.curves, self.tolerances, self.blocks = curves, tolerances, blocks
        self.n_terms, self.size = start.shape[0], dictionary.shape[0]
        self.spline = theta_spline(theta, np.concatenate([start, dictionary]).T, axis=0)
        self.on_grid = self.spline(theta)  # (M, K + D)
        self.target_spline = theta_spline(theta, curves.T, axis=0)
        self.power = 2.0

    def mixing(self, weights: np.ndarray) -> np.ndarray:
        """(K + D, K): basis curve k = start_k + Σ_j weights[k − 1, j] d_j for k ≥ 1."""
        k, d = self.n_terms, self.size
        matrix = np.zeros((k + d, k))
        matrix[:k] = np.eye(k)
        matrix[k:, 1:] = weights.reshape(k - 1, d).T
        return matrix

    def split(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        cut = (self.n_terms - 1) * self.size
        return x[:cut], np.concatenate([[0.0, 0.5 * np.pi], x[cut:]])

    def errors(self, x: np.ndarray):
        """The scaled errors, one array per block, and what the gradient needs."""
        weights, angles = self.split(x)
        mixing = self.mixing(weights)
        system = self.spline(angles) @ mixing
        inverse = np.linalg.inv(system)
        coefficients = self.target_spline(angles).T @ inverse.T
        on_grid = self.on_grid @ mixing
        residual = coefficients @ on_grid.T - self.curves
        scaled = [
            (residual[rows] if operator is None else residual[rows] @ operator.T) / self.tolerances[rows, None]
            for rows, operator in self.blocks
        ]
        return scaled, (mixing, angles, inverse, coefficients, on_grid)

    def __call__(self, x: np.ndarray) -> tuple[float, np.ndarray]:
        try:
            scaled, (mixing, angles, inverse, coefficients, on_grid) = self.errors(x)
        except np.linalg.LinAlgError:  # a trial step where the fit angles make the system singular: step back
            return np.inf, np.zeros_like(x)
        largest = max(float(np.max(np.abs(block))) for block in scaled)
        if not np.isfinite(largest):
            return np.inf, np.zeros_like(x)
        p = self.power
        count = sum(block.size for block in scaled)
        mean = sum(float(np.sum(np.abs(block / largest) ** p)) for block in scaled) / count
        loss = largest * mean ** (1.0 / p)
        # ∂L/∂e = mean^{1/p − 1} |u|^{p−1} sign(u) / n with u = e / max|e| (L is homogeneous of degree 1)
        gradient = np.zeros_like(self.curves)
        for (rows, operator), block in zip(self.blocks, scaled):
            unit = block / largest
            piece = (
                mean ** (1.0 / p - 1.0)
                * np.abs(unit) ** (p - 1.0)
                * np.sign(unit)
                / count
                / self.tolerances[rows, None]
            )
            gradient[rows] = piece if operator is None else piece @ operator
        d_grid = gradient.T @ coefficients
        d_coefficients = gradient @ on_grid
        d_system = -inverse.T @ d_coefficients.T @ coefficients
        d_samples = d_coefficients @ inverse
        d_mixing = self.on_grid.T @ d_grid + self.spline(angles).T @ d_system
        d_weights = d_mixing[self.n_terms :, 1:].T.ravel()
        slopes = self.spline(angles, 1) @ mixing  # (K, K): b_k'(θ_i)
        target_slopes = self.target_spline(angles, 1).T  # (N, K)
        d_angles = (np.sum(d_samples * target_slopes, axis=0) + np.sum(d_system * slopes, axis=1))[2:]
        return loss, np.concatenate([d_weights, d_angles])


def refine_basis(
    theta,
    groups: Mapping[str, tuple],
    n_terms: int = 4,
    start: Basis | None = None,
    dictionary_terms: int = 10,
    powers=(16.0, 64.0),
    iterations: int = 500,
    progress: Callable[[str], None] | None = None,
) -> Basis:
    """A basis whose four-point fit minimises the worst error over ``groups`` relative to their tolerances.

    Parameters
    ----------
    theta : array_like
        (M,) increasing grid over [0, π/2] on which the training curves are sampled; the new basis lives on it.
    groups : mapping
        name → (curves (N, M) of F(θ_j), tolerance > 0) or (curves, tolerance, operator): the error of a curve
        counts as error / tolerance, where the error is the fit's over θ, or the operator (P, M) applied to it
        (e.g. :func:`preintegrate.quadrature.texel_weights` over a material's roughness range: the error of F̄).
    n_terms : int
        K in [2, 8] (with K = 2 only the shape of b1 moves: the fit is F0 and F90).
    start : Basis, optional
        The basis to refine (its angles are the starting angles); default the plain SVD of the curves, whose
        elements beyond the curves' rank (fewer distinct shapes than terms) are smooth fillers: the shipped
        basis' elements, then sin(jπ cos θ).
    dictionary_terms : int
        D, the SVD curves each b_k may mix in, in [1, 14] (fewer when the curves' rank is lower).
    powers : sequence of float
        The p of each continuation stage, each ≥ 2.
    iterations : int
        L-BFGS-B iterations per stage.

    Returns
    -------
    Basis
        ``training["refinement"]`` holds the groups, tolerances, powers and the achieved worst error per group.
    """
    from scipy.optimize import minimize

    theta = check_theta_grid("theta", theta)
    n_terms = check_positive_int("n_terms", n_terms, low=2, high=8)
    dictionary_terms = check_positive_int("dictionary_terms", dictionary_terms, low=1, high=MAX_ELEMENTS - 2)
    iterations = check_positive_int("iterations", iterations, low=1, high=100_000)
    if not groups:
        raise ParameterError("refine_basis needs at least one group of curves")
    names, parts, tolerances, blocks, start_row = [], [], [], [], 0
    for name, group in groups.items():
        if not isinstance(group, tuple) or len(group) not in (2, 3):
            raise ParameterError(f"groups[{name!r}] must be (curves, tolerance) or (curves, tolerance, operator)")
        curves, tolerance, operator = (*group, None)[:3]
        curves = as_float_array(f"groups[{name!r}] curves", curves)
        if curves.ndim != 2 or curves.shape[1] != theta.size or not np.all(np.isfinite(curves)):
            raise ParameterError(f"groups[{name!r}] curves must be finite, of shape (N, {theta.size})")
        if not (np.isfinite(tolerance) and tolerance > 0):
            raise ParameterError(f"groups[{name!r}] tolerance must be positive, got {tolerance!r}")
        if operator is not None:
            operator = as_float_array(f"groups[{name!r}] operator", operator)
            if operator.ndim != 2 or operator.shape[1] != theta.size or not np.all(np.isfinite(operator)):
                raise ParameterError(f"groups[{name!r}] operator must be finite, of shape (P, {theta.size})")
        names += [name] * curves.shape[0]
        parts.append(curves)
        tolerances.append(np.full(curves.shape[0], float(tolerance)))
        blocks.append((slice(start_row, start_row + curves.shape[0]), operator))
        start_row += curves.shape[0]
    powers = [float(p) for p in powers]
    if not powers or min(powers) < 2:
        raise ParameterError(f"powers must be a non-empty sequence of numbers >= 2, got {powers}")
    curves, tolerances, names = np.concatenate(parts), np.concatenate(tolerances), np.array(names)
    with one_blas_thread():  # the same bits whatever the machine's BLAS threads
        svd, stats = build_curves(theta, [curves], min(n_terms + dictionary_terms, MAX_ELEMENTS))
        # an element after the residual has vanished (fewer distinct curves than terms) is rounding noise
        residual = np.asarray(stats["residual_rms"])
        meaningful = 2 + int(np.count_nonzero(residual[1:-1] > RANK_TOLERANCE * max(residual[0], 1e-300)))
        if start is None:
            shaped = min(n_terms, meaningful)
            start_curves = np.concatenate([svd[:shaped], _smooth_fillers(theta, shaped)[: n_terms - shaped]])
            dictionary, angles = svd[n_terms:meaningful], np.linspace(1.45, 1.2, n_terms - 2)
        else:
            if start.n_terms != n_terms:
                raise ParameterError(f"start has {start.n_terms} terms, expected {n_terms}")
            start_curves, dictionary, angles = (
                start.evaluate(theta).T,
                svd[2:meaningful][:dictionary_terms],
                start.fit_angles[2:],
            )
        objective = _Objective(theta, curves, tolerances, start_curves, dictionary, blocks)
        x = np.concatenate([np.zeros((n_terms - 1) * dictionary.shape[0]), angles])
        bounds = [(None, None)] * ((n_terms - 1) * dictionary.shape[0]) + [ANGLE_BOUNDS] * (n_terms - 2)
        for power in powers:
            objective.power = power
            result = minimize(objective, x, jac=True, method="L-BFGS-B", bounds=bounds, options={"maxiter": iterations})
            if np.all(np.isfinite(result.x)) and np.isfinite(result.fun):
                x = result.x
            if progress is not None:
                progress(f"refine: p = {power:g}, L_p = {result.fun:.4g} after {result.nit} iterations")
        scaled, (mixing, angles, *_rest) = objective.errors(x)
        refined = objective.on_grid @ mixing
    worst = np.concatenate([np.max(np.abs(block), axis=1) for block in scaled]) * tolerances
    achieved = {name: float(np.max(worst[names == name])) for name in groups}
    return Basis(
        theta,
        _conventional(theta, refined.T),
        np.concatenate([[0.0, 0.5 * np.pi], np.round(angles[2:], 6)]),
        {
            "refinement": {
                "groups": {
                    name: {
                        "curves": int(np.count_nonzero(names == name)),
                        "tolerance": float(groups[name][1]),
                        "measure": "F" if len(groups[name]) == 2 or groups[name][2] is None else "operator",
                        "max_abs_error": achieved[name],
                    }
                    for name in groups
                },
                "dictionary_terms": dictionary_terms,
                "powers": powers,
                "iterations": iterations,
                "start": start.content_hash if start is not None else "svd",
            }
        },
    )


def _smooth_fillers(theta: np.ndarray, first: int) -> np.ndarray:
    """Smooth elements for a basis whose training curves have fewer shapes than terms: the shipped basis'
    elements from index ``first`` on, then sin(jπ cos θ), j = 1, 2, … (even in θ, zero at 0 and π/2)."""
    shipped = default_basis().evaluate(theta).T[max(first, 2) :]
    waves = np.sin(np.arange(1, MAX_ELEMENTS + 1)[:, None] * np.pi * np.cos(theta)[None, :])
    return np.concatenate([shipped, waves])


def _conventional(theta: np.ndarray, curves: np.ndarray) -> np.ndarray:
    """The same span in a well-conditioned form, with the basis file's conventions.

    The four-point fit depends only on the span and the fit angles, so the curves may be re-based freely
    within it: b2 … b_{K−1} are made orthonormal (QR in the trapezoid inner product over θ) and b1 loses its
    projection on them. Refined curves drift towards near-cancelling pairs; re-based, the coefficients stay of
    the size of the curve (the showcase scene's seven terms: max |c| 25 → 0.95, condition 4.6e3 → 299, the
    errors unchanged), which matters for half-float tables. Then b0 = 1, b1(0) = 0, b1(π/2) = 1, b_k (k ≥ 2)
    zero at both ends, scaled to max |b_k| = 1 with the largest sample positive (:func:`.svd.build_curves`)."""
    curves = curves.copy()
    if curves.shape[0] > 2:
        root = np.sqrt(trapezoid_weights(theta))
        orthonormal, _ = np.linalg.qr((curves[2:] * root).T)
        curves[2:] = (orthonormal / root[:, None]).T
        curves[2:, 0] = curves[2:, -1] = 0.0  # combinations of curves that vanish there: zero up to rounding
        curves[1] -= (curves[1] * root**2) @ curves[2:].T @ curves[2:]
    curves[0] = 1.0
    curves[1:, 0] = 0.0
    curves[1, -1] = 1.0
    for k in range(2, curves.shape[0]):
        curves[k, -1] = 0.0
        largest = curves[k][np.argmax(np.abs(curves[k]))]
        curves[k] /= largest
    return curves
