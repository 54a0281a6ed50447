"""Linearly transformed cosines (LTC) fitted to this project's GGX, and the polygon integral that lights with them.

Public objects: ``LTC_CHANNELS``, ``ALPHA_FLOOR``, ``MU_FLOOR``, ``AXES``, ``WEIGHTINGS``, ``ltc_grid``,
``checked_ltc_grid``, ``fit_points``, ``fit_albedo``, ``LtcFit``, ``fit_ltc``, ``ltc_inverse``, ``ltc_density``,
``stored_density``, ``target_lobe``, ``lobe_error``, ``stored_lobe_error``, ``polygon_integral``, ``polygon_vector``,
``horizon_ltc_vector``, ``rect_light_integral``, ``rect_light_direction``, ``ltc_direction``,
``rect_light_half_cosine``, ``mean_half_v_dot_h``, ``punctual_roughness``, ``PUNCTUAL_SPREAD``, ``smoothed_fresnel``,
``rect_light_fresnel``,
``split_sum_weight``, ``lobe_density_ratio``, ``toward_lobe_limit``, ``ltc_solid_angle``,
``lobe_ratio_bound``, ``LOBE_RATIO_MAX``, ``LOBE_RATIO_PER_SIZE``, ``LOBE_SHARE_RAISED``, ``LOBE_WEIGHT_POWER``,
``SPLIT_SUM_WEIGHT_POWER``, ``SPLIT_SUM_WEIGHT_LINEAR``, ``LOBE_SPREAD_POWER``, ``LOBE_SPREAD_SHARE``,
``LOBE_SPREAD_RATIO``, ``disk_solid_angle``, ``lobe_spread``, ``ltc_upper_share``, ``toward_upper_share``,
``UPPER_SHARE_POWER``, ``shading_frame``,
``EDGE_FACTOR_DEGREE``, ``edge_factor_polynomial``, ``edge_factor``.

A linearly transformed cosine (Heitz, Dupuy, Hill, Neubelt 2016, eq. 1-3) is the clamped cosine
D_o(ω_o) = max(0, z_o)/π seen through a 3 × 3 matrix M: with ω_o = M⁻¹ω / |M⁻¹ω|,
D(ω) = D_o(ω_o) |det M⁻¹| / |M⁻¹ω|³. Its integral over a polygon P is the clamped-cosine integral over M⁻¹P:
Lambert's closed form (Heitz 2016 eq. 11; Arvo 1995) Σ_edges (p̂_i × p̂_j)_z θ_ij / (2π sin θ_ij), after clipping
M⁻¹P to the upper hemisphere (done exactly here, edge by edge, with the horizon edge from the exit to the entry
point; Heitz 2016 §5.2). A light is clipped to the shading horizon first (the BRDF is zero below the surface, where
the LTC, unless its axis is the normal, is not; Heitz 2016 clips only in the cosine's space): the clipped edges, taken
through M⁻¹, are clipped again (:func:`horizon_ltc_vector`). θ/sin θ is atan2(|p̂_i × p̂_j|, p̂_i · p̂_j)/|p̂_i × p̂_j|,
which float32 holds for short edges where acos does not; the shaders take it from a polynomial in 1 − cos θ instead
(:func:`edge_factor_polynomial`: within float32's rounding of it, and the rectangular light's pass 859 instructions
in ACO's estimate where atan made it 991, ``benchmarks.area_light_set``).

The fit. For an isotropic BRDF seen in the xz plane, M = [[a, 0, b], [0, c, 0], [d, 0, 1]] (Heitz 2016 §4.2: four
entries). As the public fit does, M = R_y(θ) [[s, 0, t], [0, u, 0], [0, 0, 1]] with θ the polar angle of the lobe's
mean direction: the LTC's support is then the half-space facing that direction, which keeps it off the
back-scattering half at grazing views (``axis="free"``, a fourth free entry, lowers the lobe error but spreads a
thin layer there that glows on a glossy silhouette under a light on the viewer's side; ``benchmarks.area_lights``
measures both). The shipped table takes per texel the mean-axis L2 fit or the free chi-square one, whichever
training lights prefer (:mod:`preintegrate.ltc_choice`). Per texel (μo, r) of an :func:`ltc_grid` (α = r²), (s, t, u)
minimise the L2 distance ∫ (f̂ − D)² dω to the normalised cosine-weighted GGX lobe f̂(ω_i) = D_GGX(h) G2(μo, μi) / (4 μo E(μo, α))
(no Fresnel: the split sum supplies it, Heitz 2016 §4.4), on a fixed set of directions, so the fit is
deterministic: a grid of visible-normal samples of the lobe (Heitz 2018) and a grid of the sphere, weighted by the
balance heuristic. Levenberg-Marquardt on (log s, t, log u), all columns of a row at once, from normal to grazing
incidence, each row starting from the one before or from the isotropic guess, whichever is closer (the public fit,
``fitLTC.cpp``, starts each texel from its neighbour; it minimises an L3 error by Nelder-Mead on random samples).
``weighting="chi-square"`` divides each squared residual by the lobe plus a tenth of its peak (issue 41's study:
``benchmarks.area_light_set`` measures the fits under lights of many sizes and places).

Stored: M⁻¹ / (M⁻¹)₁₁ as (m00, m20, m02, m22) (the polygon integral depends only on the directions M⁻¹p / |M⁻¹p|,
so the scale is free) on the axes of the public tables (:func:`ltc_grid`: column r, row √(1 − μo), end points on
texel centres; three.js ``ltc_1`` and ``LTC_Uv``), so an engine's existing area-light code reads it unchanged.

The specular of a polygonal light with a Fresnel curve F (Heitz 2016 §4.4): ∫_P f F cos dω ≈
(∫_P D dω) × E · mix(F̃, F̄ / E, w), F̄ = ∫_Ω f F cos dω the split sum Σ_k c_k b̄_k(μo, r) of the basis table and F̃ F
averaged over the light: F̄' / E' of the same table read at (V·H*, r'), the split sum of a GGX lobe of roughness
r' = min(r, k √Ω_L) (:func:`punctual_roughness`, k = :data:`PUNCTUAL_SPREAD`, Ω_L the light's solid angle as the LTC
gives it) seen at V·H*: F averaged over half vectors spread as the light's directions spread about H*, which is F(V·H*)
for a small light (r' = 0, the table's mirror row); H* along V + L*, L* the light's representative direction (the
direction of the transformed polygon's vector form factor, :func:`polygon_vector`, taken back through M:
:func:`rect_light_direction`); and w = a I + (1 − a) I^n, I the share of the lobe the light covers
(a = :data:`SPLIT_SUM_WEIGHT_LINEAR`, n = :data:`SPLIT_SUM_WEIGHT_POWER`): a small light tends to the punctual
F(V·H), one that covers the lobe to the split sum (issue 41). The lobe itself does the same: ∫_P D dω becomes
I (w + (1 − w) min(f̂(L*) / D(L*), R)), w = I^p, p = :data:`LOBE_WEIGHT_POWER`
(:func:`toward_lobe_limit`, :func:`lobe_density_ratio`), which a small light takes to the lobe's own integral
f̂(L*) Ω (where the ratio is within R) and a light covering the lobe leaves as it is; a light much wider than the
lobe (its spread, :func:`lobe_spread`, the LTC's mean density over it against its density at L*, small) keeps more of
I, unless the ratio says the LTC there holds several times the lobe (:data:`LOBE_SPREAD_POWER`). R
(:func:`lobe_ratio_bound`: :data:`LOBE_RATIO_MAX`, more for a light that is not tiny while the raised value is a small
share of the lobe) bounds what the lobe adds where the LTC holds less than it (the mirror direction at grazing views is
off pointwise and right in the integral of a medium light) and what the ratio multiplies of float32's rounding of I.
Last, the LTC's share
below the shading horizon, 1 − H (:func:`ltc_upper_share`), stands for lobe just above it, which only a light covering
nearly all of the lobe holds: I becomes I (1 + (1/H − 1) min(I/H, 1)^m) (:func:`toward_upper_share`,
m = :data:`UPPER_SHARE_POWER`), 1 for a light over the whole hemisphere where the lobe's limit leaves it the LTC's H
(the shipped table's H is 0.84 at N·V 0.08, r 0.3, above 0.99 at most texels).
The LTC matrices do not depend on Fresnel, so one table of them serves every material.

References
----------
:cite:`Heitz2016` E. Heitz, J. Dupuy, S. Hill, D. Neubelt, "Real-Time Polygonal-Light Shading with Linearly
Transformed Cosines", ACM TOG 35(4), 2016, eq. 1-3, 11 and §4-5. :cite:`Heitz2018` "Sampling the GGX Distribution of
Visible Normals", JCGT 7(4). :cite:`Arvo1995` "Applications of Irradiance Tensors to the Simulation of Non-Lambertian
Phenomena", SIGGRAPH 1995.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from basis.parallel import one_blas_thread, threaded_map, worker_count
from basis.validation import ParameterError, as_float_array, check_choice, check_positive_int, check_range

from .ggx import g1, ndf, roughness_to_alpha, sample_vndf, view_vector, visibility_g2
from .lut import LTC_LAYOUT, LutGrid
from .quadrature import directional_albedo

__all__ = [
    "ALPHA_FLOOR",
    "AXES",
    "EDGE_FACTOR_DEGREE",
    "LOBE_RATIO_MAX",
    "LOBE_RATIO_PER_SIZE",
    "LOBE_SHARE_RAISED",
    "LOBE_SPREAD_POWER",
    "LOBE_SPREAD_RATIO",
    "LOBE_SPREAD_SHARE",
    "LOBE_WEIGHT_POWER",
    "LTC_CHANNELS",
    "MU_FLOOR",
    "PUNCTUAL_SPREAD",
    "SPLIT_SUM_WEIGHT_LINEAR",
    "SPLIT_SUM_WEIGHT_POWER",
    "UPPER_SHARE_POWER",
    "WEIGHTINGS",
    "LtcFit",
    "checked_ltc_grid",
    "disk_solid_angle",
    "edge_factor",
    "edge_factor_polynomial",
    "fit_albedo",
    "fit_points",
    "ltc_grid",
    "fit_ltc",
    "horizon_ltc_vector",
    "lobe_error",
    "ltc_density",
    "ltc_direction",
    "ltc_inverse",
    "ltc_solid_angle",
    "ltc_upper_share",
    "lobe_density_ratio",
    "lobe_ratio_bound",
    "lobe_spread",
    "mean_half_v_dot_h",
    "polygon_integral",
    "polygon_vector",
    "punctual_roughness",
    "rect_light_direction",
    "rect_light_fresnel",
    "rect_light_half_cosine",
    "rect_light_integral",
    "shading_frame",
    "smoothed_fresnel",
    "split_sum_weight",
    "stored_density",
    "stored_lobe_error",
    "target_lobe",
    "toward_lobe_limit",
    "toward_upper_share",
]

#: The stored entries of M⁻¹ / (M⁻¹)₁₁, in RGBA order: the public tables' (three.js ``ltc_1``) order.
LTC_CHANNELS = ("m00", "m20", "m02", "m22")
_FIT_GRID = 24  # per axis of each direction grid: 2 × 24² directions per texel for the fit
_ERROR_GRID = 48  # and 2 × 48² for the lobe error reported
_ITERATIONS_FIRST, _ITERATIONS = 80, 30


#: The smallest α and μo a texel is fitted at (the end points r = 0 and μo = 0 are degenerate lobes).
ALPHA_FLOOR, MU_FLOOR = 1e-4, 1e-3


def ltc_grid(size: int = 64, visibility: str = "height-correlated") -> LutGrid:
    """The LTC table's grid (:data:`preintegrate.lut.LTC_LAYOUT`), the axes of the public LTC tables (``ltc_code``,
    three.js ``LTC_Uv``), so that an engine's existing area-light code reads it unchanged: column i ↔ perceptual
    roughness r = i / (size − 1), row j ↔ √(1 − μo) = j / (size − 1), end points on texel centres
    (u = r (size − 1)/size + 0.5/size, the same for v). Measured against this project's texel-centre axes (μo, r) on
    random (μo, r): the end-point √(1 − μo) rows reach normal incidence, where narrow lobes move fastest with μo (see
    ``report/area_lights.md``). The fit stands at α ≥ :data:`ALPHA_FLOOR` and μo ≥ :data:`MU_FLOOR`
    (:func:`fit_points`).

    >>> grid = ltc_grid(3)
    >>> grid.roughness.tolist(), grid.mu_o.tolist()
    ([0.0, 0.5, 1.0], [1.0, 0.75, 0.0])
    """
    size = check_positive_int("size", size, low=2, high=1024)
    return LutGrid(size, size, rows="sine-endpoints", visibility=visibility, columns="roughness-endpoints")


def fit_points(grid: LutGrid) -> tuple[np.ndarray, np.ndarray]:
    """(μo per row, α per column) at which an LTC table on ``grid`` is fitted: the grid's, at least :data:`MU_FLOOR`
    and :data:`ALPHA_FLOOR` (the lobe of a mirror or of a view along the horizon has no finite LTC)."""
    return np.maximum(grid.mu_o, MU_FLOOR), np.maximum(grid.alpha, ALPHA_FLOOR)


def checked_ltc_grid(grid) -> LutGrid:
    """``grid`` if it is an :func:`ltc_grid` (the LTC layout), else a ParameterError."""
    if not isinstance(grid, LutGrid) or (grid.columns, grid.rows) != LTC_LAYOUT:
        raise ParameterError(f"grid must be an LTC table's grid (ltc_grid), got {grid!r}")
    return grid


@dataclasses.dataclass(frozen=True, eq=False)
class LtcFit:
    """A fitted table on ``grid`` (rows: view, columns: roughness): ``parameters`` (size, size, 4) = (a, b, c, d) of
    M, ``inverse`` (size, size, 4) = the stored (m00, m20, m02, m22) of M⁻¹ / (M⁻¹)₁₁, ``error`` (size, size) =
    ½∫|f̂ − D| dω per texel; ``weighting`` one of :data:`WEIGHTINGS`, or "per-texel" for
    :func:`preintegrate.ltc_choice.fit_area_ltc`'s choice between two fits."""

    grid: LutGrid
    parameters: np.ndarray
    inverse: np.ndarray
    error: np.ndarray
    weighting: str = "l2"

    @property
    def method(self) -> str:
        """How the table was fitted, as its header states it."""
        if self.weighting == "per-texel":
            return (
                "per texel the mean-axis L2 or the free chi-square fit, whichever holds the GGX lobe over seeded "
                "training lights better (preintegrate.ltc_choice)"
            )
        norm = "L2" if self.weighting == "l2" else "chi-square (residual / sqrt(lobe + lobe max / 10))"
        return f"{norm} by Levenberg-Marquardt on 2 x {_FIT_GRID}^2 fixed directions per texel"


