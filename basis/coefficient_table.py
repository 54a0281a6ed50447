"""A table of Gulbrandsen's (r, g) → basis coefficients, read per pixel with one bilinear fetch (issue 38).

Public objects: ``COEFFICIENT_TABLE_SIZE``, ``COEFFICIENT_TABLE_FITS``, ``REFLECTIVITY_MAX``, ``warp_reflectivity``,
``unwarp_reflectivity``, ``warp_edge_tint``, ``unwarp_edge_tint``, ``coefficient_table_axes``,
``coefficient_table_weights``, ``coefficient_table_model``, ``coefficient_table``, ``coefficient_table_lookup``,
``coefficients_from_coefficient_table``.

For Gulbrandsen's inputs F(0) = r and F(π/2) = 1, so c0 = r and c1 = 1 − r exactly (:mod:`basis.coefficients`); only
c2 … c_(K−1) depend on (r, g) nonlinearly, and those are what the table holds, on warped axes that open up where they
bend (Gulbrandsen 2014, eq. 7–9: η grows like 4 / (1 − r) at r → 1, g = 0, and n_min → n_max at r → 0):

    x = r^(1/4) − √(1 − r) / 2    (columns, r from 0 to :data:`REFLECTIVITY_MAX`),
    y = 1 − (1 − g)^(1/4)         (rows, g from 0 to 1, texel centres on both ends).

The last channel is F(π/2), f90: 1, except in column 0, which holds the material of r = 0 (η = 1, κ = 0: F = 0, every
coefficient and f90 0). r = 0 lies a quarter texel outside column 0's centre, where a clamped bilinear read returns
column 0 alone whatever the rounding of the coordinate, so a shader takes c1 = f90 − r from the fetch (one
subtraction) where the test r > 0 and three products per colour channel cost 0.14 of Schlick's pass in a GPU
compiler's estimate; column 1 lies at r ≈ 2e-10. The last column's centre is r = :data:`REFLECTIVITY_MAX`.

**Criterion** (``fit="weighted"``, the default): weighted least squares over θ with c0, c1 exact and one set of
weights w(θ) on the basis' θ grid for every texel, :func:`coefficient_table_weights`: Lawson's reweighting run over
the table's materials at once, w_j ← w_j max over materials of |e_j| / E₄, E₄ the four-point solve's max error of that
material, so that w minimises the worst ratio to the four-point solve. Being linear in the exact curve, the fit is as
smooth in (r, g) as the Fresnel equations, so the table read between texels stays within 6e-5 of it; a minimax fit at
each texel (``fit="minimax"``, 40 Lawson steps) is more accurate at the median (0.65 × the four-point solve's error
against this fit's 0.76 ×) but bends where its extremal angles switch, and bilinear reading misses it by up to
6e-4. Max over θ of |F − F_exact| bounds the split sum's error too: F̄ is an average of F with positive weights that
sum to E ≤ 1. ``fit="four-point"`` tabulates the include's own solve. ``python -m benchmarks.coefficient_table``
measures all three against exact Fresnel.
"""

from __future__ import annotations

import numpy as np

from .angles import cos_theta, trapezoid_weights
from .coefficients import coefficients_from_gulbrandsen, coefficients_least_squares
from .eigenbasis import Basis, resolve_basis
from .fresnel import fresnel_kernel
from .gulbrandsen import gulbrandsen_to_nk
from .parallel import one_blas_thread
from .validation import ParameterError, as_float_array, check_broadcast, check_choice, check_positive_int, check_range

__all__ = [
    "COEFFICIENT_TABLE_FITS",
    "COEFFICIENT_TABLE_SIZE",
    "REFLECTIVITY_MAX",
    "coefficient_table",
    "coefficient_table_axes",
    "coefficient_table_lookup",
    "coefficient_table_model",
    "coefficient_table_weights",
    "coefficients_from_coefficient_table",
    "unwarp_edge_tint",
    "unwarp_reflectivity",
    "warp_edge_tint",
    "warp_reflectivity",
]

