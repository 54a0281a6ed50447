"""Coefficients of a target Fresnel curve in the eigen-basis: the Python API engines call.

Public objects: ``COEFFICIENT_FITS``, ``coefficient_fit``, ``coefficients_from_function``,
``coefficients_from_samples``, ``coefficients_from_curve``, ``coefficients_from_table``, ``coefficients_from_nk``,
``coefficients_from_model``, ``coefficients_from_gulbrandsen``, ``coefficients_least_squares``,
``coefficients_least_squares_from_table``, ``LEAST_SQUARES_NORMS``, ``MODEL_FITS``, ``reconstruct``,
``reconstruction_error``, ``fit_matrix``, ``fit_condition_number``.

The four-point scheme of Belcour et al. 2020 ("Coefficients"): the target is sampled at the basis'
fit angles θ0 = 0, θ1 = π/2, θ2, θ3 and the K × K system Σ_k c_k b_k(θ_i) = F(θ_i) is solved. Because
b_k(0) = 0 for k ≥ 1 and b_k(π/2) = 0 for k ≥ 2 (see :mod:`basis.training`), this gives c0 = F(0) and
c1 = F(π/2) − F(0) exactly, and c2, c3 from a 2 × 2 solve. Shapes: a target of shape (...) gives
coefficients (..., K); an RGB material (..., 3) gives (..., 3, 4).

The least-squares alternative keeps c0 = F(0) and c1 = F(π/2) − F(0) (so F0 and F90 stay exact, as
engines need) and fits c2 … c_{K−1} to the residual F − c0 − c1 b1 on the basis' θ grid, either in the
plain L2 norm over θ (trapezoid weights) or, by Lawson's iteratively reweighted least squares, close to
the max norm.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4 and "Coefficients".
:cite:`Lawson1961` C. L. Lawson, "Contributions to the Theory of Linear Least Maximum Approximation",
    PhD thesis, UCLA, 1961 (w ← w |e| / Σ w |e| converges to the minimax weights); see also
    J. R. Rice and K. H. Usow, "The Lawson algorithm and extensions", Math. Comp. 22, 1968.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from .angles import check_theta_grid, cos_theta, theta_spline, trapezoid_weights
from .eigenbasis import Basis, resolve_basis
from .fresnel import ETA_RANGE, KAPPA_RANGE, fresnel_kernel, fresnel_normal_incidence
from .gulbrandsen import gulbrandsen_to_nk
from .validation import (
    ParameterError,
    as_float_array,
    check_broadcast,
    check_choice,
    check_positive_int,
    check_range,
    check_shape_last,
)

__all__ = [
    "COEFFICIENT_FITS",
    "LEAST_SQUARES_NORMS",
    "MODEL_FITS",
    "coefficient_fit",
    "coefficients_from_function",
    "coefficients_from_curve",
    "coefficients_from_gulbrandsen",
    "coefficients_from_model",
    "coefficients_from_nk",
    "coefficients_from_samples",
    "coefficients_from_table",
    "coefficients_least_squares",
    "coefficients_least_squares_from_table",
    "fit_condition_number",
    "fit_matrix",
    "reconstruct",
    "reconstruction_error",
]


def fit_matrix(basis: Basis | None = None) -> np.ndarray:
    """B[i, k] = b_k(θ_i) at the fit angles: the system the four-point solver inverts."""
    basis = resolve_basis(basis)
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
    basis = resolve_basis(basis)
    samples = as_float_array("samples", samples)
    check_shape_last("samples", samples, basis.n_terms)  # one value per fit angle
    with np.errstate(over="ignore", invalid="ignore"):
        coefficients = samples @ np.linalg.inv(fit_matrix(basis)).T
    if not np.all(np.isfinite(coefficients)):
        raise ParameterError(
            f"samples as large as {np.max(np.abs(samples)):.3g} overflow the coefficients (float64); "
            "a reflectance is at most 1"
        )
    return coefficients


def coefficients_from_curve(curve: Callable, variable: str = "theta", basis: Basis | None = None) -> np.ndarray:
    """Coefficients of a callable F(θ) (``variable="theta"``) or F(cos θ) (``variable="mu"``).

    The callable receives a 1-D array of the K fit angles (or their cosines) and must return an array
    whose last axis has length K (any leading material axes are kept).
    """
    basis = resolve_basis(basis)
    if not callable(curve):
        raise ParameterError(f"curve must be callable, got {type(curve).__name__}")
    if variable == "theta":
        argument = basis.fit_angles.copy()
    elif variable == "mu":
        argument = cos_theta(basis.fit_angles)
    else:
        raise ParameterError(f"variable must be 'theta' or 'mu', got {variable!r}")
    values = as_float_array("curve(angles)", curve(argument))
    if values.ndim == 0 or values.shape[-1] != basis.n_terms:
        raise ParameterError(
            f"curve must return one value per fit angle ({basis.n_terms}) along its last axis, got shape {values.shape}"
        )
    return coefficients_from_samples(values, basis)


def coefficients_from_table(theta, values, basis: Basis | None = None) -> np.ndarray:
    """Coefficients of a tabulated curve: ``values`` (..., M) at increasing angles ``theta`` (M,).

    The table must cover [0, π/2]; it is interpolated by a cubic spline in θ at the fit angles.
    """
    basis = resolve_basis(basis)
    return coefficients_from_samples(_table_spline(theta, values)(basis.fit_angles), basis)


def _table_spline(theta, values):
    """Validate a tabulated curve over [0, π/2] and return its cubic spline in θ (zero slope at 0)."""
    theta = check_theta_grid("theta", theta)
    values = as_float_array("values", values)
    check_shape_last("values", values, theta.size)
    return theta_spline(theta, values)


def coefficients_from_nk(eta, kappa, basis: Basis | None = None, fit: str = "four-point") -> np.ndarray:
    """Coefficients of the exact Fresnel curve of η + iκ, e.g. per RGB channel: (..., 3) → (..., 3, K).

    Parameters
    ----------
    eta : array_like
        In [1e-8, 1e6]. η < 1 with κ = 0 (internal reflection) is accepted, but its curve has a kink at the
        critical angle that four smooth terms can only approximate.
    kappa : array_like
        In [0, 1e6].
    fit : str
        ``four-point`` (the talk's), ``least-squares`` or ``minimax`` (:data:`COEFFICIENT_FITS`).

    Examples
    --------
    >>> c = coefficients_from_nk([0.27, 0.68, 1.32], [3.61, 2.64, 1.81])  # gold-like RGB
    >>> c.shape
    (3, 4)
    """
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    check_broadcast(eta=eta, kappa=kappa)
    if fit.startswith("delta-e") if isinstance(fit, str) else False:
        raise ParameterError(
            f"fit {fit!r} fits RGB curves in a colour space; for eta, kappa use "
            "'four-point', 'least-squares' or 'minimax'"
        )
    if fit == "four-point":
        return _four_point_nk(np.broadcast_arrays(eta, kappa), resolve_basis(basis))
    coefficient_fit(fit)  # the name, checked before any work
    return _in_chunks(
        np.broadcast_arrays(eta, kappa),
        lambda eta, kappa: coefficients_from_function(
            lambda mu: fresnel_kernel(mu, eta[:, None], kappa[:, None]), fit, basis
        ),
        resolve_basis(basis).n_terms,
    )


def _in_chunks(eta_kappa: list[np.ndarray], fit: Callable, terms: int) -> np.ndarray:
    """``fit(eta, kappa)`` → (n, K) over flat chunks of materials, so memory stays bounded (a least-squares
    fit holds a few (materials × θ grid) arrays: 10⁵ materials at once took 12 GB)."""
    eta, kappa = eta_kappa
    shape = eta.shape
    eta, kappa = eta.ravel(), kappa.ravel()
    coefficients = np.empty((eta.size, terms))
    for start in range(0, eta.size, _LSQ_CHUNK):
        part = slice(start, start + _LSQ_CHUNK)
        coefficients[part] = fit(eta[part], kappa[part])
    return coefficients.reshape(shape + (terms,))


#: Materials per chunk of the least-squares fits of η, κ: a few 4096 × 512 arrays (16 MB each).
_LSQ_CHUNK = 4096


#: Materials per chunk of :func:`_four_point_nk`: the Fresnel kernel's temporaries stay near 30 MB.
_NK_CHUNK = 1 << 16


def _four_point_nk(eta_kappa: list[np.ndarray], basis: Basis) -> np.ndarray:
    """Four-point coefficients of many (η, κ) in chunks: c0 = F(0) in closed form, c1 = F(π/2) − F(0) with
    F(π/2) = 1 (0 only for η = 1, κ = 0), and the Fresnel kernel at the other fit angles alone (the
    structure b_k(0) = 0 for k ≥ 1, b_k(π/2) = 0 for k ≥ 2 of :mod:`basis.training.svd`)."""
    eta, kappa = eta_kappa
    shape = eta.shape
    eta, kappa = eta.ravel(), kappa.ravel()
    system = fit_matrix(basis)  # B[i, k] = b_k(θ_i), i over the fit angles 0, π/2, θ2, …
    inner = np.linalg.inv(system[2:, 2:]).T
    mu = cos_theta(basis.fit_angles[2:])
    coefficients = np.empty((eta.size, basis.n_terms))
    for start in range(0, eta.size, _NK_CHUNK):
        part = slice(start, start + _NK_CHUNK)
        f0 = fresnel_normal_incidence(eta[part], kappa[part])
        f90 = np.where((eta[part] == 1.0) & (kappa[part] == 0.0), 0.0, 1.0)
        rest = (
            fresnel_kernel(mu, eta[part, None], kappa[part, None])
            - f0[:, None] * system[2:, 0]
            - (f90 - f0)[:, None] * system[2:, 1]
        )
        coefficients[part, 0], coefficients[part, 1] = f0, f90 - f0
        coefficients[part, 2:] = rest @ inner
    return coefficients.reshape(shape + (basis.n_terms,))


def coefficients_from_gulbrandsen(reflectivity, edge_tint, basis: Basis | None = None) -> np.ndarray:
    """Coefficients of the exact Fresnel curve of Gulbrandsen's (r, g), e.g. per RGB channel.

    r in [0, 1), g in [0, 1]; shapes broadcast; (..., 3) → (..., 3, K).
    """
    eta, kappa = gulbrandsen_to_nk(reflectivity, edge_tint)
    reflectivity, edge_tint = np.broadcast_arrays(
        np.asarray(reflectivity, dtype=float), np.asarray(edge_tint, dtype=float)
    )
    outside = (eta < ETA_RANGE[0]) | (eta > ETA_RANGE[1]) | (kappa > KAPPA_RANGE[1])
    if np.any(outside):
        index = np.flatnonzero(np.broadcast_to(outside, eta.shape).ravel())[0]
        r = float(np.broadcast_to(reflectivity, eta.shape).ravel()[index])
        g = float(np.broadcast_to(edge_tint, eta.shape).ravel()[index])
        raise ParameterError(
            f"reflectivity {r} with edge_tint {g} maps to eta = {float(eta.ravel()[index]):.3g}, "
            f"kappa = {float(kappa.ravel()[index]):.3g}, outside the supported eta in [{ETA_RANGE[0]:g}, {ETA_RANGE[1]:g}], "
            f"kappa <= {KAPPA_RANGE[1]:g}: reflectivity must stay below about 1 - 4e-6 "
            f"(edge_tint 0) to 1 - 2e-8 (edge_tint 1)"
        )
    return coefficients_from_nk(eta, kappa, basis)


#: Norms of :func:`coefficients_least_squares`: name → what is minimised over θ. The names are those of the
#: same fits in :data:`COEFFICIENT_FITS` (one vocabulary for every coefficient fit).
LEAST_SQUARES_NORMS = {
    "least-squares": "L2 norm of the error over theta (trapezoid weights on the basis grid)",
    "minimax": "max norm of the error over the basis grid, approximated by Lawson's reweighting",
}

#: Lawson iterations of ``fit="minimax"``. Measured against the exact discrete minimax (a linear
#: programme) on the held-out groups of :mod:`basis.training`: every dielectric and metal is within
#: 0.4 % of it after 40 iterations (5 %, 1.8 % after 10, 20), the stiff corners within 2.3 %;
#: ``tests/basis/test_coefficients_least_squares.py`` checks 1 % on a few metals.
LAWSON_ITERATIONS = 40


def _least_squares_on_grid(values: np.ndarray, basis: Basis, fit: str, iterations: int) -> np.ndarray:
    """Unchecked kernel: ``values`` (..., M) on ``basis.theta`` → coefficients (..., K)."""
    c0 = values[..., 0]
    c1 = values[..., -1] - c0
    # b_k(0) = 0 (k ≥ 1) and b_k(π/2) = 0 (k ≥ 2): the residual vanishes at both ends (basis.training).
    residual = values - c0[..., None] - c1[..., None] * basis.curves[1]
    design = basis.curves[2:].T  # (M, K − 2)
    weights = trapezoid_weights(basis.theta)
    if fit == "least-squares":
        root = np.sqrt(weights)[:, None]
        rest = residual @ (np.linalg.pinv(root * design) * root.T).T
    else:
        rows = residual.reshape(-1, residual.shape[-1])
        rest = np.empty((len(rows), design.shape[1]))
        for start in range(0, len(rows), _LAWSON_ROWS):
            part = slice(start, start + _LAWSON_ROWS)
            rest[part] = _lawson_rest(rows[part], design, weights, iterations)
        rest = rest.reshape(residual.shape[:-1] + (design.shape[1],))
    return np.concatenate([c0[..., None], c1[..., None], rest], axis=-1)


#: Curves per block of the minimax fit's Lawson steps: each curve's steps are its own, and blocks this size keep
#: their (curves × θ grid) arrays in cache (twice as fast as 4096 at once; the same bits).
_LAWSON_ROWS = 256


def _lawson_rest(residual: np.ndarray, design: np.ndarray, weights: np.ndarray, iterations: int) -> np.ndarray:
    """(N, K − 2) minimax c2 … of the residuals (N, M) by Lawson's reweighting from ``weights`` (M,)."""
    weights = np.broadcast_to(weights, residual.shape)
    for _ in range(iterations):
        weighted = weights[..., None, :] * design.T  # (N, K − 2, M)
        gram = weighted @ design
        # a ridge of 1e-14 of the trace keeps the solve regular if the weights collapse
        ridge = 1e-14 * np.trace(gram, axis1=-2, axis2=-1)[..., None, None] + np.finfo(float).tiny
        rest = np.linalg.solve(gram + ridge * np.eye(design.shape[1]), weighted @ residual[..., None])[..., 0]
        error = np.abs(residual - rest @ design.T)
        updated = weights * error
        total = updated.sum(axis=-1, keepdims=True)
        # a curve fitted exactly (error 0 everywhere) keeps its weights
        weights = np.where(total > 0.0, updated / np.where(total > 0.0, total, 1.0), weights)
    return rest


def _check_norm(fit: str) -> str:
    return check_choice("fit", fit, list(LEAST_SQUARES_NORMS))


def coefficients_least_squares_from_table(
    theta, values, basis: Basis | None = None, fit: str = "least-squares", iterations: int = LAWSON_ITERATIONS
) -> np.ndarray:
    """Least-squares coefficients of a tabulated curve, with F(0) and F(π/2) kept exact.

    Parameters
    ----------
    theta : array_like
        (M',) strictly increasing angles covering [0, π/2] (radians).
    values : array_like
        (..., M') the curve at ``theta``; interpolated by a cubic spline in θ (zero slope at 0) onto
        ``basis.theta`` unless it already is that grid.
    basis : Basis, optional
        Default: the shipped basis.
    fit : {"least-squares", "minimax"}
        ``"least-squares"``: minimise ∫ (F − Σ c_k b_k)² dθ (trapezoid rule on ``basis.theta``).
        ``"minimax"``: minimise max_j |F − Σ c_k b_k| over ``basis.theta`` approximately, by
        ``iterations`` Lawson steps starting from the uniform weights.
    iterations : int
        Lawson iterations for ``fit="minimax"``, in [1, 10000].

    Returns
    -------
    numpy.ndarray
        (..., K) coefficients with c0 = F(0), c1 = F(π/2) − F(0) exactly and c2 … c_{K−1} the weighted
        least-squares fit of F − c0 − c1 b1 by b2 … b_{K−1}.

    Notes
    -----
    Because b_k(0) = 0 for k ≥ 1 and b_k(π/2) = 0 for k ≥ 2 (:mod:`basis.training`), fixing c0 and c1 leaves
    a residual that vanishes at both ends, and the other terms do not disturb F0 or F90. An unweighted
    L2 fit can let the error pile up at grazing angles; the minimax weighting bounds it instead.
    Lawson's update (Lawson 1961; Rice and Usow 1968) is w_j ← w_j |e_j| / Σ_i w_i |e_i|.

    Examples
    --------
    >>> from basis import default_basis
    >>> theta = default_basis().theta
    >>> curve = 0.5 + 0.25 * default_basis().curves[1]
    >>> bool(np.allclose(coefficients_least_squares_from_table(theta, curve), [0.5, 0.25, 0, 0], atol=1e-12))
    True
    """
    basis = resolve_basis(basis)
    fit = _check_norm(fit)
    iterations = check_positive_int("iterations", iterations, low=1, high=10_000)
    theta_array = as_float_array("theta", theta)
    values = as_float_array("values", values)
    if theta_array.shape != basis.theta.shape or not np.array_equal(theta_array, basis.theta):
        values = _table_spline(theta_array, values)(basis.theta)
    else:
        check_shape_last("values", values, basis.theta.size)
    return _least_squares_on_grid(values, basis, fit, iterations)


def coefficients_least_squares(
    eta, kappa, basis: Basis | None = None, fit: str = "least-squares", iterations: int = LAWSON_ITERATIONS
) -> np.ndarray:
    """Least-squares coefficients of the exact Fresnel curve of η + iκ: (...) → (..., K).

    Parameters
    ----------
    eta : array_like
        In [1e-8, 1e6].
    kappa : array_like
        In [0, 1e6]; broadcast against ``eta`` (e.g. RGB (..., 3) → (..., 3, K)).
    basis : Basis, optional
        Default: the shipped basis.
    fit : {"least-squares", "minimax"}
        See :func:`coefficients_least_squares_from_table`.
    iterations : int
        Lawson iterations for ``fit="minimax"``.

    Returns
    -------
    numpy.ndarray
        (..., K): c0 = F(0), c1 = F(π/2) − F(0), c2 … fitted on ``basis.theta``.

    Examples
    --------
    >>> c = coefficients_least_squares([0.27, 0.68, 1.32], [3.61, 2.64, 1.81], fit="minimax")
    >>> c.shape
    (3, 4)
    """
    basis = resolve_basis(basis)
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    check_broadcast(eta=eta, kappa=kappa)
    fit = _check_norm(fit)
    iterations = check_positive_int("iterations", iterations, low=1, high=10_000)
    mu = cos_theta(basis.theta)
    return _in_chunks(
        np.broadcast_arrays(eta, kappa),
        lambda eta, kappa: _least_squares_on_grid(
            fresnel_kernel(mu, eta[:, None], kappa[:, None]), basis, fit, iterations
        ),
        basis.n_terms,
    )


def reconstruct(coefficients, mu, basis: Basis | None = None) -> np.ndarray:
    """Σ_k c_k b_k(arccos μ): coefficients (..., K) and μ broadcast over the leading axes → (...)."""
    basis = resolve_basis(basis)
    coefficients = as_float_array("coefficients", coefficients)
    check_shape_last("coefficients", coefficients, basis.n_terms)
    mu = check_range("mu", mu, 0.0, 1.0)
    check_broadcast(coefficients=coefficients[..., 0], mu=mu)
    return np.sum(coefficients * basis.evaluate_mu(mu), axis=-1)


def reconstruction_error(coefficients, theta, values, basis: Basis | None = None) -> tuple[np.ndarray, np.ndarray]:
    """How far Σ_k c_k b_k(θ) is from a target curve sampled at ``theta``: (max |error|, RMS error).

    Works for any target, Fresnel or not (a constant, a step, measured data, noise): it reports the
    error, it does not judge it.

    Parameters
    ----------
    coefficients : array_like
        (..., K) coefficients, e.g. from :func:`coefficients_from_table`; finite.
    theta : array_like
        (M,) angles in [0, π/2] (radians) at which the target is known, M ≥ 1, in any order.
    values : array_like
        (..., M) the target F(θ_j); finite. The leading axes broadcast against those of ``coefficients``.
    basis : Basis, optional
        Default: the shipped basis.

    Returns
    -------
    (max_abs, rms) : tuple of numpy.ndarray
        Shape: the broadcast leading axes. ``max_abs`` = max_j |e_j| and ``rms`` = √(mean_j e_j²), with
        e_j = Σ_k c_k b_k(θ_j) − F(θ_j): every sample weighs the same (pass a uniform θ grid for an
        RMS over angle).

    Examples
    --------
    >>> theta = np.linspace(0.0, 0.5 * np.pi, 5)
    >>> max_abs, rms = reconstruction_error([0.5, 0.0, 0.0, 0.0], theta, [0.5, 0.5, 0.5, 0.5, 0.9])
    >>> round(float(max_abs), 12), round(float(rms), 12)
    (0.4, 0.1788854382)
    """
    basis = resolve_basis(basis)
    coefficients = as_float_array("coefficients", coefficients)
    check_shape_last("coefficients", coefficients, basis.n_terms)
    theta = check_range("theta", theta, 0.0, 0.5 * np.pi)
    if theta.ndim != 1 or theta.size == 0:
        raise ParameterError(f"theta must be a 1-D array of at least 1 angle, got shape {theta.shape}")
    values = as_float_array("values", values)
    check_shape_last("values", values, theta.size)
    try:
        leading = np.broadcast_shapes(coefficients.shape[:-1], values.shape[:-1])
    except ValueError:
        raise ParameterError(
            f"coefficients {coefficients.shape} and values {values.shape} have leading axes that do not broadcast"
        ) from None
    fitted = np.einsum("...k,jk->...j", coefficients, basis.evaluate(theta))
    error = np.broadcast_to(fitted, leading + (theta.size,)) - values
    return np.max(np.abs(error), axis=-1), np.sqrt(np.mean(error * error, axis=-1))


def _four_point_fit(values_of: Callable, basis: Basis, space: str | None, start, report) -> np.ndarray:
    return coefficients_from_samples(values_of(cos_theta(basis.fit_angles)), basis)


def _least_squares_fit(norm: str) -> Callable:
    def fit(values_of: Callable, basis: Basis, space: str | None, start, report) -> np.ndarray:
        return _least_squares_on_grid(values_of(cos_theta(basis.theta)), basis, norm, LAWSON_ITERATIONS)

    return fit


def _delta_e_fit(free_f0: bool) -> Callable:
    def fit(values_of: Callable, basis: Basis, space: str | None, start, report) -> np.ndarray:
        from .delta_e_fits import delta_e_coefficients  # colour science, loaded only for a ΔE2000 fit

        if space is None:
            raise ParameterError("a delta-e fit needs the colour space of the RGB curve (space='ACEScg' or 'sRGB')")
        if start is None:  # the exact-F0 fit starts from least squares; the free-F0 fit from the exact-F0 optimum
            start = _least_squares_fit("least-squares")(values_of, basis, space, None, None)
            if free_f0:
                start = delta_e_coefficients(values_of, space, basis, start, free_f0=False)
        return delta_e_coefficients(values_of, space, basis, start, free_f0, report)

    return fit


#: Registry: fit name → (values_of, basis, space, start, report) → (..., K), with values_of(μ (A,)) → (..., A)
#: the target; ``start`` and ``report`` serve the iterative fits (see :func:`coefficients_from_function`).
#: Every fit keeps F(90°) = c0 + c1 exact; all but ``delta-e`` keep F(0°) = c0 exact too.
COEFFICIENT_FITS: dict[str, Callable] = {
    "four-point": _four_point_fit,  # the talk's scheme: the curve at the fit angles (Belcour 2020, "Coefficients")
    "least-squares": _least_squares_fit("least-squares"),  # L2 over θ on the basis grid
    "minimax": _least_squares_fit("minimax"),  # max norm over the basis grid, by Lawson's reweighting
    "delta-e-exact-f0": _delta_e_fit(False),  # RGB: Σ_θ ΔE2000² over c2 … (Hoffman 2020's measure)
    "delta-e": _delta_e_fit(True),  # RGB: the same over c0, c2 …; F0 may move by an invisible ΔE
}

#: The fits of :func:`coefficients_from_model` (a model's curve is no RGB colour: the ΔE2000 fits need one).
MODEL_FITS = ("four-point", "least-squares", "minimax")


def coefficient_fit(name: str) -> Callable:
    """Look up a fit of :data:`COEFFICIENT_FITS`; the error lists the valid names."""
    return COEFFICIENT_FITS[check_choice("fit", name, sorted(COEFFICIENT_FITS))]


def coefficients_from_function(
    values_of: Callable,
    fit: str = "four-point",
    basis: Basis | None = None,
    space: str | None = None,
    start=None,
    report: dict | None = None,
) -> np.ndarray:
    """Coefficients (..., K) of any target given as a function of μ, by a fit of :data:`COEFFICIENT_FITS`.

    Parameters
    ----------
    values_of : callable
        μ (A,) in [0, 1] → (..., A): the target at the cosines the fit asks for; (3, A) for the ΔE fits.
    fit : str
        A name of :data:`COEFFICIENT_FITS`.
    space : str, optional
        Colour space of an RGB target (``delta-e`` fits only).
    start : array_like, optional
        (3, K) coefficients an iterative fit starts from (``delta-e``: the ``delta-e-exact-f0`` result,
        which is otherwise computed first).
    report : dict, optional
        Filled by the iterative fits with their convergence: ``converged``, ``status``, ``evaluations``,
        ``gradient`` (:func:`basis.delta_e_fits.fit_summary`).

    Examples
    --------
    >>> c = coefficients_from_function(lambda mu: fresnel_kernel(mu, 1.5, 0.0), fit="minimax")
    >>> round(float(c[0]), 6)  # F0 of glass
    0.04
    """
    if not callable(values_of):
        raise ParameterError(f"values_of must be callable, got {type(values_of).__name__}")
    start = None if start is None else as_float_array("start", start)
    return coefficient_fit(fit)(values_of, resolve_basis(basis), space, start, report)


def coefficients_from_model(
    name: str, fit: str = "four-point", basis: Basis | None = None, **parameters
) -> tuple[np.ndarray, np.ndarray]:
    """Project an RGB material of a model of :data:`basis.models.FRESNEL_MODELS` onto the basis.

    Returns the coefficients (3, K) by ``fit`` (``four-point``, ``least-squares`` or ``minimax``) and the
    max |F_model − Σ c_k b_k| over 2001 angles uniform in θ, per channel (3,): how much of the model the
    basis holds.

    Examples
    --------
    >>> coefficients, error = coefficients_from_model("f82", f0=[0.95, 0.64, 0.54], f82=[0.93, 0.6, 0.5])
    >>> coefficients.shape, error.shape
    ((3, 4), (3,))
    """
    from .models import fresnel_model

    model = fresnel_model(name)
    checked = model.check(**parameters)
    check_choice("fit (of a model)", fit, MODEL_FITS)

    def values_of(mu: np.ndarray) -> np.ndarray:  # (3, A)
        return np.broadcast_to(model.evaluate(mu[:, None], **checked), (mu.size, 3)).T

    basis = resolve_basis(basis)
    coefficients = coefficients_from_function(values_of, fit, basis)
    theta = np.linspace(0.0, 0.5 * np.pi, 2001)
    error, _ = reconstruction_error(coefficients, theta, values_of(cos_theta(theta)), basis)
    return coefficients, error