def _midpoints(count: int) -> np.ndarray:
    return (np.arange(count) + 0.5) / count


def _sphere_grid(count: int) -> np.ndarray:
    """(count², 3) directions uniform in z ∈ (−1, 1) and φ: equal-area cells of the sphere."""
    z, phi = np.meshgrid(1.0 - 2.0 * _midpoints(count), 2.0 * np.pi * _midpoints(count), indexing="ij")
    radius = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    return np.stack([radius * np.cos(phi), radius * np.sin(phi), z], axis=-1).reshape(-1, 3)


def target_lobe(omega_i, mu_o, alpha, albedo, visibility: str = "height-correlated", sine=None) -> np.ndarray:
    """f̂(ω_i) = D(h) G2(μo, μi) / (4 μo E): the cosine-weighted GGX lobe without Fresnel, normalised by its
    directional albedo ``albedo`` = E(μo, α); 0 below the horizon. ``omega_i`` (…, 3), the rest broadcast; the view
    (√(1 − μo²), 0, μo), or (``sine``, 0, μo) where sin θo is known more closely (a view near the normal)."""
    omega_i = np.asarray(omega_i, dtype=np.float64)
    mu_o = np.asarray(mu_o, dtype=np.float64)
    omega_o = view_vector(mu_o)
    if sine is not None:
        omega_o = np.stack([np.broadcast_to(sine, mu_o.shape), np.zeros_like(mu_o), mu_o], axis=-1)
    half = omega_o + omega_i
    length = np.linalg.norm(half, axis=-1)
    mu_h = half[..., 2] / np.where(length > 0.0, length, 1.0)
    mu_i = omega_i[..., 2]
    value = ndf(mu_h, alpha) * visibility_g2(visibility)(mu_o, mu_i, alpha) / (4.0 * mu_o * albedo)
    return np.where((mu_i > 0.0) & (length > 0.0), value, 0.0)


def _lobe_pdf(omega_i, mu_o, alpha) -> np.ndarray:
    """Density of ω_i reflected about a visible normal (Heitz 2018): D(h) G1(μo) / (4 μo)."""
    omega_o = view_vector(np.asarray(mu_o, dtype=np.float64))
    half = omega_o + omega_i
    length = np.linalg.norm(half, axis=-1)
    mu_h = half[..., 2] / np.where(length > 0.0, length, 1.0)
    return np.where(length > 0.0, ndf(mu_h, alpha) * g1(mu_o, alpha) / (4.0 * mu_o), 0.0)


