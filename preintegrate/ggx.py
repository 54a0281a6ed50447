"""The GGX (Trowbridge–Reitz) microfacet distribution with height-correlated Smith masking-shadowing.

Public objects: ``ndf``, ``smith_lambda``, ``g1``, ``g1_over_mu``, ``g2_denominator``, ``g2_height_correlated``, ``g2_separable``,
``VISIBILITIES``, ``Visibility``, ``visibility_g2``,
``ndf_inverse_cdf``, ``sample_vndf``, ``view_vector``, ``roughness_to_alpha``.

Directions are unit vectors in the local frame (normal = +z), arrays with a trailing axis of 3; μ is
the cosine to the normal. α is the distribution's width; LUTs index perceptual roughness r with
α = r² (Burley 2012, Karis 2013).

References
----------
:cite:`Walter2007` B. Walter et al., "Microfacet Models for Refraction through Rough Surfaces",
    EGSR 2007, eq. 33 (D) and 34 (G1 via Λ).
:cite:`Heitz2014` E. Heitz, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
    JCGT 3(2), 2014, eq. 72 (Λ of GGX) and eq. 99 (height-correlated G2 = 1 / (1 + Λ(ωo) + Λ(ωi))).
:cite:`Heitz2018` E. Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), 2018, listing 1.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from basis.validation import choose

__all__ = [
    "g1",
    "g1_over_mu",
    "g2_denominator",
    "g2_height_correlated",
    "g2_separable",
    "VISIBILITIES",
    "Visibility",
    "visibility_g2",
    "ndf",
    "ndf_inverse_cdf",
    "roughness_to_alpha",
    "sample_vndf",
    "smith_lambda",
    "view_vector",
]


def roughness_to_alpha(roughness):
    """α = r²: perceptual roughness (the LUT's row axis) to the GGX width."""
    return np.asarray(roughness, dtype=np.float64) ** 2


def ndf(mu_h, alpha):
    """D(h) = α² / (π (μ_h² (α² − 1) + 1)²) (Walter 2007, eq. 33); 0 below the horizon."""
    mu_h = np.asarray(mu_h, dtype=np.float64)
    alpha2 = np.asarray(alpha, dtype=np.float64) ** 2
    denominator = mu_h * mu_h * (alpha2 - 1.0) + 1.0
    return np.where(mu_h > 0.0, alpha2 / (np.pi * denominator * denominator), 0.0)


def _slope_root(mu, alpha):
    """√(μ² + α²(1 − μ²)), the quantity through which Λ stays finite at the horizon."""
    return np.sqrt(mu * mu + alpha * alpha * (1.0 - mu * mu))


def smith_lambda(mu, alpha):
    """Λ(μ) = (−1 + √(1 + α² tan²θ)) / 2 (Heitz 2014, eq. 72), written as (√(μ² + α²(1 − μ²)) − μ) / (2μ)."""
    mu = np.asarray(mu, dtype=np.float64)
    alpha = np.asarray(alpha, dtype=np.float64)
    with np.errstate(divide="ignore"):
        return (_slope_root(mu, alpha) - mu) / (2.0 * mu)


def g1(mu, alpha):
    """Smith masking G1 = 1 / (1 + Λ) = 2μ / (μ + √(μ² + α²(1 − μ²))); 0 at and below the horizon."""
    mu = np.asarray(mu, dtype=np.float64)
    mu_pos, denominator = _g1_denominator(mu, alpha)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(mu > 0.0, 2.0 * mu_pos / np.where(denominator > 0, denominator, 1.0), 0.0)


def g1_over_mu(mu, alpha):
    """G1(μ)/μ = 2 / (μ + √(μ² + α²(1 − μ²))) for μ ≥ 0 (μ < 0 is read as 0): finite at the horizon, 2/α there,
    where the separable BRDF's G1(μo)/μo is needed; 0 for μ = α = 0 (the mirror at grazing, a zero-measure case)."""
    _, denominator = _g1_denominator(mu, alpha)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.where(denominator > 0, 2.0 / np.where(denominator > 0, denominator, 1.0), 0.0)


def _g1_denominator(mu, alpha):
    """(max(μ, 0), max(μ, 0) + √(μ² + α²(1 − μ²))): G1 = 2μ / the second."""
    mu_pos = np.maximum(np.asarray(mu, dtype=np.float64), 0.0)
    return mu_pos, mu_pos + _slope_root(mu_pos, np.asarray(alpha, dtype=np.float64))


def g2_denominator(mu_o, mu_i, alpha):
    """μi √(μo² + α²(1 − μo²)) + μo √(μi² + α²(1 − μi²)), so that the height-correlated G2 is
    2 μo μi / this (Heitz 2014, eq. 99); unchecked, μo, μi ≥ 0."""
    return mu_i * _slope_root(mu_o, alpha) + mu_o * _slope_root(mu_i, alpha)


def g2_height_correlated(mu_o, mu_i, alpha):
    """Height-correlated G2 = 1 / (1 + Λ(μo) + Λ(μi)) (Heitz 2014, eq. 99).

    Written as 2 μo μi / (μi √(μo² + α²(1 − μo²)) + μo √(μi² + α²(1 − μi²))), finite at grazing;
    0 when either direction is at or below the horizon.
    """
    mu_o = np.asarray(mu_o, dtype=np.float64)
    mu_i = np.asarray(mu_i, dtype=np.float64)
    alpha = np.asarray(alpha, dtype=np.float64)
    o = np.maximum(mu_o, 0.0)
    i = np.maximum(mu_i, 0.0)
    denominator = g2_denominator(o, i, alpha)
    with np.errstate(invalid="ignore", divide="ignore"):
        value = 2.0 * o * i / np.where(denominator > 0.0, denominator, 1.0)
    return np.where((mu_o > 0.0) & (mu_i > 0.0), value, 0.0)


def g2_separable(mu_o, mu_i, alpha):
    """Separable G2 = G1(μo) G1(μi) (Walter 2007, eq. 23; Heitz 2014, eq. 98), the form of several offline
    renderers; never above the height-correlated one, since (1 + Λo)(1 + Λi) ≥ 1 + Λo + Λi."""
    return g1(mu_o, alpha) * g1(mu_i, alpha)


@dataclasses.dataclass(frozen=True)
class Visibility:
    """A Smith masking-shadowing form of the BRDF: its G2, the words a table's header names it by, and who uses it."""

    name: str
    g2: Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]
    header: str
    description: str


