"""Directional albedo of pbrt's FresnelBlend BRDF (Ashikhmin and Shirley 2000) with a GGX distribution.

Public objects: ``fresnel_blend_brdf``, ``fresnel_blend_diffuse_albedo``, ``fresnel_blend_specular_albedo``,
``fresnel_blend_albedo``.

pbrt 3rd ed., section 8.5:

    f = 28 Rd / (23 π) (1 − Rs)(1 − (1 − μi/2)^5)(1 − (1 − μo/2)^5)                     (diffuse)
      + D(h) F(ωi·h) / (4 |ωi·h| max(μi, μo)),  F = Rs + (1 − Rs)(1 − ωi·h)^5             (specular)

Diffuse albedo in closed form: ∫ μ (1 − (1 − μ/2)^5) dμ over [0, 1] is 23/56, so
E_d(μo) = Rd (1 − Rs)(1 − (1 − μo/2)^5) — 28/23 is the factor that makes it so.

Specular albedo: with dωi = 4 (ωo·h) dωh and ωi·h = ωo·h,
E_s(μo) = ∫ D(h) F(ωo·h) μi / max(μi, μo) dωh over the half vectors whose reflection is above the
horizon, which is linear in F: E_s = Rs A(μo, α) + B(μo, α) with the Schlick terms, as for the GGX
split sum (but with pbrt's 1/max(μi, μo) in place of Smith masking). It is integrated in GGX's
inverse-CDF variable u (tan²θh = α² u / (1 − u), D μh dωh = du dφ / 2π) by Gauss–Legendre in u and
the midpoint rule in φ.

References
----------
:cite:`Ashikhmin2000` M. Ashikhmin, P. Shirley, "An Anisotropic Phong BRDF Model", JGT 5(2), 2000.
:cite:`Pharr2016` pbrt 3rd ed., section 8.5, ``FresnelBlend::f``.
"""

from __future__ import annotations

import numpy as np

from basis.models.formulas import schlick_curve, schlick_weight
from basis.validation import check_positive_int, check_range

from .channels import schlick_channels
from .ggx import ndf, ndf_inverse_cdf

__all__ = [
    "fresnel_blend_albedo",
    "fresnel_blend_brdf",
    "fresnel_blend_diffuse_albedo",
    "fresnel_blend_specular_albedo",
]


def _diffuse_factor(mu):
    """1 − (1 − μ/2)^5 of Ashikhmin and Shirley's diffuse term (pbrt's ``pow5(1 − .5 AbsCosTheta)``)."""
    return 1.0 - schlick_weight(0.5 * mu)


def fresnel_blend_brdf(mu_i, mu_o, mu_h, i_dot_h, alpha, rd, rs) -> np.ndarray:
    """pbrt's ``FresnelBlend::f`` with a GGX D, for given cosines (vectorised; no validation)."""
    diffuse = 28.0 / (23.0 * np.pi) * rd * (1.0 - rs) * _diffuse_factor(mu_i) * _diffuse_factor(mu_o)
    fresnel = schlick_curve(i_dot_h, rs)
    specular = ndf(mu_h, alpha) * fresnel / (4.0 * np.abs(i_dot_h) * np.maximum(mu_i, mu_o))
    return diffuse + specular


def fresnel_blend_diffuse_albedo(mu_o, rd, rs) -> np.ndarray:
    """E_d(μo) = Rd (1 − Rs)(1 − (1 − μo/2)^5), exact (module docstring)."""
    mu_o = check_range("mu_o", mu_o, 0.0, 1.0)
    rd = check_range("rd", rd, 0.0, 1.0)
    rs = check_range("rs", rs, 0.0, 1.0)
    return rd * (1.0 - rs) * _diffuse_factor(mu_o)


#: Nodes (texels × u × φ) evaluated at once: about a dozen float64 temporaries of this size, ~100 MB.
_MAX_NODES = 1 << 20


def _specular_terms(mu_o: np.ndarray, alpha: np.ndarray, nodes_u: int, nodes_phi: int) -> np.ndarray:
    """(…, 2): A, B with E_s = Rs A + B, by the product rule of the module docstring, in chunks of texels."""
    u, w_u = np.polynomial.legendre.leggauss(nodes_u)
    u, w_u = 0.5 * (u + 1.0), 0.5 * w_u
    cos_phi = np.cos((np.arange(nodes_phi) + 0.5) * (2.0 * np.pi / nodes_phi))
    shape = np.broadcast_shapes(mu_o.shape, alpha.shape)
    mu_o, alpha = np.broadcast_to(mu_o, shape).ravel(), np.broadcast_to(alpha, shape).ravel()
    result = np.empty((mu_o.size, 2))
    chunk = max(1, _MAX_NODES // (nodes_u * nodes_phi))
    for start in range(0, mu_o.size, chunk):
        texels = slice(start, start + chunk)
        cos_o, width = mu_o[texels, None, None], alpha[texels, None, None]
        sin_h, mu_h = ndf_inverse_cdf(width, u[:, None])
        sin_o = np.sqrt(np.maximum(0.0, 1.0 - cos_o * cos_o))
        o_dot_h = sin_o * sin_h * cos_phi + cos_o * mu_h
        mu_i = 2.0 * o_dot_h * mu_h - cos_o
        valid = (o_dot_h > 0.0) & (mu_i > 0.0)
        ratio = np.where(valid, mu_i / np.maximum(np.maximum(mu_i, cos_o), np.finfo(float).tiny) / mu_h, 0.0)
        # D dωh = du dφ / (2π μh); the integrand D F μi / max(μi, μo) dωh
        weight = ratio * (w_u[:, None] / nodes_phi)
        result[texels] = np.einsum("tij,tijk->tk", weight, schlick_channels().functions(np.clip(o_dot_h, 0.0, 1.0)))
    return result.reshape(shape + (2,))


def fresnel_blend_specular_albedo(mu_o, alpha, rs, nodes_u: int = 256, nodes_phi: int = 256) -> np.ndarray:
    """E_s(μo, α) of the specular lobe (module docstring); μo, α, Rs broadcast.

    The reflection's horizon cuts the (u, φ) domain along a curve, so the product rule converges
    algebraically there; 256 × 256 nodes give about 1e-5 (``tests/preintegrate/test_fresnel_blend.py`` bounds it
    against Monte Carlo). As α → 0 it tends to F(μo) (the mirror).
    """
    mu_o = check_range("mu_o", mu_o, 0.0, 1.0)
    alpha = check_range("alpha", alpha, 1e-6, 1.0)
    rs = check_range("rs", rs, 0.0, 1.0)
    nodes_u = check_positive_int("nodes_u", nodes_u, low=2, high=1 << 14)
    nodes_phi = check_positive_int("nodes_phi", nodes_phi, low=2, high=1 << 14)
    terms = _specular_terms(mu_o, alpha, nodes_u, nodes_phi)
    return rs * terms[..., 0] + terms[..., 1]


def fresnel_blend_albedo(mu_o, alpha, rd, rs, nodes_u: int = 256, nodes_phi: int = 256) -> np.ndarray:
    """E(μo, α) = E_d + E_s of pbrt's FresnelBlend with a GGX distribution of width α."""
    return fresnel_blend_diffuse_albedo(mu_o, rd, rs) + fresnel_blend_specular_albedo(
        mu_o, alpha, rs, nodes_u, nodes_phi
    )
