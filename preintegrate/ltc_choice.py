"""The area lights' LTC table: per texel, the mean-axis or the free chi-square fit, whichever lights hold better.

Public objects: ``CHOICE_LIGHTS``, ``CHOICE_WIDTHS``, ``CHOICE_NODES``, ``CHOICE_ROUGHNESS_MIN``,
``facing_rectangle``, ``training_lights``, ``lobe_over_lights``, ``light_nodes``, ``free_texels``, ``per_texel_fit``, ``fit_area_ltc``.

A fit of the lobe's distribution is not a fit of what a rectangular light reflects (issue 41): the mean-axis L2 fit
(the public fit's method, :func:`preintegrate.ltc.fit_ltc`) has no density on the viewer's side, where a rough lobe
still reflects, and the fit with M's four entries free in chi-square (``axis="free", weighting="chi-square"``) holds
that side but, at some grazing texels, spreads a thin layer over the back-scattering half that glows on a glossy
silhouette. Per texel (μo, r), the table keeps whichever of the two holds the lobe better over seeded training lights
(:func:`training_lights`: rectangles 0.1 to 6 wide two units away, over the hemisphere and just below it), by
Σ |log((I E + ε) / (L + ε))|: I the LTC's integral over the light clipped to the horizon
(:func:`preintegrate.ltc.rect_light_integral`, what existing area-light code computes), E the lobe's albedo, L the
lobe over the light by Gauss-Legendre over its area (:func:`lobe_over_lights`), ε = 1e-3 (values below it are the
lobe's far tails, which no LTC holds); below r = 0.07, where no such quadrature resolves the lobe over a large light,
the mean-axis fit stays. Both fits store M⁻¹ in the same four entries, so the table is read as the public one is: the
choice changes values, not code. ``benchmarks.area_light_set`` measures it on lights that are not the training ones.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from basis.parallel import threaded_map
from basis.validation import ParameterError, as_float_array, check_positive_int

from .ltc import LtcFit, checked_ltc_grid, fit_albedo, fit_ltc, fit_points, ltc_grid, rect_light_integral, target_lobe
from .lut import LutGrid

__all__ = [
    "CHOICE_LIGHTS",
    "CHOICE_NODES",
    "CHOICE_ROUGHNESS_MIN",
    "CHOICE_WIDTHS",
    "facing_rectangle",
    "fit_area_ltc",
    "free_texels",
    "light_nodes",
    "lobe_over_lights",
    "per_texel_fit",
    "training_lights",
]

#: The choice's training lights: how many, their widths (log-uniform, at distance 2) and the Gauss-Legendre nodes per
#: axis of each light for the lobe over it (with 64, the choice is the same as with 128 at every texel of r ≥ 0.07).
CHOICE_LIGHTS, CHOICE_WIDTHS, CHOICE_NODES = 24, (0.1, 6.0), 64
#: Below this roughness the lobe is narrower than the nodes resolve over a large light (the choice changes between
#: 128 and 192 nodes): there the mean-axis fit stays, as the public fit.
CHOICE_ROUGHNESS_MIN = 0.07
_FLOOR = 1e-3


def facing_rectangle(theta: float, phi: float, width: float, distance: float = 2.0) -> np.ndarray:
    """(4, 3) a width × width/2 rectangle at ``distance`` from the origin in direction (θ, φ) (z the normal), facing
    the origin, wound so that (c1 − c0) × (c3 − c0) points at it."""
    if not (np.isfinite(width) and width > 0.0 and np.isfinite(distance) and distance > 0.0):
        raise ParameterError(f"width and distance must be positive, got {width!r} and {distance!r}")
    centre = distance * np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])
    facing = -centre / distance
    u = np.cross(facing, [0.0, 0.0, 1.0] if abs(facing[2]) < 0.99 else [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(facing, u)
    a, b = 0.5 * width * u, 0.25 * width * v
    corners = np.array([centre - a - b, centre + a - b, centre + a + b, centre - a + b])
    if np.dot(np.cross(corners[1] - corners[0], corners[3] - corners[0]), facing) < 0.0:
        corners = corners[::-1]
    return corners


def training_lights(count: int = CHOICE_LIGHTS, widths: tuple[float, float] = CHOICE_WIDTHS) -> np.ndarray:
    """(count, 4, 3) seeded rectangles (:func:`facing_rectangle`) two units away: widths log-uniform in ``widths``,
    directions uniform in cos θ ∈ [−0.15, 1] (over the hemisphere and just below it) and in φ."""
    check_positive_int("count", count)
    smallest, largest = widths
    if not 0.0 < smallest <= largest:
        raise ParameterError(f"widths must be 0 < smallest <= largest, got {widths!r}")
    rng = np.random.default_rng(123)
    return np.array(
        [
            facing_rectangle(
                np.arccos(rng.uniform(-0.15, 1.0)),
                rng.uniform(0.0, 2.0 * np.pi),
                np.exp(rng.uniform(np.log(smallest), np.log(largest))),
            )
            for _ in range(count)
        ]
    )


def lobe_over_lights(mu_o: float, alpha, lights, nodes: int = CHOICE_NODES) -> np.ndarray:
    """(A, L) ∫_P D(h) G2 / (4 μo) dω, the GGX lobe without Fresnel (height-correlated G2), over each rectangle of
    ``lights`` (L, 4, 3) seen from the origin with normal z and the view (√(1 − μo²), 0, μo), for each of ``alpha``
    (A,): :func:`light_nodes`; 0 below the horizon."""
    alpha = np.atleast_1d(as_float_array("alpha", alpha))
    omega, solid = light_nodes(lights, nodes)
    sine = np.sqrt(max(1.0 - mu_o * mu_o, 0.0))
    lobe = target_lobe(omega[None], mu_o, alpha[:, None, None], 1.0, sine=sine)
    return np.einsum("alq,lq->al", lobe, solid)


def light_nodes(lights, nodes: int = CHOICE_NODES) -> tuple[np.ndarray, np.ndarray]:
    """(directions (L, Q, 3), solid angles (L, Q)) of tensor Gauss-Legendre with ``nodes`` per edge over each rectangle
    of ``lights`` (L, 4, 3) seen from the origin: dω = (n_P · −ω) dA / d², 0 where the light faces away."""
    lights = as_float_array("lights", lights)
    if lights.ndim != 3 or lights.shape[1:] != (4, 3):
        raise ParameterError(f"lights must be (L, 4, 3) corners, got shape {lights.shape}")
    x, w = np.polynomial.legendre.leggauss(check_positive_int("nodes", nodes))
    s = 0.5 * (x + 1.0)
    u, v = (grid.reshape(-1) for grid in np.meshgrid(s, s, indexing="ij"))
    weights = (np.outer(w, w) / 4.0).reshape(-1)
    edge_u, edge_v = lights[:, 1] - lights[:, 0], lights[:, 3] - lights[:, 0]
    normal = np.cross(edge_u, edge_v)
    area = np.linalg.norm(normal, axis=-1)
    points = lights[:, None, 0] + u[:, None] * edge_u[:, None] + v[:, None] * edge_v[:, None]  # (L, Q, 3)
    distance = np.linalg.norm(points, axis=-1)
    omega = points / distance[..., None]
    facing = np.maximum(-np.einsum("lj,lqj->lq", normal / area[:, None], omega), 0.0)
    return omega, facing / distance**2 * area[:, None] * weights


def free_texels(
    first: np.ndarray,
    second: np.ndarray,
    grid: LutGrid,
    lights,
    nodes: int = CHOICE_NODES,
    progress: Callable[[int, int], None] | None = None,
    workers: int | None = None,
) -> np.ndarray:
    """(size, size) bool: where the stored table ``second`` holds the lobe over ``lights`` better than ``first``
    (module docstring's score; ties keep ``first``), both (size, size, 4) on the LTC ``grid``; ``progress`` (rows
    done, rows); the rows shared among ``workers`` threads (default: the machine's cores; the same choice)."""
    grid = checked_ltc_grid(grid)
    tables = [as_float_array("first", first), as_float_array("second", second)]
    if any(table.shape != (grid.height, grid.width, 4) for table in tables):
        raise ParameterError(f"both tables must be ({grid.height}, {grid.width}, 4)")
    lights = as_float_array("lights", lights)
    mu_rows, alphas = fit_points(grid)
    albedo = fit_albedo(grid)
    normal, origin = np.array([0.0, 0.0, 1.0]), np.zeros(3)
    chosen = np.zeros((grid.height, grid.width), dtype=bool)

    def choose(row: int) -> np.ndarray:
        mu_o = mu_rows[row]
        view = np.array([np.sqrt(1.0 - mu_o * mu_o), 0.0, mu_o])
        lobe = lobe_over_lights(mu_o, alphas, lights, nodes)  # (columns, lights)

        def score(table):
            integral = rect_light_integral(table[row][:, None], normal, view, origin, lights[None])
            held = integral * albedo[row][:, None]
            return np.sum(np.abs(np.log((held + _FLOOR) / (lobe + _FLOOR))), axis=1)

        return score(tables[1]) < score(tables[0])

    for row, preferred in enumerate(threaded_map(choose, range(grid.height), workers)):
        chosen[row] = preferred
        if progress is not None:
            progress(row + 1, grid.height)
    return chosen


def per_texel_fit(
    mean: LtcFit,
    free: LtcFit,
    lights=None,
    progress: Callable[[int, int], None] | None = None,
    preferred: np.ndarray | None = None,
    workers: int | None = None,
) -> LtcFit:
    """Per texel ``mean`` (the mean-axis L2 fit) or ``free`` (the free chi-square fit) of the same grid, whichever
    :func:`free_texels` prefers over ``lights`` (default :func:`training_lights`), at roughness at least
    :data:`CHOICE_ROUGHNESS_MIN`; ``progress`` as :func:`free_texels`'. ``preferred``: that preference where it is
    already at hand (:func:`free_texels` of the two fits over the training lights), not computed again; ``workers``
    as :func:`free_texels`'."""
    if not (isinstance(mean, LtcFit) and isinstance(free, LtcFit)) or mean.grid != free.grid:
        raise ParameterError("mean and free must be LtcFit of the same grid")
    if preferred is None:
        lights = training_lights() if lights is None else lights
        preferred = free_texels(mean.inverse, free.inverse, mean.grid, lights, progress=progress, workers=workers)
    elif np.shape(preferred) != (mean.grid.height, mean.grid.width):
        raise ParameterError(f"preferred must be ({mean.grid.height}, {mean.grid.width}), got {np.shape(preferred)}")
    chosen = np.asarray(preferred, dtype=bool) & (mean.grid.roughness >= CHOICE_ROUGHNESS_MIN)
    pick = chosen[..., None]
    return LtcFit(
        mean.grid,
        np.where(pick, free.parameters, mean.parameters),
        np.where(pick, free.inverse, mean.inverse),
        np.where(chosen, free.error, mean.error),
        "per-texel",
    )


def fit_area_ltc(
    grid: LutGrid | None = None, progress: Callable[[int, int], None] | None = None, workers: int | None = None
) -> LtcFit:
    """The shipped LTC table (module docstring): the mean-axis L2 and free chi-square fits of ``grid`` (default
    64 × 64; :func:`preintegrate.ltc.fit_ltc`, ``workers`` threads, the same bits for any number), then
    :func:`per_texel_fit`; ``progress`` (done, total) over both fits' rows and the choice's."""
    grid = ltc_grid() if grid is None else checked_ltc_grid(grid)
    steps = grid.height + 1  # a fit's progress counts its rows and its lobe error
    total = 2 * steps + grid.height

    def stage(offset: int):
        return None if progress is None else lambda done, _total: progress(offset + done, total)

    mean = fit_ltc(grid, stage(0), workers)
    free = fit_ltc(grid, stage(steps), workers, axis="free", weighting="chi-square")
    return per_texel_fit(mean, free, progress=stage(2 * steps), workers=workers)
