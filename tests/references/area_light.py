"""Independent reference for a rectangular light: the exact GGX BRDF with an exact Fresnel curve integrated over
the light's area,

L_o = L ∫_P F(ω_o·h) ρ(ω_o, ω_i) μ_i dω_i,  ρ = D(h) G2(ω_o, ω_i) / (4 μo μi),  dω_i = (n_L · (−ω_i)) dA / d²,

by tensor Gauss-Legendre over the rectangle's two edge parameters (no LTC, no split sum, no half-vector change of
variables; D and G2 from tests/references/integration.py, re-typed from the definitions). Points below the shading
point's horizon contribute nothing (G2 = 0). Converges like any Gauss rule on a smooth integrand: ≲1e-6 relative
for the default 96² nodes when the BRDF lobe is wider than a few nodes over the light (α ≳ 0.04 at a 2 × 1 light two
units away); the report states its node count. Where the lobe is sharper than that or the horizon cuts the light,
:func:`rect_light_reference_adaptive` integrates the same integrand over the light's part above the horizon by
adaptive cubature on triangles; :func:`rect_light_monte_carlo` checks both by sampling visible normals.
"""

from __future__ import annotations

import numpy as np

from .integration import g2_reference, ggx_d, smith_lambda_tan
from .random_walk import visible_normal


def _lobe_per_area(normal, view, position, points, light_normal, alpha) -> tuple[np.ndarray, np.ndarray]:
    """(ρ μi (n_L · −ω_i) / d², V·H) (…, Q) at the light's ``points`` (…, Q, 3) seen from ``position`` (…, 3): the
    integrand per unit of the light's area without Fresnel, 0 below the horizon and behind the light."""
    to_light = points - position[..., None, :]  # (…, Q, 3)
    distance = np.linalg.norm(to_light, axis=-1)
    omega_i = to_light / distance[..., None]
    facing = np.sum(light_normal * -omega_i, axis=-1)  # the light emits along its normal (c1 - c0) x (c3 - c0)
    solid = np.where(facing > 0.0, facing, 0.0) / distance**2
    mu_o = np.sum(normal * view, axis=-1)[..., None]
    mu_i = np.sum(normal[..., None, :] * omega_i, axis=-1)
    half = omega_i + view[..., None, :]
    half /= np.linalg.norm(half, axis=-1, keepdims=True)
    mu_h = np.sum(normal[..., None, :] * half, axis=-1)
    v_dot_h = np.clip(np.sum(view[..., None, :] * half, axis=-1), 0.0, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        value = ggx_d(mu_h, alpha) * g2_reference(mu_o, mu_i, alpha) / (4.0 * mu_o)  # ρ μi
    return np.where((mu_i > 0.0) & (mu_o > 0.0), value, 0.0) * solid, v_dot_h


def _edges(corners) -> tuple[np.ndarray, np.ndarray, np.ndarray, float]:
    """(c1 − c0, c3 − c0, the light's unit normal, its area) of the parallelogram ``corners`` (4, 3)."""
    edge_u, edge_v = corners[1] - corners[0], corners[3] - corners[0]
    light_normal = np.cross(edge_u, edge_v)
    area = float(np.linalg.norm(light_normal))
    return edge_u, edge_v, light_normal / area, area


def rect_light_reference(normal, view, position, corners, alpha, fresnel, nodes: int = 96) -> np.ndarray:
    """(…, C) L_o / L for unit ``normal`` and ``view`` (…, 3), ``position`` (…, 3), the parallelogram ``corners``
    (4, 3) (c0, c1, c2, c3 with c2 = c1 + c3 − c0), GGX ``alpha`` (scalar) and ``fresnel``: μ (…) → (…, C), the
    exact curve."""
    normal, view, position = (np.asarray(v, dtype=np.float64) for v in (normal, view, position))
    corners = np.asarray(corners, dtype=np.float64)
    x, w = np.polynomial.legendre.leggauss(nodes)
    s = 0.5 * (x + 1.0)
    u, v = np.meshgrid(s, s, indexing="ij")
    weights = (np.outer(w, w) / 4.0).reshape(-1)
    edge_u, edge_v, light_normal, area = _edges(corners)
    points = corners[0] + u.reshape(-1, 1) * edge_u + v.reshape(-1, 1) * edge_v  # (Q, 3)
    value, v_dot_h = _lobe_per_area(normal, view, position, points, light_normal, alpha)
    return np.einsum("...q,...qc->...c", value * area * weights, fresnel(v_dot_h))


#: The adaptive reference's rule on each triangle: Gauss-Legendre on the square collapsed onto it (Duffy), per side.
TRIANGLE_NODES = 6


def _above_horizon(normal, position, corners) -> np.ndarray:
    """(V, 2) the convex polygon, in the edge parameters (s, t) ∈ [0, 1]², of the part of the parallelogram
    ``corners`` above the horizon of ``position`` with ``normal`` (the unit square clipped by n · (p(s, t) − x) ≥ 0,
    which is affine in s and t); (0, 2) where none is."""
    edge_u, edge_v, _, _ = _edges(corners)
    base, along_u, along_v = normal @ (corners[0] - position), normal @ edge_u, normal @ edge_v
    square = [np.array(p, dtype=np.float64) for p in ((0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0))]
    kept = []
    for here, there in zip(square, square[1:] + square[:1]):
        a, b = (base + point[0] * along_u + point[1] * along_v for point in (here, there))
        if a >= 0.0:
            kept.append(here)
        if (a >= 0.0) != (b >= 0.0):
            kept.append(here + a / (a - b) * (there - here))
    return np.array(kept).reshape(-1, 2)


def _triangle_rule(triangles) -> tuple[np.ndarray, np.ndarray]:
    """(points (T, Q, 2), weights (T, Q)): :data:`TRIANGLE_NODES`² collapsed Gauss-Legendre nodes on each of the
    ``triangles`` (T, 3, 2) (A + a (B − A) + a b (C − B), Jacobian a |(B − A) × (C − B)|)."""
    x, w = np.polynomial.legendre.leggauss(TRIANGLE_NODES)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    a, b = (grid.reshape(-1) for grid in np.meshgrid(x, x, indexing="ij"))
    weight = (np.outer(w, w).reshape(-1) * a)[None, :]
    first, second, third = triangles[:, 0, None], triangles[:, 1, None], triangles[:, 2, None]
    points = first + a[None, :, None] * (second - first) + (a * b)[None, :, None] * (third - second)
    u, v = second[:, 0] - first[:, 0], third[:, 0] - second[:, 0]
    cross = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0])
    return points, weight * cross[:, None]


