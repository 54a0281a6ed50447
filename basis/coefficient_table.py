"""A table of Gulbrandsen's (r, g) → basis coefficients, read per pixel with one bilinear fetch (issue 38).

Public objects: ``COEFFICIENT_TABLE_SIZE``, ``COEFFICIENT_TABLE_FITS``, ``REFLECTIVITY_MAX``, ``warp_reflectivity``,
``unwarp_reflectivity``, ``warp_edge_tint``, ``unwarp_edge_tint``, ``coefficient_table``, ``coefficient_table_lookup``,
``coefficients_from_coefficient_table``.

For Gulbrandsen's inputs F(0) = r and F(π/2) = 1, so c0 = r and c1 = 1 − r exactly (:mod:`basis.coefficients`); only
c2 … c_(K−1) depend on (r, g) nonlinearly, and those are what the table holds, on warped axes that open up where they
bend (Gulbrandsen 2014, eq. 7–9: η grows like 4 / (1 − r) at r → 1, g = 0, and n_min → n_max at r → 0):

    x = r^(1/4) − √(1 − r) / 2    (columns, r from 0 to :data:`REFLECTIVITY_MAX`),
    y = 1 − (1 − g)^(1/4)         (rows, g from 0 to 1),

texels at the end points of both (the first and last texel centre on r = 0 and 0.9999, g = 0 and 1).

**Criterion** (``fit="minimax"``, the default): the coefficients minimise max over θ of |F − F_exact| on the basis'
θ grid with c0, c1 kept exact (:func:`basis.coefficients.coefficients_least_squares`, 40 Lawson steps). That is the
error for lights, F(V·H), and it also bounds the split sum's everywhere in a table: F̄ is an average of F with positive
weights that sum to E ≤ 1, so |ΔF̄| ≤ max |ΔF|, with equality on the mirror row. Against exact Fresnel it is never worse
than the four-point solve at a texel and 1.5 × better at the median (``python -m benchmarks.coefficient_table``).
``fit="four-point"`` tabulates the include's own solve instead: smoother in (r, g), so read between texels it stays
closer to its model, at the four-point solve's accuracy.

At r = 0 (η = 1, κ = 0) every coefficient is 0; column 0 holds the limit r → 0⁺ for the interpolation beside it,
and the lookup returns 0 there, as the solve does.
"""

from __future__ import annotations

import numpy as np

from .coefficients import coefficients_from_gulbrandsen, coefficients_least_squares
from .eigenbasis import Basis, resolve_basis
from .gulbrandsen import gulbrandsen_to_nk
from .validation import ParameterError, as_float_array, check_broadcast, check_choice, check_positive_int, check_range