def _directions(mu_o: np.ndarray, alpha: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(T, N, 3) directions and (T, N) weights 1/(N pdf) of the fit's fixed set for T texels: count² reflected
    visible normals and count² cells of the sphere, balance heuristic."""
    u1, u2 = (grid.reshape(-1) for grid in np.meshgrid(_midpoints(count), _midpoints(count), indexing="ij"))
    omega_o = view_vector(mu_o)[:, None, :]
    half = sample_vndf(omega_o, alpha[:, None], u1[None, :], u2[None, :])
    reflected = 2.0 * np.sum(omega_o * half, axis=-1, keepdims=True) * half - omega_o
    sphere = np.broadcast_to(_sphere_grid(count)[None], (len(mu_o), count * count, 3))
    directions = np.concatenate([reflected, sphere], axis=1)
    pdf = 0.5 * _lobe_pdf(directions, mu_o[:, None], alpha[:, None]) + 0.5 / (4.0 * np.pi)
    return directions, 1.0 / (directions.shape[1] * pdf)


def _matrix_inverse(parameters: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(…, 3, 3) M⁻¹ of (a, b, c, d) and |det M⁻¹|; M = [[a, 0, b], [0, c, 0], [d, 0, 1]]."""
    a, b, c, d = np.moveaxis(parameters, -1, 0)
    pivot = a - b * d
    zero = np.zeros_like(a)
    inverse = np.stack(
        [
            np.stack([1.0 / pivot, zero, -b / pivot], axis=-1),
            np.stack([zero, 1.0 / c, zero], axis=-1),
            np.stack([-d / pivot, zero, a / pivot], axis=-1),
        ],
        axis=-2,
    )
    return inverse, np.abs(1.0 / (c * pivot))


def ltc_density(omega, parameters) -> np.ndarray:
    """D(ω) of the LTC with M = [[a, 0, b], [0, c, 0], [d, 0, 1]] (Heitz 2016 eq. 1-3): ``omega`` (…, N, 3),
    ``parameters`` (…, 4) = (a, b, c, d) with c > 0 and a − b d > 0. With p = a − b d, M⁻¹ω =
    ((x − b z)/p, y/c, (a z − d x)/p) and |det M⁻¹| = 1/(c p)."""
    omega = np.asarray(omega, dtype=np.float64)
    a, b, c, d = (value[..., None] for value in np.moveaxis(np.asarray(parameters, dtype=np.float64), -1, 0))
    x, y, z = omega[..., 0], omega[..., 1], omega[..., 2]
    pivot = a - b * d
    local_x, local_y, local_z = (x - b * z) / pivot, y / c, (a * z - d * x) / pivot
    length2 = local_x * local_x + local_y * local_y + local_z * local_z
    return np.maximum(local_z, 0.0) / (np.pi * np.abs(c * pivot) * length2 * length2)


def _unpack(free: np.ndarray, theta: np.ndarray) -> np.ndarray:
    """(…, 4) (a, b, c, d) of M = R_y(θ) [[s, 0, t], [0, u, 0], [0, 0, 1]] normalised to m22 = 1, from the free
    (log s, t, log u): m22 = cos θ − t sin θ, a = s cos θ / m22, b = (t cos θ + sin θ) / m22, c = u / m22,
    d = −s sin θ / m22. Four free entries (log a, b, log c, d): M itself (``axis="free"``)."""
    if free.shape[-1] == 4:
        return np.stack([np.exp(free[..., 0]), free[..., 1], np.exp(free[..., 2]), free[..., 3]], axis=-1)
    s, t, u = np.exp(free[..., 0]), free[..., 1], np.exp(free[..., 2])
    cosine, sine = np.cos(theta), np.sin(theta)
    m22 = cosine - t * sine
    return np.stack([s * cosine / m22, (t * cosine + sine) / m22, u / m22, -s * sine / m22], axis=-1)


def _residuals(free, theta, directions, weights, target) -> np.ndarray:
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):  # a step out of range: inf, refused
        parameters = _unpack(free, theta)
        if free.shape[-1] == 4:
            m22 = parameters[..., 0] - parameters[..., 1] * parameters[..., 3] - 1e-12 * parameters[..., 0]
        else:
            m22 = np.cos(theta) - free[..., 1] * np.sin(theta) - 1e-9
    valid = (m22 > 0.0) & np.all(np.isfinite(parameters), axis=-1)
    safe = np.where(valid[..., None], parameters, np.array([1.0, 0.0, 1.0, 0.0]))
    residual = np.sqrt(weights) * (target - ltc_density(directions, safe))
    return np.where(valid[..., None], residual, np.inf)


def _levenberg_marquardt(free, theta, directions, weights, target, iterations: int) -> np.ndarray:
    """Minimise Σ residual² for every texel at once (T, P) → (T, P); forward-difference Jacobians. A texel stops
    when a step gains less than 1e-10 of its cost or its damping passes 1e10, so each texel's path depends on
    itself alone (the columns can be split among threads without changing a bit)."""
    count = free.shape[1]
    unit = np.eye(count)
    damping = np.full(free.shape[0], 1e-3)
    residual = _residuals(free, theta, directions, weights, target)
    cost = np.sum(residual * residual, axis=-1)
    active = np.isfinite(cost)
    for _ in range(iterations):
        if not np.any(active):
            break
        step = 1e-6 * np.maximum(1.0, np.abs(free))
        jacobian = np.stack(
            [
                (_residuals(free + step[:, k : k + 1] * unit[k], theta, directions, weights, target) - residual)
                / step[:, k : k + 1]
                for k in range(count)
            ],
            axis=-1,
        )  # (T, N, P)
        jacobian = np.where(np.isfinite(jacobian), jacobian, 0.0)
        normal = np.einsum("tni,tnj->tij", jacobian, jacobian)
        gradient = np.einsum("tni,tn->ti", jacobian, residual)
        damped = normal + damping[:, None, None] * (unit * np.diagonal(normal, axis1=1, axis2=2)[:, None, :])
        damped += 1e-300 * unit
        delta = -np.linalg.solve(damped, gradient[..., None])[..., 0]
        trial = free + delta
        trial_residual = _residuals(trial, theta, directions, weights, target)
        trial_cost = np.sum(trial_residual * trial_residual, axis=-1)
        better = active & (trial_cost < cost)
        gain = np.where(better, cost - trial_cost, 0.0)
        free = np.where(better[:, None], trial, free)
        residual = np.where(better[:, None], trial_residual, residual)
        cost = np.where(better, trial_cost, cost)
        damping = np.where(better, damping / 3.0, np.where(active, damping * 4.0, damping))
        active &= ~((better & (gain <= 1e-10 * cost)) | (damping > 1e10))
    return free


def _mean_angle(directions, weights, target) -> np.ndarray:
    """(T,) the signed polar angle, in the xz plane, of the target lobe's mean direction."""
    mean = np.sum((weights * target)[..., None] * directions, axis=1)
    return np.arctan2(mean[:, 0], np.maximum(mean[:, 2], 1e-9))


def _fit_rows(
    mu_o, alpha, albedo, visibility, start, iterations, axis, weighting="l2"
) -> tuple[np.ndarray, np.ndarray]:
    """Fit the texels of one row's columns (T,): (free (T, P), (a, b, c, d) (T, 4)), from ``start`` (the previous
    row's free parameters) or the guess, whichever is closer: s = u = 2α, t = 0 on the lobe's mean axis; for
    ``axis="free"`` the same matrix in (a, b, c, d). ``weighting`` "chi-square" divides each squared residual by the
    lobe there plus a tenth of its peak: an LTC that puts density where the lobe has little pays for it."""
    directions, weights = _directions(mu_o, alpha, _FIT_GRID)
    target = target_lobe(directions, mu_o[:, None], alpha[:, None], albedo[:, None], visibility)
    theta = _mean_angle(directions, weights, target)
    if weighting == "chi-square":
        weights = weights / (target + 0.1 * np.max(target, axis=-1, keepdims=True))
    spread = np.log(np.clip(2.0 * alpha, 1e-5, 1.0))
    guess = np.stack([spread, np.zeros_like(spread), spread], axis=-1)
    if axis == "free":
        a, b, c, d = np.moveaxis(_unpack(guess, theta), -1, 0)
        guess = np.stack([np.log(a), b, np.log(c), d], axis=-1)
    if start is not None:  # the previous row's shape where it starts closer
        costs = [np.sum(_residuals(c, theta, directions, weights, target) ** 2, axis=-1) for c in (start, guess)]
        guess = np.where((costs[0] <= costs[1])[:, None], start, guess)
    free = _levenberg_marquardt(guess, theta, directions, weights, target, iterations)
    return free, _unpack(free, theta)


def lobe_error(
    parameters, grid: LutGrid, albedo: np.ndarray | None = None, count: int = _ERROR_GRID, workers: int | None = None
) -> np.ndarray:
    """(size, size) half the L1 distance ½∫|f̂ − D| dω between the target lobe and the LTC of ``parameters``
    (size, size, 4) = (a, b, c, d), on 2 × ``count``² directions per texel (0: the same lobe; 1: disjoint); the rows
    shared among ``workers`` threads (default: the machine's cores; the same bits)."""
    grid = checked_ltc_grid(grid)
    albedo = fit_albedo(grid) if albedo is None else albedo
    mu_rows, alpha = fit_points(grid)

    def row_error(row: int) -> np.ndarray:
        mu_o = np.full(grid.width, mu_rows[row])
        directions, weights = _directions(mu_o, alpha, count)
        target = target_lobe(directions, mu_o[:, None], alpha[:, None], albedo[row][:, None], grid.visibility)
        return 0.5 * np.sum(weights * np.abs(target - ltc_density(directions, parameters[row])), axis=-1)

    return np.stack(list(threaded_map(row_error, range(grid.height), workers)))