#: Registry: the masking-shadowing forms a table can be built for (``fresnel-lut build --visibility``, a scene's
#: ``visibility``); an engine's table must match its own BRDF (the two differ by up to 0.15 at r = 0.8 near grazing).
VISIBILITIES = {
    visibility.name: visibility
    for visibility in (
        Visibility(
            "height-correlated",
            g2_height_correlated,
            "height-correlated Smith G2",
            "height-correlated Smith G2 (Heitz 2014 eq. 99; most real-time engines)",
        ),
        Visibility(
            "separable",
            g2_separable,
            "separable Smith G2 = G1(omega_o) * G1(omega_i)",
            "separable G1(o) G1(i) (Heitz 2014 eq. 98; several offline renderers)",
        ),
    )
}


def visibility_g2(name: str) -> Callable[[np.ndarray, np.ndarray, np.ndarray], np.ndarray]:
    """G2(μo, μi, α) of a form of :data:`VISIBILITIES`; the error lists the forms."""
    return choose("visibility", name, VISIBILITIES).g2


def view_vector(mu_o):
    """ω_o = (sin θo, 0, μo) (..., 3): the view direction in the plane xz of the local frame."""
    mu_o = np.asarray(mu_o, dtype=np.float64)
    return np.stack([np.sqrt(np.maximum(1.0 - mu_o * mu_o, 0.0)), np.zeros_like(mu_o), mu_o], axis=-1)


def ndf_inverse_cdf(alpha, u):
    """(sin θh, cos θh) of the half vector drawn from D(h) μh by the uniform number u ∈ [0, 1):
    tan²θh = α² u / (1 − u) (Walter 2007, eq. 35; Karis 2013's ``ImportanceSampleGGX``)."""
    tan2 = alpha * alpha * (u / (1.0 - u))
    mu_h = 1.0 / np.sqrt(1.0 + tan2)
    return np.sqrt(tan2) * mu_h, mu_h


def sample_vndf(omega_o, alpha, u1, u2):
    """Sample a microfacet normal from the distribution of visible normals D_ωo(h) (Heitz 2018, listing 1).

    Parameters
    ----------
    omega_o : numpy.ndarray
        (..., 3) view directions with ω_o,z > 0.
    alpha : array_like
        Isotropic GGX width, broadcast against the sample shape.
    u1, u2 : numpy.ndarray
        Uniform numbers in [0, 1), broadcast against each other and ``omega_o[..., 0]``.

    Returns
    -------
    numpy.ndarray
        (..., 3) unit half vectors h with h·ω_o ≥ 0 and h_z ≥ 0.
    """
    omega_o = np.asarray(omega_o, dtype=np.float64)
    alpha = np.asarray(alpha, dtype=np.float64)
    # Section 1: stretch the view direction to the hemisphere configuration.
    vh = np.stack(np.broadcast_arrays(alpha * omega_o[..., 0], alpha * omega_o[..., 1], omega_o[..., 2]), axis=-1)
    vh /= np.linalg.norm(vh, axis=-1, keepdims=True)
    # Section 2: orthonormal basis (T1 horizontal, T2 = vh × T1).
    length2 = vh[..., 0] ** 2 + vh[..., 1] ** 2
    safe = np.where(length2 > 0.0, length2, 1.0)
    t1 = np.where(
        (length2 > 0.0)[..., None],
        np.stack([-vh[..., 1], vh[..., 0], np.zeros_like(length2)], axis=-1) / np.sqrt(safe)[..., None],
        np.array([1.0, 0.0, 0.0]),
    )
    t2 = np.cross(vh, t1)
    # Section 3: uniform point on the disk, warped to the projected visible half-disk.
    radius = np.sqrt(u1)
    phi = 2.0 * np.pi * u2
    p1 = radius * np.cos(phi)
    p2 = radius * np.sin(phi)
    s = 0.5 * (1.0 + vh[..., 2])
    p2 = (1.0 - s) * np.sqrt(np.maximum(1.0 - p1 * p1, 0.0)) + s * p2
    # Section 4: reproject onto the hemisphere, then unstretch (section 5).
    lift = np.sqrt(np.maximum(1.0 - p1 * p1 - p2 * p2, 0.0))
    nh = p1[..., None] * t1 + p2[..., None] * t2 + lift[..., None] * vh
    h = np.stack(np.broadcast_arrays(alpha * nh[..., 0], alpha * nh[..., 1], np.maximum(nh[..., 2], 0.0)), axis=-1)
    return h / np.linalg.norm(h, axis=-1, keepdims=True)