__all__ = [
    "COEFFICIENT_TABLE_FITS",
    "COEFFICIENT_TABLE_SIZE",
    "REFLECTIVITY_MAX",
    "coefficient_table",
    "coefficient_table_lookup",
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
COEFFICIENT_TABLE_FITS = ("minimax", "four-point")
#: The r at which column 0 is computed: the limit r → 0⁺ (the material at r = 0 itself reflects nothing).
_R_LIMIT = 1e-12


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


def _axes(width: int, height: int) -> tuple[np.ndarray, np.ndarray]:
    """(r (W,), g (H,)) of the texels: end points of the warped axes."""
    x = np.linspace(warp_reflectivity(0.0), warp_reflectivity(REFLECTIVITY_MAX), width)
    reflectivity = unwarp_reflectivity(x)
    reflectivity[0], reflectivity[-1] = 0.0, REFLECTIVITY_MAX
    return reflectivity, unwarp_edge_tint(np.linspace(0.0, 1.0, height))


def coefficient_table(
    basis: Basis | None = None, fit: str = "minimax", size: tuple[int, int] = COEFFICIENT_TABLE_SIZE
) -> np.ndarray:
    """(H, W, K − 2) coefficients c2 … c_(K−1) of Gulbrandsen's (r, g) at the texels (module notes) on ``basis``
    (default: the shipped one), by ``fit`` (:data:`COEFFICIENT_TABLE_FITS`); ``size`` = (W, H), each in [2, 4096].

    >>> table = coefficient_table(size=(8, 4), fit="four-point")
    >>> table.shape
    (4, 8, 2)
    """
    basis = resolve_basis(basis)
    fit = check_choice("fit", fit, list(COEFFICIENT_TABLE_FITS))
    width, height = (
        check_positive_int(name, value, low=2, high=4096) for name, value in zip(("width", "height"), size)
    )
    reflectivity, edge_tint = np.meshgrid(*_axes(width, height))
    reflectivity = np.maximum(reflectivity, _R_LIMIT)
    if fit == "four-point":
        coefficients = coefficients_from_gulbrandsen(reflectivity, edge_tint, basis)
    else:
        coefficients = coefficients_least_squares(*gulbrandsen_to_nk(reflectivity, edge_tint), basis, fit="minimax")
    return coefficients[..., 2:]


def coefficient_table_lookup(table, reflectivity, edge_tint, weight_bits: int | None = None) -> np.ndarray:
    """(…, C) of a table (H, W, C) on this module's axes read as a GPU reads it (bilinear, clamp to edge, texel
    centres at the axes' end points) at (r, g) in [0, :data:`REFLECTIVITY_MAX`] × [0, 1] (unchecked: callers clamp);
    with ``weight_bits``, each filter weight rounded to that many bits, as GPUs that filter with 8-bit weights do."""
    table = as_float_array("table", table)
    height, width = table.shape[:2]
    x0, x1 = warp_reflectivity(0.0), warp_reflectivity(REFLECTIVITY_MAX)
    u = np.clip((warp_reflectivity(reflectivity) - x0) / (x1 - x0), 0.0, 1.0) * (width - 1)
    v = np.clip(warp_edge_tint(edge_tint), 0.0, 1.0) * (height - 1)
    i, j = np.minimum(np.floor(u).astype(int), width - 2), np.minimum(np.floor(v).astype(int), height - 2)
    fu, fv = (u - i)[..., None], (v - j)[..., None]
    if weight_bits is not None:
        step = 2.0 ** check_positive_int("weight_bits", weight_bits, low=1, high=52)
        fu, fv = np.round(fu * step) / step, np.round(fv * step) / step
    return (1 - fv) * ((1 - fu) * table[j, i] + fu * table[j, i + 1]) + fv * (
        (1 - fu) * table[j + 1, i] + fu * table[j + 1, i + 1]
    )


def coefficients_from_coefficient_table(table, reflectivity, edge_tint, weight_bits: int | None = None) -> np.ndarray:
    """(…, K) coefficients of Gulbrandsen's (r, g) from a :func:`coefficient_table` (H, W, K − 2): c0 = r,
    c1 = 1 − r, the rest read bilinearly (``weight_bits``: :func:`coefficient_table_lookup`); all 0 at r = 0. r in
    [0, :data:`REFLECTIVITY_MAX`], g in [0, 1].

    >>> table = coefficient_table(size=(64, 16), fit="four-point")
    >>> c = coefficients_from_coefficient_table(table, 0.5, 0.5)
    >>> c.shape, round(float(c[0]), 12), round(float(c[1]), 12)
    ((4,), 0.5, 0.5)
    """
    table = as_float_array("table", table)
    if table.ndim != 3:
        raise ParameterError(f"table must be (H, W, K - 2), got shape {table.shape}")
    reflectivity = check_range("reflectivity", reflectivity, 0.0, REFLECTIVITY_MAX)
    edge_tint = check_range("edge_tint", edge_tint, 0.0, 1.0)
    check_broadcast(reflectivity=reflectivity, edge_tint=edge_tint)
    reflectivity, edge_tint = np.broadcast_arrays(reflectivity, edge_tint)
    reflects = (reflectivity > 0.0)[..., None]
    rest = np.where(reflects, coefficient_table_lookup(table, reflectivity, edge_tint, weight_bits), 0.0)
    first = np.stack([reflectivity, np.where(reflectivity > 0.0, 1.0 - reflectivity, 0.0)], axis=-1)
    return np.concatenate([first, rest], axis=-1)