def stored_density(stored, omega) -> np.ndarray:
    """D(ω) of LTCs given as stored entries (…, 4) = (m00, m20, m02, m22) at unit directions ``omega`` (…, 3), the
    rest broadcast: D_o(M⁻¹ω / |M⁻¹ω|) |det M⁻¹| / |M⁻¹ω|³ (Heitz et al. 2016, eq. 1-3; the stored scale cancels)."""
    inverse = ltc_inverse(stored)
    local = np.einsum("...ij,...j->...i", inverse, np.asarray(omega, dtype=np.float64))
    length2 = np.sum(local * local, axis=-1)
    return np.maximum(local[..., 2], 0.0) * np.abs(np.linalg.det(inverse)) / (np.pi * length2 * length2)


def stored_lobe_error(stored, mu_o, roughness, visibility: str = "height-correlated", count: int = _ERROR_GRID):
    """(N,) ½∫|f̂ − D| dω of LTCs given as stored entries (N, 4) = (m00, m20, m02, m22) at (μo, r) (N,): the
    measure of any table (this project's, the public ones) at any point, for the benchmark and the report; 256
    points at a time (2 × count² directions each)."""
    stored = as_float_array("stored", stored)
    mu_o = np.maximum(as_float_array("mu_o", mu_o), MU_FLOOR)
    alpha = np.maximum(roughness_to_alpha(as_float_array("roughness", roughness)), ALPHA_FLOOR)
    errors = []
    for part in np.array_split(np.arange(len(mu_o)), max(1, -(-len(mu_o) // 256))):
        albedo = directional_albedo(
            lambda x: np.ones(np.shape(x) + (1,)), mu_o[part], alpha[part], visibility=visibility, workers=1
        )
        directions, weights = _directions(mu_o[part], alpha[part], count)
        target = target_lobe(directions, mu_o[part, None], alpha[part, None], albedo[..., 0][:, None], visibility)
        density = stored_density(stored[part, None, :], directions)
        errors.append(0.5 * np.sum(weights * np.abs(target - density), axis=-1))
    return np.concatenate(errors)


def fit_albedo(grid: LutGrid) -> np.ndarray:
    """(size, size) E(μo, α) with F = 1 at the fitted points, by the project's quadrature (3e-8 against an
    independent integral)."""
    mu_rows, alpha = fit_points(grid)
    return directional_albedo(
        lambda x: np.ones(np.shape(x) + (1,)), mu_rows[:, None], alpha[None, :], visibility=grid.visibility, workers=1
    )[..., 0]


#: The LTC's axis: the lobe's mean direction (the public fit's), or M's four entries free (the shipped table takes one
#: or the other per texel: preintegrate.ltc_choice).
AXES = ("mean", "free")
#: The fit's norm: L2 of the density (the public fit's), or chi-square (issue 41: the free fit the shipped table takes).
WEIGHTINGS = ("l2", "chi-square")


def fit_ltc(
    grid: LutGrid | None = None,
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
    axis: str = "mean",
    weighting: str = "l2",
) -> LtcFit:
    """The LTC of every texel of ``grid`` (default 64 × 64, height-correlated G2), row by row from normal to grazing
    incidence, the roughness columns of a row shared among ``workers`` threads (default: the machine's cores; the
    result is the same bits); ``axis`` one of :data:`AXES`, ``weighting`` one of :data:`WEIGHTINGS` (module
    docstring: the benchmarks measure them)."""
    check_choice("axis", axis, AXES)
    check_choice("weighting", weighting, WEIGHTINGS)
    grid = ltc_grid() if grid is None else checked_ltc_grid(grid)
    albedo = fit_albedo(grid)
    mu_rows, alpha = fit_points(grid)
    size = grid.width
    fitted = np.empty((size, size, 4))
    chunks = np.array_split(np.arange(size), min(size, 4 * worker_count(workers)))
    free = None
    with one_blas_thread(), ThreadPoolExecutor(worker_count(workers)) as pool:
        for row, mu in enumerate(mu_rows):
            mu_o = np.full(size, mu)
            iterations = _ITERATIONS_FIRST if row == 0 else _ITERATIONS
            parts = pool.map(
                lambda columns: _fit_rows(
                    mu_o[columns],
                    alpha[columns],
                    albedo[row, columns],
                    grid.visibility,
                    None if free is None else free[columns],
                    iterations,
                    axis,
                    weighting,
                ),
                chunks,
            )
            parts = list(parts)
            free = np.concatenate([part[0] for part in parts])
            fitted[row] = np.concatenate([part[1] for part in parts])
            if progress is not None:
                progress(row + 1, size + 1)
    inverse, _ = _matrix_inverse(fitted)
    stored = np.stack([inverse[..., 0, 0], inverse[..., 2, 0], inverse[..., 0, 2], inverse[..., 2, 2]], axis=-1)
    stored /= inverse[..., 1, 1][..., None]
    error = lobe_error(fitted, grid, albedo, workers=workers)
    if progress is not None:
        progress(size + 1, size + 1)
    return LtcFit(grid, fitted, stored, error, weighting)


def ltc_inverse(stored) -> np.ndarray:
    """(…, 3, 3) M⁻¹ (up to scale) from the stored (…, 4) = (m00, m20, m02, m22): [[m00, 0, m02], [0, 1, 0],
    [m20, 0, m22]], as the shaders (and three.js's ``mat3(vec3(t.x, 0, t.y), …)``) build it."""
    stored = as_float_array("stored", stored)
    m00, m20, m02, m22 = np.moveaxis(stored, -1, 0)
    zero, one = np.zeros_like(m00), np.ones_like(m00)
    return np.stack(
        [np.stack([m00, zero, m02], -1), np.stack([zero, one, zero], -1), np.stack([m20, zero, m22], -1)], -2
    )


def _edge(p, q) -> np.ndarray:
    """Lambert's edge vector (p̂ × q̂) θ / sin θ, θ the angle between p and q (Heitz 2016 eq. 11 without 1/2π)."""
    p = p / np.linalg.norm(p, axis=-1, keepdims=True)
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    cross = np.cross(p, q)
    sine = np.linalg.norm(cross, axis=-1)
    cosine = np.sum(p * q, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        ratio = np.where(sine > 1e-12, np.arctan2(sine, cosine) / sine, 1.0)
    return cross * ratio[..., None]


#: Degree of :func:`edge_factor_polynomial`: 7 is within 8.7e-7 of θ / sin θ (and float32 evaluates it within 9.5e-7,
#: about eight units of its last place: float32's atan on GPUs is no closer; degree 8: 1.4e-7).
EDGE_FACTOR_DEGREE = 7


def edge_factor_polynomial(degree: int = EDGE_FACTOR_DEGREE) -> np.ndarray:
    """(degree + 1,) coefficients, constant first, of the polynomial P(u) that interpolates θ / sin θ at the
    ``degree`` + 1 Chebyshev–Lobatto points of u = 1 − cos θ ∈ [0, 1] (θ ≤ π/2; P(0) = 1 and P(1) = π/2 to
    round-off): the factor of Lambert's edge vector (Heitz 2016 eq. 11) as the shaders evaluate it, by Horner, and
    beyond a right angle as π / sin θ − P(1 + cos θ) (:func:`edge_factor`). In u, the constant 1 comes last in Horner's
    order: a short edge's factor is 1 plus u times the rest, so float32 rounds it as it rounds 1, not as it rounds
    the sum of the coefficients (in cos θ, edges a thousandth as long as their distance cancelled to 2e-4 of their
    light). θ / sin θ is analytic there (its nearest singularity is u = 2), so the error falls geometrically with the
    degree.

    >>> c = edge_factor_polynomial()
    >>> round(float(c[0]), 12), round(float(c.sum()), 12)
    (1.0, 1.570796326795)
    """
    degree = check_positive_int("degree", degree, low=1, high=32)
    u = 0.5 - 0.5 * np.cos(np.pi * np.arange(degree + 1) / degree)
    sine = np.sqrt(u * (2.0 - u))
    ratio = np.where(u > 0.0, np.arccos(1.0 - u) / np.where(u > 0.0, sine, 1.0), 1.0)
    return np.polynomial.polynomial.polyfit(u, ratio, degree)


def edge_factor(cosine, sine, coefficients=None) -> np.ndarray:
    """θ / sin θ of the angle with ``cosine`` and ``sine`` (≥ 0, > 0 where ``cosine`` < 0) as the shaders take it:
    P(1 − cos θ) for cos θ ≥ 0, π / sin θ − P(1 + cos θ) below (θ / sin θ + (π − θ) / sin(π − θ) = π / sin θ); P the
    polynomial of ``coefficients`` (default :func:`edge_factor_polynomial`).

    >>> theta = np.array([1e-3, 1.0, 2.0, 3.1])
    >>> bool(np.all(np.abs(edge_factor(np.cos(theta), np.sin(theta)) * np.sin(theta) / theta - 1.0) < 1e-6))
    True
    """
    coefficients = edge_factor_polynomial() if coefficients is None else np.asarray(coefficients, dtype=np.float64)
    cosine = np.asarray(cosine, dtype=np.float64)
    sine = np.asarray(sine, dtype=np.float64)
    near = np.polynomial.polynomial.polyval(1.0 - np.abs(cosine), coefficients)
    with np.errstate(divide="ignore"):
        return np.where(cosine >= 0.0, near, np.pi / np.where(cosine >= 0.0, 1.0, sine) - near)


def polygon_integral(vertices) -> np.ndarray:
    """∫ of the clamped cosine max(0, z)/π over the spherical polygon of ``vertices`` (…, V, 3) (directions from
    the origin; the polygon clipped to z ≥ 0 edge by edge): Lambert's formula (Heitz 2016 eq. 11). Positive when
    the vertices turn counter-clockwise seen from the origin, i.e. (v1 − v0) × (v3 − v0) points towards it: the
    winding three.js gives a rectangular light that faces the shaded point."""
    return polygon_vector(vertices)[..., 2]


def polygon_vector(vertices) -> np.ndarray:
    """(…, 3) the vector form factor of the polygon clipped to z ≥ 0, (1/π) ∫ ω dω over it (Arvo 1994's vector
    irradiance; Heitz 2016 eq. 11 per component): its z is :func:`polygon_integral`, its direction the polygon's
    mean direction, its length at most 1."""
    vertices = as_float_array("vertices", vertices)
    if vertices.ndim < 2 or vertices.shape[-1] != 3 or vertices.shape[-2] < 3:
        raise ParameterError(f"vertices must be (..., V >= 3, 3), got shape {vertices.shape}")
    return _edges_vector(*_clip_edges(vertices, np.roll(vertices, -1, axis=-2)))


def _clip_edges(p, q, kept=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The edges p → q (…, E, 3) of a convex polygon (``kept`` (…, E) marks the edges it has; default all) clipped
    to z ≥ 0 one by one, and the horizon edge that closes the clipped polygon from its exit to its entry point:
    (starts, ends (…, E + 1, 3), kept (…, E + 1))."""
    kept = np.ones(p.shape[:-1], dtype=bool) if kept is None else kept
    above_p, above_q = p[..., 2] >= 0.0, q[..., 2] >= 0.0
    with np.errstate(invalid="ignore", divide="ignore"):
        t = p[..., 2] / (p[..., 2] - q[..., 2])
    crossing = p + np.where(np.isfinite(t), t, 0.0)[..., None] * (q - p)
    start = np.where(above_p[..., None], p, crossing)
    end = np.where(above_q[..., None], q, crossing)
    exits = kept & above_p & ~above_q
    entries = kept & ~above_p & above_q
    exit_point = np.sum(np.where(exits[..., None], crossing, 0.0), axis=-2, keepdims=True)
    entry_point = np.sum(np.where(entries[..., None], crossing, 0.0), axis=-2, keepdims=True)
    closed = np.any(exits, axis=-1, keepdims=True) & np.any(entries, axis=-1, keepdims=True)
    return (
        np.concatenate([start, exit_point], axis=-2),
        np.concatenate([end, entry_point], axis=-2),
        np.concatenate([kept & (above_p | above_q), closed], axis=-1),
    )


def _edges_vector(start, end, kept) -> np.ndarray:
    """(…, 3) −Σ Lambert's edge vectors / 2π over the ``kept`` edges start → end (…, E, 3) of a closed polygon."""
    safe_start = np.where(kept[..., None], start, [1.0, 0.0, 0.0])
    safe_end = np.where(kept[..., None], end, [1.0, 0.0, 0.0])
    return -np.sum(np.where(kept[..., None], _edge(safe_start, safe_end), 0.0), axis=-2) / (2.0 * np.pi)


def horizon_ltc_vector(stored, local) -> np.ndarray:
    """(…, 3) the vector form factor, in the cosine's space, of the quad ``local`` (…, 4, 3) (shading frame: the
    normal is z) clipped first to the shading horizon and then, through M⁻¹ of ``stored`` (…, 4), to the cosine's:
    the LTC's density counts only where the BRDF lives (above the surface) and where the LTC does (issue 41: a light
    across the horizon, 462 % → 249 % p90 of the lobe alone, ``benchmarks.area_light_set``). Its z is ∫_P D dω over
    the part of the quad above the horizon."""
    start, end, kept = _clip_edges(local, np.roll(local, -1, axis=-2))
    inverse = ltc_inverse(stored)[..., None, :, :]
    start = np.einsum("...ij,...j->...i", inverse, start)
    end = np.einsum("...ij,...j->...i", inverse, end)
    return _edges_vector(*_clip_edges(start, end, kept))


def shading_frame(normal, view) -> np.ndarray:
    """(…, 3, 3) rows T1, T2, N: the local frame in which the view lies in the xz plane (T1 along the view's
    tangential part; a fixed tangent where the view is within 1e-4 rad of the normal, where the LTC is isotropic
    to float32's resolution and float32's tangent would be rounding noise)."""
    normal = as_float_array("normal", normal)
    view = as_float_array("view", view)
    tangent = view - normal * np.sum(view * normal, axis=-1, keepdims=True)
    tangent = tangent - normal * np.sum(tangent * normal, axis=-1, keepdims=True)  # as float32 needs it
    length = np.linalg.norm(tangent, axis=-1, keepdims=True)
    fallback = np.cross(normal, np.where(np.abs(normal[..., :1]) < 0.9, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]))
    fallback /= np.linalg.norm(fallback, axis=-1, keepdims=True)
    t1 = np.where(length > 1e-4, tangent / np.where(length > 0.0, length, 1.0), fallback)
    t2 = np.cross(normal, t1)
    return np.stack([t1, t2, normal], axis=-2)


def rect_light_integral(stored, normal, view, position, corners) -> np.ndarray:
    """∫_P D dω of the LTC of ``stored`` (…, 4) (one texel's M⁻¹ entries, as fetched) over the part above the
    horizon of the quad ``corners`` (…, 4, 3) seen from ``position`` (…, 3) with ``normal`` and ``view`` (…, 3)
    (:func:`horizon_ltc_vector`): one-sided (0 from behind), what the shaders' ``fresnelLtcRect`` computes."""
    return np.maximum(horizon_ltc_vector(stored, _local_corners(normal, view, position, corners))[..., 2], 0.0)


def _local_corners(normal, view, position, corners) -> np.ndarray:
    """(…, 4, 3) the quad's corners relative to ``position`` in the :func:`shading_frame`."""
    frame = shading_frame(normal, view)
    return np.einsum(
        "...ij,...vj->...vi", frame, as_float_array("corners", corners) - np.asarray(position)[..., None, :]
    )


def rect_light_direction(stored, normal, view, position, corners) -> tuple[np.ndarray, np.ndarray]:
    """(:func:`rect_light_integral`, the light's representative direction (…, 3) in the shading frame): the direction
    of the transformed quad's vector form factor (:func:`horizon_ltc_vector`, its mean direction in the cosine's space)
    taken back through M (the LTC of ``stored``); where the quad lies below the horizon, the normal."""
    vector = horizon_ltc_vector(stored, _local_corners(normal, view, position, corners))
    return np.maximum(vector[..., 2], 0.0), ltc_direction(stored, vector)


def ltc_direction(stored, vector) -> np.ndarray:
    """(…, 3) a light's representative direction M f / |M f| from the vector form factor ``vector`` f (…, 3) of its
    transformed polygon (:func:`horizon_ltc_vector`), M the LTC of ``stored`` (…, 4); the normal where f is 0 (the
    light below the horizon)."""
    return _unit_or_normal(_taken_back(stored, as_float_array("vector", vector)))


def _taken_back(stored, vector) -> np.ndarray:
    """(…, 3) M f: the cosine's-space ``vector`` f (…, 3) taken back through M, the LTC of ``stored`` (…, 4)."""
    return np.einsum("...ij,...j->...i", np.linalg.inv(ltc_inverse(stored)), vector)


def _unit_or_normal(back) -> np.ndarray:
    """(…, 3) M f / |M f| from ``back`` = M f (:func:`_taken_back`); the normal where f is 0 (the quad below the
    horizon)."""
    length = np.linalg.norm(back, axis=-1, keepdims=True)
    return np.where(length > 0.0, back / np.where(length > 0.0, length, 1.0), [0.0, 0.0, 1.0])


def ltc_solid_angle(stored, vector) -> np.ndarray:
    """(…) Ω ≈ π |f|⁴ / (|det M⁻¹| |M f|³): the solid angle of a light whose transformed polygon has the vector form
    factor ``vector`` f (…, 3) (:func:`horizon_ltc_vector`), the LTC of ``stored`` (…, 4), as the LTC's own Jacobian at
    its representative direction L = M f / |M f| gives it: ∫_P D dω ≈ D(L) Ω with D(L) = f_z |det M⁻¹| / (π |M⁻¹ L|³)
    (Heitz 2016 eq. 1-3) and f_z the integral, so Ω = π |M⁻¹ L|³ / |det M⁻¹| with |M⁻¹ L| = |f| / |M f|; exact as the
    light shrinks, and no difference of nearly equal terms (the shaders' ``fresnelLtcTowardLobe`` takes √Ω as
    √π |det| q |back|^½, q = |f|² / |back|², back = |det| M f). 0 where f is."""
    vector = as_float_array("vector", vector)
    return _solid_angle(stored, vector, _taken_back(stored, vector))


def disk_solid_angle(local) -> np.ndarray:
    """(…) the solid angle of the quad ``local`` (…, 4, 3) (its corners from the shaded point; the whole quad, not
    clipped to the horizon) as that of a disk seen on its axis with the quad's projected solid angle
    Ω_p = |c · a| / |c|³, c the quad's centre, a = ½ (v₂ − v₀) × (v₃ − v₁) its vector area:
    2π (1 − 1 / √(1 + Ω_p / π)), written 2 Ω_p / (ρ (1 + ρ)), ρ = √(1 + Ω_p / π) (no difference of nearly equal
    terms for a small light). Exact for a disk seen on its axis and as the light shrinks, at most 2π; never below a
    quad's exact solid angle in tests/preintegrate/test_ltc.py and at most 1.29 × it for quads seen obliquely (the
    exact one would take the shaders a fan of atan2 per light)."""
    local = as_float_array("local", local)
    if local.ndim < 2 or local.shape[-2:] != (4, 3):
        raise ParameterError(f"local must be (..., 4, 3), got shape {local.shape}")
    centre = np.mean(local, axis=-2)
    area = 0.5 * np.cross(local[..., 2, :] - local[..., 0, :], local[..., 3, :] - local[..., 1, :])
    distance2 = np.maximum(np.sum(centre * centre, axis=-1), 1e-300)
    projected = np.abs(np.sum(centre * area, axis=-1)) / (distance2 * np.sqrt(distance2))
    root = np.sqrt(1.0 + projected / np.pi)
    return 2.0 * projected / (root * (1.0 + root))


def lobe_spread(ltc_angle, solid_angle) -> np.ndarray:
    """(…) min(Ω_L / Ω, 1): a light's spread (:data:`LOBE_SPREAD_POWER`) from its solid angle as the LTC gives it,
    ``ltc_angle`` Ω_L (:func:`ltc_solid_angle`), and its own, ``solid_angle`` Ω (:func:`disk_solid_angle`); 1 where
    Ω is 0."""
    ltc_angle = np.asarray(ltc_angle, dtype=np.float64)
    solid_angle = np.asarray(solid_angle, dtype=np.float64)
    return np.where(solid_angle > 0.0, np.minimum(ltc_angle / np.where(solid_angle > 0.0, solid_angle, 1.0), 1.0), 1.0)


def _solid_angle(stored, vector, back) -> np.ndarray:
    """:func:`ltc_solid_angle` from f = ``vector`` and ``back`` = M f (:func:`_taken_back`), where both are at hand."""
    determinant = np.abs(np.linalg.det(ltc_inverse(stored)))
    denominator = determinant * np.linalg.norm(back, axis=-1) ** 3
    length = np.linalg.norm(vector, axis=-1)
    return np.where(denominator > 0.0, np.pi * length**4 / np.where(denominator > 0.0, denominator, 1.0), 0.0)


def lobe_density_ratio(
    stored, direction, mu_o, alpha, albedo, visibility: str = "height-correlated", sine=None
) -> np.ndarray:
    """(…) f̂(L) / D(L) at unit directions L ``direction`` (…, 3) of the shading frame: the lobe normalised by
    ``albedo`` E (:func:`target_lobe`: the view (``sine``, 0, μo), μo at least 1e-6, where f̂ is continuous) over the
    density of the LTC of ``stored`` (…, 4) (:func:`stored_density`); 1 where that density is 0."""
    density = stored_density(stored, direction)
    lobe = target_lobe(direction, np.maximum(mu_o, 1e-6), alpha, albedo, visibility, sine)
    return np.where(density > 0.0, lobe / np.where(density > 0.0, density, 1.0), 1.0)


#: The bound on how far the lobe-to-LTC density ratio raises a rectangular light's integral (:func:`toward_lobe_limit`)
#: is R = max(R₀, min(K √Ω, S / I)) (:func:`lobe_ratio_bound`): R₀ = ``LOBE_RATIO_MAX`` for any light, more for a light
#: that is not tiny (K = ``LOBE_RATIO_PER_SIZE`` per unit of √Ω, its angular size) as long as the raised value stays a
#: small share of the lobe (S = ``LOBE_SHARE_RAISED``; the normalised lobe integrates to 1). The three, with the
#: weight's power p (:data:`LOBE_WEIGHT_POWER`), are the candidates' (p, R₀, K, S) whose lobe error on seeded training
#: lights 0.02 to 10 wide (:func:`preintegrate.ltc_choice.training_lights`, not the benchmark's set) has the lowest p90,
#: then median, with the worst within 1.25 × that of the ratio at most 1 (``python -m benchmarks.area_light_set``, "The
#: weight and the bound of the lobe's ratio"). Finite, and growing with √Ω, because the ratio multiplies float32's
#: rounding of the integral, a difference of edge terms each some 1 / √Ω times larger than it (a light's width over its
#: distance against its solid angle), most where the LTC's density at the light is far below the lobe's (unbounded, a
#: light 2e-3 wide is off by 1.2e-2 of its largest value; K = 400 doubles float32's error of lights 0.02 to 0.2 wide, a
#: light 0.06 wide 1.2e-4 off where K = 100 or 200 leaves 6.1e-5 and the LTC's own integral 5.4e-5:
#: tests/luts/test_shaders_area.py). Ω is the light's solid angle as the LTC gives it (:func:`ltc_solid_angle`), which
#: the shaders have at the cost of a few multiplies.
LOBE_RATIO_MAX = 1.5
LOBE_RATIO_PER_SIZE = 100.0
LOBE_SHARE_RAISED = 0.03


def lobe_ratio_bound(
    integral, solid_angle, least=LOBE_RATIO_MAX, per_size=LOBE_RATIO_PER_SIZE, share=LOBE_SHARE_RAISED
) -> np.ndarray:
    """(…) max(R₀, min(K √Ω, S / I)): the most the lobe-to-LTC ratio may raise an LTC ``integral`` I over a light of
    ``solid_angle`` Ω (:func:`ltc_solid_angle`); R₀ = ``least``, K = ``per_size``, S = ``share``, by default what
    ships, :data:`LOBE_RATIO_MAX`, :data:`LOBE_RATIO_PER_SIZE` and :data:`LOBE_SHARE_RAISED` (see there)."""
    integral = np.asarray(integral, dtype=np.float64)
    size = per_size * np.sqrt(np.asarray(solid_angle, dtype=np.float64))
    return np.maximum(least, np.minimum(size, share / np.maximum(integral, 1e-30)))


#: The power p of the weight w = I^p with which :func:`toward_lobe_limit` keeps the LTC's own integral I against the
#: lobe-to-LTC ratio at the light's representative direction: as I grows the ratio at one direction stands less for
#: the light, and a light that covers the lobe keeps I. Chosen with the ratio's bound (:data:`LOBE_RATIO_MAX`), on
#: the same training lights and by the same criterion, among p = 1/4 to 5/8 in steps of 1/16 (``python -m
#: benchmarks.area_light_set``, "The weight and the bound of the lobe's ratio"; √I, p = 1/2, shipped before: on the
#: set's lights the lobe 3.36 % / 23.9 % median / p90, at 3/8 3.13 % / 19.2 %).
LOBE_WEIGHT_POWER = 0.375

#: The weight w = a I + (1 − a) I^n with which :func:`rect_light_fresnel` blends a rectangular light's Fresnel from
#: F̃ (F averaged over the light, :data:`PUNCTUAL_SPREAD`) toward the split sum F̄ / E, I the light's share of the lobe
#: (a = ``SPLIT_SUM_WEIGHT_LINEAR``, n = ``SPLIT_SUM_WEIGHT_POWER``): the light's Fresnel leaves F̃ as the share of the
#: lobe's V·H it spans grows (the linear part), but is F̄ / E only where it covers all of the lobe, whose far tails, on
#: the viewer's side where V·H → 1, hold a dielectric's lowest F. Chosen with :data:`UPPER_SHARE_POWER` and
#: :data:`PUNCTUAL_SPREAD`, on seeded training lights (drawn where the training views' and roughnesses' lobes reflect,
#: and uniform over the hemisphere), by the total error of the include's form (its lobe and its factor, which take the
#: same I) against the reference: the lowest sum of the worse kind's median over 3 % and p90 over 20 % (issue 41's
#: targets), among the candidates whose p90 is no worse than that of what shipped before, w = I² with no horizon share
#: and F(V·H*) (``python -m benchmarks.area_light_set``, "The Fresnel blend's weight and the horizon's share").
SPLIT_SUM_WEIGHT_LINEAR = 0.5
SPLIT_SUM_WEIGHT_POWER = 16.0

#: The power m of :func:`toward_upper_share`'s min(I/H, 1)^m: how near a light must come to holding all the LTC holds
#: above the horizon before the LTC's share below it counts (chosen with the Fresnel blend's weight,
#: :data:`SPLIT_SUM_WEIGHT_POWER`).
UPPER_SHARE_POWER = 32.0

#: The spread s = Ω_L / Ω of a light: Ω_L its solid angle as the LTC's Jacobian at L* gives it (:func:`ltc_solid_angle`,
#: the LTC's integral over its density at L*), Ω its own (:func:`disk_solid_angle`); s is the LTC's mean density over
#: the light against its density at L*, 1 for a small light and small for one much wider than the lobe, and tells how
#: little the ratio at L* stands for the light. :func:`toward_lobe_limit` keeps at least
#: (1 − s^k) min(1, I / c) min(1, ratio / ρ) of the LTC's own integral, k = ``LOBE_SPREAD_POWER``,
#: c = ``LOBE_SPREAD_SHARE``, ρ = ``LOBE_SPREAD_RATIO``: with I^p alone, a light on the lobe's peak and wider than it,
#: holding a few hundredths of it, was raised by the ratio at the peak as if the lobe were that dense all over it, and
#: one beside the peak lowered as if the lobe were that thin all over it; but where the ratio is below ρ the LTC holds
#: several times the lobe at L*, density where the lobe has little (the free fit's thin layer over the viewer's side
#: at grazing views, ``preintegrate.ltc_choice``), and the ratio is taken more. Chosen with the bound and p fixed, by
#: the lowest p90, then median, on seeded lights where the training views' and roughnesses' lobes reflect, among the
#: candidates whose p90 on the bound's training lights, uniform over the hemisphere, is no higher than that of the form
#: shipped before (the term only where the ratio exceeds 1, k = 3) (``python -m benchmarks.area_light_set``, "The
#: lobe's spread"; ``benchmarks.area_light_set.lobe_lights``); k is a power of two, which the shaders square to.
LOBE_SPREAD_POWER = 4.0
LOBE_SPREAD_SHARE = 0.1
LOBE_SPREAD_RATIO = 0.5

#: A rectangular light's Fresnel away from the split sum is F averaged over its directions' half vectors, which spread
#: about H* (along V + L*) as the light's directions spread, over a solid angle Ω_L (:func:`ltc_solid_angle`: the
#: light's extent under the lobe, at most about the lobe's own): F̄' / E' of a GGX lobe of perceptual roughness
#: r' = min(r, k √Ω_L) seen at V·H*, k = ``PUNCTUAL_SPREAD`` (:func:`punctual_roughness`), read from the table that
#: holds the split sum (its mirror row, r' = 0, is the curve itself: F(V·H*) for a small light). F is convex in V·H,
#: so a light spanning a range of V·H reflects more than F at its middle (most for a dielectric under a rough lobe);
#: r' stops at r, where a light as wide as the lobe sees the lobe's own V·H. Chosen with the Fresnel blend's weight
#: (:data:`SPLIT_SUM_WEIGHT_POWER`), by its criterion, among k = 0 (F(V·H*) itself, shipped before) to 0.5
#: (``python -m benchmarks.area_light_set``, "The Fresnel blend's weight and the horizon's share").
PUNCTUAL_SPREAD = 0.3


def toward_lobe_limit(
    integral,
    ratio,
    power=LOBE_WEIGHT_POWER,
    spread=None,
    spread_power=LOBE_SPREAD_POWER,
    spread_share=LOBE_SPREAD_SHARE,
    spread_ratio=LOBE_SPREAD_RATIO,
) -> np.ndarray:
    """(…) an LTC ``integral`` I taken toward the lobe's own punctual limit, min(I (w + (1 − w) ``ratio``), 1),
    w = min(I, 1)^p, p = ``power`` (default :data:`LOBE_WEIGHT_POWER`): ``ratio`` the lobe over the LTC's density at
    the light's representative direction (:func:`lobe_density_ratio`). As a light shrinks, I × ratio tends to the
    lobe's own integral over it; as it covers the lobe, w → 1 keeps the LTC's; the normalised lobe integrates to 1,
    which bounds any light's share (issue 41; the shaders take min(ratio, :func:`lobe_ratio_bound`):
    :func:`rect_light_half_cosine`). With the light's ``spread`` s ∈ [0, 1] (…) (:data:`LOBE_SPREAD_POWER`), w is at
    least (1 − s^k) min(1, I / c) min(1, ratio / ρ), k = ``spread_power``, c = ``spread_share``, ρ = ``spread_ratio``."""
    integral = np.asarray(integral, dtype=np.float64)
    weight = np.clip(integral, 0.0, 1.0) ** check_range("power", power, 0.0, 8.0, low_open=True)
    if spread is not None:
        spread = check_range("spread", spread, 0.0, 1.0)
        spread_power = check_range("spread_power", spread_power, 0.0, 8.0, low_open=True)
        spread_share = check_range("spread_share", spread_share, 0.0, 1.0, low_open=True)
        spread_ratio = check_range("spread_ratio", spread_ratio, 0.0, 1.0, low_open=True)
        wide = (1.0 - spread**spread_power) * np.minimum(integral / spread_share, 1.0)
        weight = np.maximum(weight, wide * np.minimum(np.asarray(ratio, dtype=np.float64) / spread_ratio, 1.0))
    return np.minimum(integral * (weight + (1.0 - weight) * ratio), 1.0)


def ltc_upper_share(stored) -> np.ndarray:
    """(…) H = (1 + n_z) / 2: the share of the LTC of ``stored`` (…, 4) above the shading horizon, n the unit normal
    (M's third row) of the plane that M⁻¹ takes the horizon to. The clamped cosine's integral over the lune between
    its own horizon and that plane, by the lune's vector form factor (π z + π n) / 2 (Arvo 1995: each of its two
    half great circles adds θ = π times its plane's normal, halved); 1 where M keeps the normal's axis; at least 1e-3, as
    the shaders' ``fresnelLtcTowardUpper`` takes it (:func:`toward_upper_share` divides by it)."""
    stored = as_float_array("stored", stored)
    if stored.shape[-1:] != (4,):
        raise ParameterError(f"stored must be (..., 4), got shape {stored.shape}")
    m00, m20, m02, m22 = np.moveaxis(stored, -1, 0)
    # M = adj(M⁻¹) / det: its third row is (−m20, 0, m00) / det
    length = np.hypot(m00, m20)
    cosine = np.sign(m00 * m22 - m02 * m20) * m00 / np.where(length > 0.0, length, 1.0)
    return np.maximum(0.5 * (1.0 + np.where(length > 0.0, cosine, 1.0)), 1e-3)


def toward_upper_share(integral, upper_share, power=UPPER_SHARE_POWER) -> np.ndarray:
    """(…) min(I (1 + (1/H − 1) min(I/H, 1)^m), 1): an LTC ``integral`` I with the LTC's share below the shading
    horizon, 1 − H (``upper_share`` H, :func:`ltc_upper_share`), counted for a light as it comes to hold all that the LTC
    holds above it, m = ``power`` (default :data:`UPPER_SHARE_POWER`): I = H (all the LTC holds above the horizon)
    becomes 1, the lobe's own integral over the hemisphere; a small I stays as it is."""
    integral = np.asarray(integral, dtype=np.float64)
    upper = check_range("upper_share", upper_share, 0.0, 1.0, low_open=True)
    power = check_range("power", power, 0.0, 64.0, low_open=True)
    share = np.minimum(integral / upper, 1.0) ** power
    return np.minimum(integral * (1.0 + (1.0 / upper - 1.0) * share), 1.0)


def rect_light_half_cosine(
    stored,
    normal,
    view,
    position,
    corners,
    roughness=None,
    albedo=None,
    upper_power=UPPER_SHARE_POWER,
    direction_spread=0.0,
    punctual_spread=PUNCTUAL_SPREAD,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(:func:`rect_light_integral`, V·H* (…), r' (…)): H* along V + R L*, L* the light's representative direction
    (:func:`rect_light_direction`), R = 1 as the shaders take it (``direction_spread`` c > 0, for the benchmark's
    studies: R = max(1 − c Ω_L, 0), :func:`mean_half_v_dot_h`), the view
    (|N × V|, 0, N·V) in the shading frame with N·V clamped to [0, 1] ((1, 0, 0) below the horizon), as the shaders'
    ``fresnelLtcView`` and ``fresnelLtcVdotH``. With the perceptual ``roughness`` r ∈ [0, 1] and the lobe's ``albedo`` E > 0
    (…), the integral is taken toward the lobe's punctual limit, :func:`toward_lobe_limit` with
    min(:func:`lobe_density_ratio`, :func:`lobe_ratio_bound`) and the light's :func:`lobe_spread` (from
    :func:`disk_solid_angle`), α = max(r², :data:`ALPHA_FLOOR`), and then toward the LTC's share above the horizon
    (:func:`toward_upper_share` with ``upper_power``, default :data:`UPPER_SHARE_POWER`; None leaves it out, for the
    benchmark's studies): what the shaders' ``fresnelLtcRectVector`` returns for albedo E; and r' the roughness of the
    lobe whose F average stands for the light's (:func:`punctual_roughness` with ``punctual_spread``, default
    :data:`PUNCTUAL_SPREAD`; 0 where no roughness is given), as ``fresnelLtcRectLight``'s."""
    local = _local_corners(normal, view, position, corners)
    vector = horizon_ltc_vector(stored, local)
    back = _taken_back(stored, vector)
    integral, direction = np.maximum(vector[..., 2], 0.0), _unit_or_normal(back)
    normal, view = as_float_array("normal", normal), as_float_array("view", view)
    cosine = np.sum(normal * view, axis=-1)
    n_dot_v = np.clip(cosine, 0.0, 1.0)
    # sin θo as |N × V| (not √(1 − N·V²), which float32's N·V moves by 3e-4 at the normal); a view below the horizon
    # is taken to it, as N·V is clamped (the shaders' fresnelLtcView)
    sine = np.where(cosine > 0.0, np.linalg.norm(np.cross(normal, view), axis=-1), 1.0)
    if (roughness is None) != (albedo is None):
        raise ParameterError("roughness and albedo go together: both (the lobe's limit) or neither (the LTC's own)")
    ltc_angle = _solid_angle(stored, vector, back)
    if albedo is not None:
        alpha = np.maximum(check_range("roughness", roughness, 0.0, 1.0) ** 2, ALPHA_FLOOR)
        albedo = check_range("albedo", albedo, 0.0, 1.0, low_open=True)
        ratio = lobe_density_ratio(stored, direction, n_dot_v, alpha, albedo, sine=sine)
        spread = lobe_spread(ltc_angle, disk_solid_angle(local))
        integral = toward_lobe_limit(integral, np.minimum(ratio, lobe_ratio_bound(integral, ltc_angle)), spread=spread)
        if upper_power is not None:
            integral = toward_upper_share(integral, ltc_upper_share(stored), upper_power)
    local_view = np.stack([sine, np.zeros_like(n_dot_v), n_dot_v], axis=-1)
    smoothing = (
        np.zeros_like(integral) if roughness is None else punctual_roughness(roughness, ltc_angle, punctual_spread)
    )
    return integral, mean_half_v_dot_h(local_view, direction, ltc_angle, direction_spread), smoothing


def mean_half_v_dot_h(local_view, direction, ltc_angle, spread=0.0) -> np.ndarray:
    """(…) V·H, H along V + R L (the mean of V + L over a light whose directions average to R L): ``local_view`` V
    and the light's representative ``direction`` L (…, 3, unit) in the shading frame, ``ltc_angle`` Ω_L its solid angle as the LTC gives it
    (:func:`ltc_solid_angle`), R = max(1 − c Ω_L, 0), c = ``spread`` (broadcast against Ω_L: several c for one light
    give V·H for each); clamped to [0, 1] (0 where R L cancels V), as the shaders' ``fresnelLtcVdotH`` of
    ``fresnelLtcRectVector``'s direction."""
    spread = check_range("spread", spread, 0.0, 1.0)
    length = np.maximum(1.0 - spread * np.asarray(ltc_angle, dtype=np.float64), 0.0)
    half = local_view + length[..., None] * direction
    half = half / np.maximum(np.linalg.norm(half, axis=-1, keepdims=True), 1e-30)
    return np.clip(np.sum(local_view * half, axis=-1), 0.0, 1.0)


def punctual_roughness(roughness, ltc_angle, spread=PUNCTUAL_SPREAD) -> np.ndarray:
    """(…) r' = min(r, k √Ω_L): the perceptual roughness of the GGX lobe whose F average, read at V·H* (F̄' / E' of the
    split-sum table at (V·H*, r')), stands for a rectangular light's own (:data:`PUNCTUAL_SPREAD`); ``roughness`` r in
    [0, 1], ``ltc_angle`` Ω_L ≥ 0 the light's solid angle as the LTC gives it (:func:`ltc_solid_angle`), k = ``spread``
    in [0, 1] (0: F(V·H*) itself), broadcast; the shaders' ``fresnelLtcRectLight`` (k √π on √(Ω_L / π)).

    >>> float(punctual_roughness(0.5, 0.0)), float(punctual_roughness(0.5, 1.0, 0.3)), float(punctual_roughness(0.2, 4.0))
    (0.0, 0.3, 0.2)
    """
    roughness = check_range("roughness", roughness, 0.0, 1.0)
    spread = check_range("spread", spread, 0.0, 1.0)
    return np.minimum(roughness, spread * np.sqrt(check_range("ltc_angle", ltc_angle, 0.0)))


def smoothed_fresnel(
    curve: Callable[[np.ndarray], np.ndarray], v_dot_h, roughness, workers: int | None = None
) -> np.ndarray:
    """(…, C) F averaged over a GGX lobe of perceptual roughness r' seen at V·H: F̄' / E' of ``curve`` (x (N,) →
    (N, C)) at (μo = ``v_dot_h``, α = r'²), by the project's quadrature (:func:`preintegrate.quadrature.directional_albedo`,
    ``workers`` threads); F(V·H) itself at r' = 0. The exact curve's counterpart of the shaders'
    ``fresnelBasisSmoothed`` (a rectangular light's F̃ at r' = :func:`punctual_roughness`).

    >>> float(smoothed_fresnel(lambda x: x[:, None] ** 2, 0.5, 0.0)[0])
    0.25
    """
    v_dot_h = check_range("v_dot_h", v_dot_h, 0.0, 1.0)
    roughness = check_range("roughness", roughness, 0.0, 1.0)
    v_dot_h, roughness = np.broadcast_arrays(v_dot_h, roughness)
    flat_mu, flat_alpha = v_dot_h.ravel(), roughness_to_alpha(roughness.ravel())

    def functions(x):
        values = np.asarray(curve(np.ravel(x)), dtype=np.float64).reshape(np.shape(x) + (-1,))
        return np.concatenate([np.ones(np.shape(x) + (1,)), values], axis=-1)

    both = directional_albedo(functions, flat_mu, flat_alpha, workers=workers)
    return (both[:, 1:] / both[:, :1]).reshape(v_dot_h.shape + (-1,))


def rect_light_fresnel(
    integral, split_sum, punctual, power=SPLIT_SUM_WEIGHT_POWER, linear=SPLIT_SUM_WEIGHT_LINEAR
) -> np.ndarray:
    """(…, C) a rectangular light's specular per unit radiance: the LTC ``integral`` I (…) × mix(``punctual``,
    ``split_sum``, w), w = a I + (1 − a) I^n with I clamped to [0, 1], n = ``power`` and a = ``linear`` (default
    :data:`SPLIT_SUM_WEIGHT_POWER`, :data:`SPLIT_SUM_WEIGHT_LINEAR`); ``punctual`` = E F̃ and ``split_sum`` = F̄
    (…, C) (module docstring; the shaders' ``fresnelBasisRectLight`` and ``fresnelLinearRectLight``)."""
    integral = np.asarray(integral, dtype=np.float64)
    weight = split_sum_weight(integral, power, linear)[..., None]
    return integral[..., None] * (weight * np.asarray(split_sum) + (1.0 - weight) * np.asarray(punctual))


def split_sum_weight(integral, power=SPLIT_SUM_WEIGHT_POWER, linear=SPLIT_SUM_WEIGHT_LINEAR) -> np.ndarray:
    """(…) w = a I + (1 − a) I^n, the split sum's weight in :func:`rect_light_fresnel`: the LTC ``integral`` I (…)
    clamped to [0, 1], n = ``power`` in (0, 64], a = ``linear`` in [0, 1] (the shaders' ``fresnelLtcSplitSumWeight``)."""
    power = check_range("power", power, 0.0, 64.0, low_open=True)
    linear = check_range("linear", linear, 0.0, 1.0)
    share = np.clip(np.asarray(integral, dtype=np.float64), 0.0, 1.0)
    return linear * share + (1.0 - linear) * share**power