#: Columns (r) and rows (g) of the table a build writes.
COEFFICIENT_TABLE_SIZE = (512, 128)
#: The largest reflectivity, as the include clamps it: beyond it η of g = 0 passes 4 × 10⁴.
REFLECTIVITY_MAX = 0.9999
COEFFICIENT_TABLE_FITS = ("weighted", "minimax", "four-point")
#: Lawson steps of :func:`coefficient_table_weights` (the worst ratio settles to 3 digits by 60), and how often a
#: texel of the training set is taken along each axis before the rest are checked.
_WEIGHT_ITERATIONS = 80
_TRAINING_STRIDE = 2
#: Materials per block when the whole table is fitted or checked (a few (block × θ grid) float64 arrays at a time), and
#: per block of a Lawson step (arrays that stay in cache: the step takes half the time).
_BLOCK = 4096
_CACHE_BLOCK = 256


def warp_reflectivity(reflectivity):
    """x = r^(1/4) − √(1 − r) / 2: −1/2 at r = 0, increasing, 0.995 at r = 0.9999."""
    r = np.asarray(reflectivity, dtype=np.float64)
    return np.sqrt(np.sqrt(r)) - 0.5 * np.sqrt(1.0 - r)


def unwarp_reflectivity(x):
    """r of :func:`warp_reflectivity` (bisection to the last bit; x in [−1/2, 1])."""
    x = np.asarray(x, dtype=np.float64)
    low, high = np.zeros_like(x), np.ones_like(x)
    for _ in range(64):
        middle = 0.5 * (low + high)
        below = warp_reflectivity(middle) < x
        low, high = np.where(below, middle, low), np.where(below, high, middle)
    return 0.5 * (low + high)


def warp_edge_tint(edge_tint):
    """y = 1 − (1 − g)^(1/4)."""
    return 1.0 - np.sqrt(np.sqrt(1.0 - np.asarray(edge_tint, dtype=np.float64)))


def unwarp_edge_tint(y):
    """g of :func:`warp_edge_tint`."""
    return 1.0 - (1.0 - np.asarray(y, dtype=np.float64)) ** 4


def coefficient_table_axes(width: int, height: int) -> tuple[float, float]:
    """(x of column 0's centre, the step between columns) of a table ``width`` wide: the last centre at
    x(:data:`REFLECTIVITY_MAX`) and x(0) = −1/2 a quarter step before the first (module notes)."""
    low, high = warp_reflectivity(0.0), warp_reflectivity(REFLECTIVITY_MAX)
    step = (high - low) / (width - 0.75)
    return float(low + 0.25 * step), float(step)