def _quarters(triangles) -> np.ndarray:
    """(T, 4, 3, 2) each of ``triangles`` (T, 3, 2) split at its edges' midpoints."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    ab, bc, ca = 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)
    return np.stack([np.stack(t, axis=1) for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))], axis=1)


def rect_light_reference_adaptive(
    normal, view, position, corners, alpha, fresnel, tolerance: float = 1e-7, max_triangles: int = 1 << 18
) -> np.ndarray:
    """(C,) :func:`rect_light_reference` for one shading point (``normal``, ``view``, ``position`` (3,)) to a
    relative ``tolerance``, where the tensor rule does not converge: a lobe far narrower than the light (α = 0.09 seen
    at grazing under a 10 × 5 light two units away: 96² nodes give 0.53 of the lobe, 384² 0.89, this 0.92) or the
    horizon's kink across it. The light's part above the horizon (a convex polygon in its edge parameters) in
    triangles, each by :data:`TRIANGLE_NODES`² collapsed Gauss nodes, its error the difference to its four quarters'
    sum; the triangles with the largest errors split in four until those left sum to ``tolerance`` × the total (every
    channel); RuntimeError past ``max_triangles``."""
    if not 0.0 < tolerance < 1.0:
        raise ValueError(f"tolerance must be in (0, 1), got {tolerance!r}")
    normal, view, position = (np.asarray(v, dtype=np.float64) for v in (normal, view, position))
    corners = np.asarray(corners, dtype=np.float64)
    edge_u, edge_v, light_normal, area = _edges(corners)
    polygon = _above_horizon(normal, position, corners)
    channels = np.shape(fresnel(np.ones(1)))[-1]
    if len(polygon) < 3:
        return np.zeros(channels)

    def integral(triangles):
        points, weights = _triangle_rule(triangles)
        located = corners[0] + points[..., :1] * edge_u + points[..., 1:] * edge_v
        value, v_dot_h = _lobe_per_area(normal, view, position, located, light_normal, alpha)
        return np.einsum("tq,tqc->tc", value * weights * area, fresnel(v_dot_h.reshape(-1)).reshape(*value.shape, -1))

    def leaves(triangles):
        """(the values (T, 4, C) of the quarters of each of ``triangles`` (T, 3, 2), those quarters (T, 4, 3, 2))."""
        quarters = _quarters(triangles)
        finer = integral(quarters.reshape(-1, 3, 2)).reshape(len(triangles), 4, channels)
        return finer, quarters

    triangles = np.stack([np.stack([polygon[0], polygon[k], polygon[k + 1]]) for k in range(1, len(polygon) - 1)])
    finer, quarters = leaves(triangles)
    errors = np.abs(finer.sum(axis=1) - integral(triangles))
    while True:
        values = finer.sum(axis=1)  # each leaf's value: its quarters' sum
        total = np.abs(values.sum(axis=0))
        relative = np.max(errors / np.where(total > 0.0, total, 1.0), axis=1)
        if relative.sum() <= tolerance:
            return values.sum(axis=0)
        if 4 * len(values) > max_triangles:
            raise RuntimeError(f"not within {tolerance:g} after {len(values)} triangles ({relative.sum():.2g})")
        # keep the smallest errors while they sum to half the tolerance; split the rest into their quarters
        order = np.argsort(relative)
        split = np.zeros(len(relative), dtype=bool)
        split[order[np.cumsum(relative[order]) > 0.5 * tolerance]] = True
        finer_split, quarters_split = leaves(quarters[split].reshape(-1, 3, 2))
        own = finer[split].reshape(-1, channels)  # the new leaves' own values
        errors = np.concatenate([errors[~split], np.abs(finer_split.sum(axis=1) - own)])
        finer = np.concatenate([finer[~split], finer_split])
        quarters = np.concatenate([quarters[~split], quarters_split])


def rect_light_monte_carlo(view, corners, alpha, fresnel, samples: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(mean, standard error) (C,) of :func:`rect_light_reference` seen from the origin with normal z by Monte Carlo:
    normals drawn from the view's visible normals (Heitz 2018; tests/references/random_walk.py's spherical caps), the
    view reflected about each, weight F(V·H) G2 / G1(μo) where that ray meets the parallelogram ``corners`` from its
    emitting side (height-correlated G2: G2 / G1 = (1 + Λo) / (1 + Λo + Λi)); no quadrature, no change of variables."""
    view, corners = np.asarray(view, dtype=np.float64), np.asarray(corners, dtype=np.float64)
    rng = np.random.default_rng(seed)
    half = visible_normal(np.broadcast_to(view, (samples, 3)), alpha, rng.random(samples), rng.random(samples))
    v_dot_h = np.sum(view * half, axis=1)
    omega_i = 2.0 * v_dot_h[:, None] * half - view
    edge_u, edge_v, light_normal, _ = _edges(corners)
    along = omega_i @ light_normal
    with np.errstate(divide="ignore", invalid="ignore"):
        distance = (corners[0] @ light_normal) / along
        hit = distance[:, None] * omega_i - corners[0]
    # the hit point's edge parameters through the dual basis of (edge_u, edge_v) in the light's plane
    gram = np.array([[edge_u @ edge_u, edge_u @ edge_v], [edge_u @ edge_v, edge_v @ edge_v]])
    s, t = np.linalg.solve(gram, np.stack([hit @ edge_u, hit @ edge_v])).reshape(2, -1)
    inside = (along < 0.0) & (distance > 0.0) & (s >= 0.0) & (s <= 1.0) & (t >= 0.0) & (t <= 1.0)
    inside &= omega_i[:, 2] > 0.0
    mu_o = view[2]
    lambda_o = smith_lambda_tan(mu_o, alpha)
    lambda_i = smith_lambda_tan(np.where(inside, omega_i[:, 2], 1.0), alpha)
    weight = np.where(inside, (1.0 + lambda_o) / (1.0 + lambda_o + lambda_i), 0.0)[:, None] * fresnel(
        np.clip(v_dot_h, 0.0, 1.0)
    )
    return weight.mean(axis=0), weight.std(axis=0) / np.sqrt(samples)
