"""Multiple scattering on a GGX conductor microsurface by random walk (Heitz, Hanika, d'Eon, Dachsbacher
2016, "Multiple-Scattering Microfacet BSDFs with the Smith Model", Section 4 and its supplemental code):
a stochastic reference for multiple-scattering compensation, typed independently of the library.

Smith's microsurface with uniform heights in [−1, 1] (C1(h) = (h + 1)/2; the result does not depend on
the height distribution). A path enters from above going down; at each step it draws the height of its
next intersection from the Smith shadowing of its direction (or escapes, with probability G1(ω, h) =
C1(h)^Λ(ω) going up), draws a visible normal (Dupuy and Benyoub 2023, spherical caps: valid for every
direction, below the horizon too), multiplies its weight by the exact Fresnel reflectance at that
normal and reflects. The mean weight on escape is the albedo; paths of one bounce alone give the
single-scattering albedo of the height-correlated Smith BRDF.
"""

import numpy as np

from .fresnel import fresnel_complex


def _lambda(direction, alpha):
    """Smith Λ of GGX for a direction of travel: positive going up, ≤ −1 going down (Heitz 2016, Eq. 14
    and the supplemental code's signed form)."""
    z = np.clip(direction[:, 2], -1.0, 1.0)
    sin_theta = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    with np.errstate(divide="ignore", invalid="ignore"):
        a = z / (alpha * sin_theta)
        value = 0.5 * (-1.0 + np.sign(a) * np.sqrt(1.0 + 1.0 / (a * a)))
    return np.where(z > 0.9999, 0.0, np.where(z < -0.9999, -1.0, value))


def _c1(height):
    return np.clip(0.5 * (height + 1.0), 0.0, 1.0)


def _inverse_c1(u):
    return np.clip(2.0 * u - 1.0, -1.0, 1.0)


def _next_height(direction, height, u, alpha):
    """Height of the next intersection, +inf where the path escapes."""
    z = direction[:, 2]
    lam = _lambda(direction, alpha)
    c1 = _c1(height)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        escape_probability = np.where(z > 0.0, c1**lam, 0.0)
        travelled = _inverse_c1(c1 / (1.0 - u) ** (1.0 / lam))
    result = np.where(u > 1.0 - escape_probability, np.inf, travelled)
    result = np.where(z < -0.9999, _inverse_c1(u * c1), result)
    result = np.where(np.abs(z) < 1e-4, height, result)
    return np.where(z > 0.9999, np.inf, result)


def visible_normal(towards, alpha, u1, u2):
    """A normal drawn from D_ω(m) ∝ max(0, ω·m) D(m) for ω = ``towards`` (pointing away from the surface
    side it sees), by the spherical-cap construction in the stretched configuration."""
    stretched = towards * np.array([alpha, alpha, 1.0])
    stretched /= np.linalg.norm(stretched, axis=1, keepdims=True)
    phi = 2.0 * np.pi * u1
    z = (1.0 - u2) * (1.0 + stretched[:, 2]) - stretched[:, 2]
    sin_theta = np.sqrt(np.clip(1.0 - z * z, 0.0, 1.0))
    cap = np.stack([sin_theta * np.cos(phi), sin_theta * np.sin(phi), z], axis=1)
    half = cap + stretched
    normal = half * np.array([alpha, alpha, 1.0])
    return normal / np.linalg.norm(normal, axis=1, keepdims=True)


def random_walk_albedo(mu_o, alpha, eta, kappa, paths=200_000, seed=0, max_bounces=200):
    """(total, single, standard_error_total, standard_error_single), each (C,), for C colour channels
    (``eta``, ``kappa`` of shape (C,)) of a GGX conductor seen at cos θ = ``mu_o``."""
    rng = np.random.default_rng(seed)
    eta, kappa = np.atleast_1d(eta).astype(float), np.atleast_1d(kappa).astype(float)
    sin_o = np.sqrt(1.0 - mu_o * mu_o)
    direction = np.tile([-sin_o, 0.0, -mu_o], (paths, 1))
    height = np.full(paths, 1.0 + _inverse_c1(0.999))
    weight = np.ones((paths, eta.size))
    escaped = np.zeros((paths, eta.size))
    single = np.zeros((paths, eta.size))
    alive = np.arange(paths)
    for bounce in range(max_bounces + 1):
        height[alive] = _next_height(direction[alive], height[alive], rng.random(alive.size), alpha)
        leaving = np.isinf(height[alive])
        escaped[alive[leaving]] = weight[alive[leaving]]
        if bounce == 1:
            single[alive[leaving]] = weight[alive[leaving]]
        alive = alive[~leaving]
        if alive.size == 0 or bounce == max_bounces:
            break
        towards = -direction[alive]
        normal = visible_normal(towards, alpha, rng.random(alive.size), rng.random(alive.size))
        cosine = np.clip(np.sum(towards * normal, axis=1), 0.0, 1.0)
        weight[alive] *= fresnel_complex(cosine[:, None], eta, kappa)
        direction[alive] = -towards + 2.0 * cosine[:, None] * normal
    scale = np.sqrt(paths - 1.0)
    return escaped.mean(axis=0), single.mean(axis=0), escaped.std(axis=0) / scale, single.std(axis=0) / scale