def _texel_parameters(width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """(r (W,), g (H,)) at the texel centres; r[0] is column 0's centre, which holds r = 0."""
    first, step = coefficient_table_axes(width, height)
    reflectivity = unwarp_reflectivity(first + step * np.arange(width))
    reflectivity[-1] = REFLECTIVITY_MAX
    return reflectivity, unwarp_edge_tint(np.linspace(0.0, 1.0, height))


def _residuals(reflectivity: np.ndarray, edge_tint: np.ndarray, basis: Basis) -> np.ndarray:
    """(N, M) exact Fresnel of Gulbrandsen's (r, g) less c0 b0 + c1 b1 (c0 = r, c1 = 1 − r) on ``basis.theta``: what
    c2 … fit, 0 at both ends of θ (b_k(0) = 0 for k ≥ 1, b_k(π/2) = 0 for k ≥ 2)."""
    eta, kappa = gulbrandsen_to_nk(reflectivity, edge_tint)
    values = fresnel_kernel(cos_theta(basis.theta)[None, :], eta[:, None], kappa[:, None])
    return values - values[:, :1] - (values[:, -1:] - values[:, :1]) * basis.curves[1]


def _weighted_projection(weights: np.ndarray, basis: Basis) -> np.ndarray:
    """(M, K − 2): residuals (N, M) @ it are the weighted least-squares c2 …"""
    design = basis.curves[2:].T
    root = np.sqrt(weights)[:, None]
    return (np.linalg.pinv(root * design) * root.T).T


def _ratios(projection: np.ndarray, residuals: np.ndarray, four_point: np.ndarray, basis: Basis) -> np.ndarray:
    """(N, M) |error| of the weighted fit (``projection``: :func:`_weighted_projection` of its weights) over each
    material's four-point max error."""
    error = residuals @ projection @ basis.curves[2:] - residuals
    return np.abs(error) / four_point[:, None]


def _four_point_errors(residuals: np.ndarray, reflectivity, edge_tint, basis: Basis) -> np.ndarray:
    """(N,) max over ``basis.theta`` of the four-point solve's error (c0, c1 are the same in both fits)."""
    fit = coefficients_from_gulbrandsen(reflectivity, edge_tint, basis)[:, 2:] @ basis.curves[2:]
    return np.maximum(np.max(np.abs(fit - residuals), axis=1), 1e-12)


def _residual_blocks(reflectivity: np.ndarray, edge_tint: np.ndarray, basis: Basis):
    """(part, residuals, four-point errors) of the materials, :data:`_BLOCK` at a time (Fresnel's complex
    temporaries)."""
    for start in range(0, reflectivity.size, _BLOCK):
        part = slice(start, start + _BLOCK)
        residuals = _residuals(reflectivity[part], edge_tint[part], basis)
        yield part, residuals, _four_point_errors(residuals, reflectivity[part], edge_tint[part], basis)


def _lawson(weights: np.ndarray, residuals: np.ndarray, four_point: np.ndarray, basis: Basis) -> np.ndarray:
    """Lawson's steps on the worst ratio over the materials: w_j ← w_j max_n |e_nj| / E₄,n (Lawson 1961)."""
    for _ in range(_WEIGHT_ITERATIONS):
        projection = _weighted_projection(weights, basis)
        worst = np.zeros_like(weights)
        for start in range(0, len(residuals), _CACHE_BLOCK):
            part = slice(start, start + _CACHE_BLOCK)
            worst = np.maximum(worst, np.max(_ratios(projection, residuals[part], four_point[part], basis), axis=0))
        weights = weights * worst
        weights = weights / weights.sum()
    return weights


_WEIGHTS: dict[str, np.ndarray] = {}


def coefficient_table_weights(basis: Basis | None = None) -> np.ndarray:
    """(M,) weights w(θ) on ``basis.theta`` (sum 1) of ``fit="weighted"`` (module notes), trained on the texels of a
    :data:`COEFFICIENT_TABLE_SIZE` table whatever size is built from them.

    Lawson's steps run on every other texel of each axis (column 0 aside); every texel is then checked, and any whose
    fit is worse than its four-point solve joins the training set for another round (at most four). Deterministic,
    with BLAS on one thread; about 10 s, once per basis and process.

    >>> weights = coefficient_table_weights()
    >>> weights.shape, round(float(weights.sum()), 12), bool(np.all(weights >= 0.0))
    ((512,), 1.0, True)
    """
    basis = resolve_basis(basis)
    if basis.content_hash not in _WEIGHTS:
        with one_blas_thread():
            _WEIGHTS[basis.content_hash] = _train_weights(basis, *COEFFICIENT_TABLE_SIZE)
    return _WEIGHTS[basis.content_hash].copy()


def _train_weights(basis: Basis, width: int, height: int) -> np.ndarray:
    reflectivity, edge_tint = (part.ravel() for part in np.meshgrid(*_texel_parameters(width, height)))
    column, row = (part.ravel() for part in np.meshgrid(np.arange(width), np.arange(height)))
    used = column > 0  # column 0 holds r = 0, no fit
    reflectivity, edge_tint = reflectivity[used], edge_tint[used]
    # every other texel of each axis, and all of column 1 (r → 0, where the ratio is most delicate)
    training = ((column[used] % _TRAINING_STRIDE == 1) & (row[used] % _TRAINING_STRIDE == 0)) | (column[used] == 1)
    weights = trapezoid_weights(basis.theta)
    weights = weights / weights.sum()
    for _ in range(4):
        chosen = np.flatnonzero(training)
        residuals = np.empty((chosen.size, basis.theta.size))
        four_point = np.empty(chosen.size)
        for part, block, errors in _residual_blocks(reflectivity[chosen], edge_tint[chosen], basis):
            residuals[part], four_point[part] = block, errors
        weights = _lawson(weights, residuals, four_point, basis)
        projection = _weighted_projection(weights, basis)
        worse = np.zeros_like(training)
        for part, block, errors in _residual_blocks(reflectivity, edge_tint, basis):
            worse[part] = np.max(_ratios(projection, block, errors, basis), axis=1) > 1.0
        if not np.any(worse & ~training):
            break
        training |= worse
    return weights


def coefficient_table_model(reflectivity, edge_tint, basis: Basis | None = None, fit: str = "weighted") -> np.ndarray:
    """(…, K) the float64 coefficients a table of ``fit`` (:data:`COEFFICIENT_TABLE_FITS`) holds at any (r, g), not
    only at its texels: c0 = r, c1 = 1 − r and c2 … by the criterion; all 0 at r = 0. r in
    [0, :data:`REFLECTIVITY_MAX`], g in [0, 1].

    >>> c = coefficient_table_model(0.9, 0.5)
    >>> [round(float(value), 6) for value in c[:2]]
    [0.9, 0.1]
    """
    basis = resolve_basis(basis)
    fit = check_choice("fit", fit, list(COEFFICIENT_TABLE_FITS))
    reflectivity = check_range("reflectivity", reflectivity, 0.0, REFLECTIVITY_MAX)
    edge_tint = check_range("edge_tint", edge_tint, 0.0, 1.0)
    check_broadcast(reflectivity=reflectivity, edge_tint=edge_tint)
    reflectivity, edge_tint = np.broadcast_arrays(reflectivity, edge_tint)
    shape = reflectivity.shape
    r, g = reflectivity.ravel(), edge_tint.ravel()
    reflects = r > 0.0
    coefficients = np.zeros((r.size, basis.n_terms))
    lit = np.flatnonzero(reflects)
    if fit == "four-point":
        coefficients[lit] = coefficients_from_gulbrandsen(r[lit], g[lit], basis)
    elif fit == "minimax":
        coefficients[lit] = coefficients_least_squares(*gulbrandsen_to_nk(r[lit], g[lit]), basis, fit="minimax")
    else:
        weights = coefficient_table_weights(basis)
        with one_blas_thread():
            projection = _weighted_projection(weights, basis)
            for start in range(0, lit.size, _BLOCK):
                part = lit[start : start + _BLOCK]
                coefficients[part, 2:] = _residuals(r[part], g[part], basis) @ projection
        coefficients[lit, 0], coefficients[lit, 1] = r[lit], 1.0 - r[lit]
    return coefficients.reshape(shape + (basis.n_terms,))


def coefficient_table(
    basis: Basis | None = None, fit: str = "weighted", size: tuple[int, int] = COEFFICIENT_TABLE_SIZE
) -> np.ndarray:
    """(H, W, K − 1) c2 … c_(K−1) and f90 of Gulbrandsen's (r, g) at the texels (module notes) on ``basis`` (default:
    the shipped one), by ``fit`` (:data:`COEFFICIENT_TABLE_FITS`); ``size`` = (W, H), each in [2, 4096]. Column 0 is
    the material of r = 0: all 0.

    >>> table = coefficient_table(size=(8, 4), fit="four-point")
    >>> table.shape, float(table[0, 0, -1]), float(table[0, 1, -1])
    ((4, 8, 3), 0.0, 1.0)
    """
    basis = resolve_basis(basis)
    fit = check_choice("fit", fit, list(COEFFICIENT_TABLE_FITS))
    width, height = (
        check_positive_int(name, value, low=2, high=4096) for name, value in zip(("width", "height"), size)
    )
    reflectivity, edge_tint = np.meshgrid(*_texel_parameters(width, height))
    reflectivity[:, 0] = 0.0
    coefficients = coefficient_table_model(reflectivity, edge_tint, basis, fit)
    f90 = (reflectivity > 0.0).astype(np.float64)[..., None]
    return np.concatenate([coefficients[..., 2:], f90], axis=-1)


def coefficient_table_lookup(table, reflectivity, edge_tint, weight_bits: int | None = None) -> np.ndarray:
    """(…, C) of a table (H, W, C) on this module's axes read as a GPU reads it (bilinear, clamp to edge; r = 0 a
    quarter texel before column 0's centre) at (r, g) in [0, :data:`REFLECTIVITY_MAX`] × [0, 1] (unchecked: callers
    clamp); with ``weight_bits``, each filter weight rounded to that many bits, as GPUs that filter with 8-bit weights
    do."""
    table = as_float_array("table", table)
    height, width = table.shape[:2]
    first, step = coefficient_table_axes(width, height)
    u = np.clip((warp_reflectivity(reflectivity) - first) / step, 0.0, width - 1)
    v = np.clip(warp_edge_tint(edge_tint), 0.0, 1.0) * (height - 1)
    i, j = np.minimum(np.floor(u).astype(int), width - 2), np.minimum(np.floor(v).astype(int), height - 2)
    fu, fv = (u - i)[..., None], (v - j)[..., None]
    if weight_bits is not None:
        step_size = 2.0 ** check_positive_int("weight_bits", weight_bits, low=1, high=52)
        fu, fv = np.round(fu * step_size) / step_size, np.round(fv * step_size) / step_size
    return (1 - fv) * ((1 - fu) * table[j, i] + fu * table[j, i + 1]) + fv * (
        (1 - fu) * table[j + 1, i] + fu * table[j + 1, i + 1]
    )


def coefficients_from_coefficient_table(table, reflectivity, edge_tint, weight_bits: int | None = None) -> np.ndarray:
    """(…, K) coefficients of Gulbrandsen's (r, g) from a :func:`coefficient_table` (H, W, K − 1): c0 = r,
    c1 = f90 − r and c2 … read bilinearly (``weight_bits``: :func:`coefficient_table_lookup`); all 0 at r = 0. r in
    [0, :data:`REFLECTIVITY_MAX`], g in [0, 1].

    >>> table = coefficient_table(size=(64, 16), fit="four-point")
    >>> c = coefficients_from_coefficient_table(table, 0.5, 0.5)
    >>> c.shape, round(float(c[0]), 12), round(float(c[1]), 12)
    ((4,), 0.5, 0.5)
    """
    table = as_float_array("table", table)
    if table.ndim != 3 or table.shape[-1] < 1:
        raise ParameterError(f"table must be (H, W, K - 1), got shape {table.shape}")
    reflectivity = check_range("reflectivity", reflectivity, 0.0, REFLECTIVITY_MAX)
    edge_tint = check_range("edge_tint", edge_tint, 0.0, 1.0)
    check_broadcast(reflectivity=reflectivity, edge_tint=edge_tint)
    reflectivity, edge_tint = np.broadcast_arrays(reflectivity, edge_tint)
    read = coefficient_table_lookup(table, reflectivity, edge_tint, weight_bits)
    first = np.stack([reflectivity, read[..., -1] - reflectivity], axis=-1)
    return np.concatenate([first, read[..., :-1]], axis=-1)
