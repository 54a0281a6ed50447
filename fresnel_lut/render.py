"""A small vectorised renderer: spheres under an environment, split sum against Monte Carlo.

Public objects: ``Environment``, ``STUDIO``, ``RenderMaterial``, ``DEFAULT_SCENES``, ``FIGURE2``, ``FIGURE2_ROUGHNESS``,
``render_split_sum``, ``render_point_light``, ``POINT_LIGHT_DIRECTION``, ``POINT_LIGHT_RADIANCE``, ``render_rect_light``,
``RECT_LIGHT``, ``RECT_LIGHT_RADIANCE``, ``rect_light_corners``, ``render_reference``, ``sphere_geometry``, ``tone_map``,
``to_srgb8``.

* **Environment**: a procedural studio made of spherical Gaussians (SGs) — a sky dome, a ground
  bounce, two soft boxes and a rim light — so that both the exact radiance L(ω) and Karis's prefiltered
  radiance have closed forms. Prefiltering uses the SG approximation of the GGX lobe around the mirror
  direction with n = v = r (Karis 2013; Wang et al. 2009: D(h) ≈ exp(2/α² (h·n − 1)) / (πα²), a lobe of
  sharpness 1/(2α²) around r), and the SG inner product in closed form.
* **Split sum**: pixel = prefiltered L(r, α) × F̄(μo, α), F̄ from the shipped LUTs by bilinear lookup
  (the default grid's coordinates, clamp to edge, as a GPU): Schlick's two channels with F0 = F(0°), or the basis'
  four with the material's coefficients.
* **Point light**: L ρ(ωo, ωl) μl with the GGX BRDF ρ = D G2 F / (4 μo μl), F(ωo·h) three ways: Schlick's,
  the basis' (the shaders' direct-light curves, :func:`handoff.shaders.direct_fresnel`, with the
  material's coefficients: one material, one curve for the environment and the lamp) and the exact curve
  (the reference of a punctual light needs no integral).
* **Rectangular light**: linearly transformed cosines (Heitz 2016; :mod:`preintegrate.ltc`) with Fresnel three ways:
  the exact curve through the include's factorisation (the LTC's own error), the basis (``fresnelBasisRectLight``)
  and Schlick's split sum; its
  reference (the exact BRDF and curve over the light's area) is ``tests/references/area_light.py``.
* **Reference**: Monte Carlo of ∫ F(ωo·h) ρ(ωo, ωi) L(ωi) μi dωi with VNDF sampling (Heitz 2018),
  weight F · G2/G1, the material's exact RGB Fresnel curve, seeded; its standard error is returned.

The camera is orthographic along −z; the sphere fills the image; pixels outside it are black.

References
----------
:cite:`Karis2013` "Real Shading in Unreal Engine 4", split-sum approximation.
:cite:`Wang2009` J. Wang et al., "All-frequency rendering of dynamic, spatially-varying reflectance",
    SIGGRAPH Asia 2009 (spherical-Gaussian GGX lobe and warp).
:cite:`Heitz2018` JCGT 7(4), VNDF sampling.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import math
import time
from collections.abc import Callable

import numpy as np

from basis.eigenbasis import default_basis
from basis.materials import material_from_mapping
from basis.parallel import one_blas_thread, worker_count
from basis.validation import check_choice, check_positive_int, check_range
from handoff.shaders import direct_fresnel, rect_light_specular
from preintegrate.estimators import contributions
from preintegrate.ggx import VISIBILITIES, ndf, roughness_to_alpha
from preintegrate.ltc import ltc_grid, rect_light_fresnel, rect_light_half_cosine, smoothed_fresnel
from preintegrate.lut import lut_lookup, texel_centres
from preintegrate.multiple_scattering import compensate_lookup
from preintegrate.quadrature import directional_albedo

__all__ = [
    "DEFAULT_SCENES",
    "FIGURE2",
    "FIGURE2_ROUGHNESS",
    "POINT_LIGHT_DIRECTION",
    "POINT_LIGHT_RADIANCE",
    "RECT_LIGHT_RADIANCE",
    "STUDIO",
    "Environment",
    "RenderMaterial",
    "RECT_LIGHT",
    "rect_light_corners",
    "render_point_light",
    "render_rect_light",
    "render_reference",
    "render_split_sum",
    "sphere_geometry",
    "to_srgb8",
    "tone_map",
]


@dataclasses.dataclass(frozen=True)
class Environment:
    """L(ω) = Σ_i c_i exp(λ_i (ω·p_i − 1)): axes p_i (unit), sharpness λ_i ≥ 0, RGB amplitudes c_i."""

    axes: np.ndarray  # (N, 3)
    sharpness: np.ndarray  # (N,)
    amplitudes: np.ndarray  # (N, 3)

    def radiance(self, direction: np.ndarray) -> np.ndarray:
        """(..., 3) radiance for unit directions (..., 3), one lobe at a time (no (..., N) array)."""
        total = np.zeros(direction.shape)
        for axis, sharpness, amplitude in zip(self.axes, self.sharpness, self.amplitudes):
            cosine = direction[..., 0] * axis[0] + direction[..., 1] * axis[1] + direction[..., 2] * axis[2]
            total += np.exp(sharpness * (cosine - 1.0))[..., None] * amplitude
        return total

    def prefiltered(self, direction: np.ndarray, alpha) -> np.ndarray:
        """Karis's prefiltered radiance: L convolved with a normalised SG lobe of sharpness 1/(2α²) around
        ``direction`` (…, 3); α broadcast against its leading axes."""
        lobe = 0.5 / np.maximum(np.asarray(alpha, dtype=np.float64), 1e-4) ** 2
        lobe = np.asarray(lobe)[..., None]  # (..., 1) against the N SGs
        vector = self.sharpness[:, None] * self.axes  # (N, 3)
        total = vector[None, ...] + lobe[..., None] * direction[..., None, :]  # (..., N, 3)
        length = np.linalg.norm(total, axis=-1)  # (..., N)
        # ∫ e^{λ1(d·p1 − 1) + λ2(d·p2 − 1)} dd = 2π e^{m − λ1 − λ2} (1 − e^{−2m}) / m, m = |λ1 p1 + λ2 p2|;
        # the lobe is divided by its own integral 2π (1 − e^{−2λ2}) / λ2
        inner = np.exp(length - self.sharpness - lobe) * -np.expm1(-2.0 * length) / np.maximum(length, 1e-300)
        norm = -np.expm1(-2.0 * lobe) / lobe
        return (inner / norm) @ self.amplitudes


def _unit(vector) -> np.ndarray:
    vector = np.asarray(vector, dtype=np.float64)
    return vector / np.linalg.norm(vector, axis=-1, keepdims=True)


#: The default studio: sky from above, warm ground bounce, a large key soft box, a fill and a rim light.
STUDIO = Environment(
    axes=_unit([[0.0, 1.0, 0.2], [0.0, -1.0, 0.0], [-0.6, 0.55, 0.6], [0.8, 0.2, 0.55], [0.2, 0.3, -0.9]]),
    sharpness=np.array([1.5, 2.0, 40.0, 25.0, 60.0]),
    amplitudes=np.array([[0.35, 0.45, 0.65], [0.25, 0.2, 0.15], [6.0, 5.8, 5.4], [1.6, 1.8, 2.2], [5.0, 5.0, 5.0]]),
)


@dataclasses.dataclass(frozen=True)
class RenderMaterial:
    """A material to render: its exact RGB curve, Schlick's F0 and its basis coefficients (3, K)."""

    name: str
    curve: Callable[[np.ndarray], np.ndarray]  # μ (...) → (..., 3), exact
    coefficients: np.ndarray
    roughness: tuple[float, ...]


def _render_material(name: str, mapping: dict, space: str, roughness: tuple[float, ...]) -> RenderMaterial:
    """A material of :mod:`basis.materials` to render: its exact curve (a preset's tabulated: see :func:`_tabulated`)
    and its coefficients."""
    material = material_from_mapping(mapping, space)
    curve = _tabulated(material.curve) if material.kind == "preset" else material.curve
    return RenderMaterial(name, curve, material.coefficients(), roughness)


#: The talk's Figure 2 material (Gulbrandsen's reflectivity and edge tint) and its roughness there (α = 0.08).
FIGURE2 = {"reflectivity": 0.44, "edge_tint": [0.0, 1.0, 0.0]}
FIGURE2_ROUGHNESS = float(np.sqrt(0.08))


def _figure2(space: str) -> RenderMaterial:
    return _render_material("Figure 2 (r 0.44, g (0, 1, 0))", FIGURE2, space, (FIGURE2_ROUGHNESS, 0.5))


def _tabulated(curve: Callable[[np.ndarray], np.ndarray], samples: int = 8193) -> Callable[[np.ndarray], np.ndarray]:
    """The curve on a dense μ table, linearly interpolated (max error < 1e-6 for Fresnel curves, measured
    by ``tests/fresnel_lut/test_render.py``): the spectral curve costs 95 wavelengths per evaluation."""
    mu = np.linspace(0.0, 1.0, samples)
    table = curve(mu)

    def tabulated(x: np.ndarray) -> np.ndarray:
        x = np.clip(np.asarray(x, dtype=np.float64), 0.0, 1.0)
        position = x * (samples - 1)
        low = np.minimum(position.astype(int), samples - 2)
        fraction = (position - low)[..., None]
        return (1.0 - fraction) * table[low] + fraction * table[low + 1]

    return tabulated


def _preset(name: str, space: str) -> RenderMaterial:
    return _render_material(name, {"preset": name}, space, (0.15, 0.3, 0.6))


#: The default scenes: the talk's Figure 2 material at α = 0.08 (r = √0.08), and three measured metals.
DEFAULT_SCENES: dict[str, Callable[[str], RenderMaterial]] = {
    "figure2": _figure2,
    "chromium": lambda space: _preset("Chromium", space),
    "gold": lambda space: _preset("Gold", space),
    "beryllium": lambda space: _preset("Beryllium", space),
}


def sphere_geometry(size: int) -> tuple[np.ndarray, np.ndarray]:
    """(normals (S, S, 3), mask (S, S)) of a unit sphere filling a square orthographic image, +y up."""
    size = check_positive_int("size", size, low=2, high=8192)
    coordinate = texel_centres(size) * 2.0 - 1.0
    x, y = np.meshgrid(coordinate, -coordinate)
    radius2 = x * x + y * y
    mask = radius2 < 1.0
    z = np.sqrt(np.clip(1.0 - radius2, 0.0, 1.0))
    return np.stack([x, y, z], axis=-1), mask


def render_split_sum(
    material: RenderMaterial,
    roughness: float,
    size: int,
    basis_lut: np.ndarray,
    schlick_lut: np.ndarray,
    environment: Environment = STUDIO,
) -> dict[str, np.ndarray]:
    """Linear RGB images (S, S, 3) of the split sum with the Schlick and the basis LUTs, the basis one
    compensated for multiple scattering (:mod:`preintegrate.multiple_scattering`), and their time."""
    roughness = float(check_range("roughness", roughness, 0.0, 1.0))
    started = time.perf_counter()
    normals, mask = sphere_geometry(size)
    mu_o = np.clip(normals[..., 2], 0.0, 1.0)
    view = np.array([0.0, 0.0, 1.0])
    reflected = 2.0 * mu_o[..., None] * normals - view
    prefiltered = environment.prefiltered(reflected, roughness_to_alpha(roughness))
    f0 = material.curve(np.array(1.0))
    schlick = lut_lookup(schlick_lut, mu_o, roughness)  # (S, S, 2 or 3): scale, bias[, E]
    basis = lut_lookup(basis_lut, mu_o, roughness) @ material.coefficients.T
    images = {
        "schlick": prefiltered * (schlick[..., :1] * f0 + schlick[..., 1:2]),
        "basis": prefiltered * basis,
        "basis_multiple_scattering": prefiltered
        * compensate_lookup(basis, schlick, material.coefficients, default_basis()),
    }
    for image in images.values():
        image[~mask] = 0.0
    images["seconds"] = time.perf_counter() - started
    return images


#: The renderer's punctual light: from above, right and in front, of this radiance (a directional light).
POINT_LIGHT_DIRECTION = (0.5, 0.6, 0.62)
POINT_LIGHT_RADIANCE = 3.0


def render_point_light(
    material: RenderMaterial,
    roughness: float,
    size: int,
    direction=POINT_LIGHT_DIRECTION,
    radiance: float = POINT_LIGHT_RADIANCE,
    visibility: str = "height-correlated",
) -> dict[str, np.ndarray]:
    """Linear RGB images (S, S, 3) of a directional (punctual) light of ``radiance`` from ``direction`` on the
    sphere: the GGX BRDF with Schlick's F, the basis' direct-light F and the exact F (module docstring)."""
    roughness = float(check_range("roughness", roughness, 1e-3, 1.0))
    check_choice("visibility", visibility, list(VISIBILITIES))
    light = _unit(direction)
    normals, mask = sphere_geometry(size)
    view = np.array([0.0, 0.0, 1.0])
    half = _unit(view + light)
    mu_o, mu_l = np.clip(normals[..., 2], 0.0, 1.0), np.clip(normals @ light, 0.0, 1.0)
    mu_h = np.clip(normals @ half, 0.0, 1.0)
    v_dot_h = float(np.clip(view @ half, 0.0, 1.0))
    alpha = roughness_to_alpha(roughness)
    g2 = VISIBILITIES[visibility].g2(mu_o, mu_l, alpha)
    with np.errstate(divide="ignore", invalid="ignore"):
        brdf_cos = np.where((mu_o > 0) & (mu_l > 0), ndf(mu_h, alpha) * g2 / (4.0 * mu_o), 0.0)  # ρ μl without F
    f0 = material.curve(np.array(1.0))
    fresnel = {
        "schlick": f0 + (1.0 - f0) * (1.0 - v_dot_h) ** 5,
        "basis": direct_fresnel(material.coefficients, np.full(3, v_dot_h)),
        "exact": material.curve(np.array(v_dot_h)),
    }
    images = {name: radiance * brdf_cos[..., None] * np.broadcast_to(value, (3,)) for name, value in fresnel.items()}
    for image in images.values():
        image[~mask] = 0.0
    return images


def rect_light_corners(centre=(-1.2, 2.0, 2.6), size=(1.6, 0.8)) -> np.ndarray:
    """(4, 3) corners of a rectangular light centred at ``centre`` facing the origin (the sphere's centre), wound as
    three.js winds them: (c1 − c0) × (c3 − c0) points towards the lit side."""
    centre = np.asarray(centre, dtype=np.float64)
    towards = -centre / np.linalg.norm(centre)
    across = _unit(np.cross(towards, [0.0, 1.0, 0.0]))
    up = np.cross(across, towards)
    half_w, half_h = 0.5 * size[0] * across, 0.5 * size[1] * up
    corners = np.array(
        [centre - half_w - half_h, centre - half_w + half_h, centre + half_w + half_h, centre + half_w - half_h]
    )
    if np.dot(np.cross(corners[1] - corners[0], corners[3] - corners[0]), towards) < 0.0:
        corners = corners[::-1].copy()
    return corners


#: The report's rectangular light (a soft box above, left and in front of the sphere) and its radiance.
RECT_LIGHT = rect_light_corners()
RECT_LIGHT_RADIANCE = 4.0


def render_rect_light(
    material: RenderMaterial,
    roughness: float,
    size: int,
    ltc_lut: np.ndarray,
    basis_lut: np.ndarray,
    schlick_lut: np.ndarray,
    corners=RECT_LIGHT,
    radiance: float = RECT_LIGHT_RADIANCE,
    visibility: str = "height-correlated",
) -> dict[str, np.ndarray]:
    """Linear RGB images (S, S, 3) of a rectangular light of ``radiance`` on the unit sphere by linearly transformed
    cosines (:mod:`preintegrate.ltc`, the shaders' ``fresnelLtcRectVector``), its Fresnel three ways: the exact
    curve's (the LTC integral, taken toward the lobe's punctual limit, × E mix(F̃, F̄ / E, w) with the exact F̃ (the
    curve averaged over a GGX lobe of roughness r' at V·H*, :func:`preintegrate.ltc.smoothed_fresnel`) and F̄: what the
    LTC and that factorisation alone cost), the basis' (``fresnelBasisRectLight``,
    :func:`handoff.shaders.rect_light_specular`) and Schlick's F0 s + b (``fresnelSchlickRectLight``), all three on
    the same integral; and that integral, the one their Fresnel factors multiply (``ltc``, one channel)."""
    roughness = float(check_range("roughness", roughness, 0.0, 1.0))
    check_choice("visibility", visibility, list(VISIBILITIES))
    normals, mask = sphere_geometry(size)
    view = np.broadcast_to([0.0, 0.0, 1.0], normals.shape)
    mu_o = np.clip(normals[..., 2], 0.0, 1.0)
    sine = np.linalg.norm(np.cross(normals, view), axis=-1)
    grid = ltc_grid(ltc_lut.shape[0], visibility)
    stored = grid.lookup(ltc_lut, mu_o, roughness, sine)
    schlick = lut_lookup(schlick_lut, mu_o, roughness)
    toward, v_dot_h, spread = rect_light_half_cosine(
        stored, normals, view, normals, corners, roughness, schlick[..., 2]
    )
    nodes = texel_centres(256)
    exact_table = directional_albedo(
        material.curve, nodes, roughness_to_alpha(roughness), visibility=visibility, workers=1
    )  # (256, 3): F̄ of the exact curve along μo
    exact = np.stack([np.interp(mu_o, nodes, exact_table[:, c]) for c in range(3)], axis=-1)
    f0 = material.curve(np.array(1.0))
    coefficients = np.broadcast_to(material.coefficients, normals.shape[:-1] + material.coefficients.shape)
    basis = rect_light_specular(ltc_lut, basis_lut, normals, view, normals, corners, roughness, coefficients)
    images = {
        "exact": radiance
        * rect_light_fresnel(
            toward, exact, schlick[..., 2:3] * smoothed_fresnel(material.curve, v_dot_h, spread, workers=1)
        ),
        "basis": radiance * basis,
        "schlick": radiance * toward[..., None] * (schlick[..., :1] * f0 + schlick[..., 1:2]),
    }
    for image in images.values():
        image[~mask] = 0.0
    images["ltc"] = np.where(mask, toward, 0.0)
    return images


#: Point sets of :func:`render_reference`: independent uniform numbers, or a rank-1 lattice randomly shifted
#: per pixel (Cranley–Patterson), which is as unbiased and, on these smooth integrands, less noisy.
SAMPLINGS = ("random", "lattice")
#: The golden ratio's generator of the rank-1 lattice (i/N, {i g/N}) with g ≈ N/φ coprime to N.
_GOLDEN = 0.5 * (1.0 + 5.0**0.5)


def _uniform_points(rng: np.random.Generator, sampling: str, samples: int, pixels: int):
    """Yield (u1, u2), each (count, pixels), over ``samples`` points per pixel in batches of 16."""
    if sampling == "lattice":
        generator = max(1, round(samples / _GOLDEN))
        while math.gcd(generator, samples) != 1:
            generator += 1
        shift = rng.random((2, pixels))
    for start in range(0, samples, _BATCH):
        count = min(_BATCH, samples - start)
        if sampling == "random":
            yield rng.random((count, pixels)), rng.random((count, pixels))
            continue
        index = np.arange(start, start + count)[:, None]
        yield np.mod(index / samples + shift[0], 1.0), np.mod(index * generator / samples + shift[1], 1.0)


#: Samples per pixel evaluated at once: (16, pixels, 3) arrays keep a 256² reference near 0.2 GB.
_BATCH = 16


def render_reference(
    material: RenderMaterial,
    roughness: float,
    size: int,
    samples: int,
    seed: int = 0,
    environment: Environment = STUDIO,
    sampling: str = "lattice",
    workers: int | None = None,
    visibility: str = "height-correlated",
) -> tuple[np.ndarray, np.ndarray, float]:
    """(image (S, S, 3), spread (S, S, 3), seconds): VNDF Monte Carlo with the exact Fresnel curve.

    ``sampling="random"`` draws independent uniform numbers and ``spread`` is the standard error of the mean;
    ``"lattice"`` (default) uses a randomly shifted rank-1 lattice per pixel (unbiased; about half the
    ΔE2000 noise at 256 spp, ``tests/fresnel_lut/test_render.py``), for which the same formula is an upper
    bound. Either way two seeds give independent estimates. ``workers`` threads (default: the machine's
    cores) share the pixels; BLAS runs on one thread (:mod:`basis.parallel`). ``visibility``: the BRDF's G2 form
    (:data:`preintegrate.ggx.VISIBILITIES`), which the split-sum tables compared with it must share.
    """
    roughness = float(check_range("roughness", roughness, 1e-3, 1.0))
    samples = check_positive_int("samples", samples, low=2, high=1 << 20)
    check_choice("sampling", sampling, SAMPLINGS)
    check_choice("visibility", visibility, list(VISIBILITIES))
    started = time.perf_counter()
    alpha = roughness_to_alpha(roughness)
    normals, mask = sphere_geometry(size)
    n = normals[mask]  # (P, 3)
    view = np.array([0.0, 0.0, 1.0])
    mu_o = np.clip(n[:, 2], 1e-6, 1.0)
    tangent = view - mu_o[:, None] * n
    length = np.linalg.norm(tangent, axis=-1, keepdims=True)
    fallback = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0.0, 0.0]], [[0.0, 1.0, 0.0]])
    tangent = np.where(
        length > 1e-9, tangent / np.maximum(length, 1e-300), fallback - (fallback * n).sum(-1, keepdims=True) * n
    )
    tangent /= np.linalg.norm(tangent, axis=-1, keepdims=True)
    bitangent = np.cross(n, tangent)
    total = np.zeros((n.shape[0], 3))
    total_sq = np.zeros_like(total)

    def accumulate(pixels: slice, u1: np.ndarray, u2: np.ndarray) -> None:
        cos_d, local_i, weight = contributions(
            mu_o[None, pixels], alpha, u1[:, pixels], u2[:, pixels], visibility=visibility
        )  # local frame
        world_i = (
            local_i[..., :1] * tangent[pixels] + local_i[..., 1:2] * bitangent[pixels] + local_i[..., 2:] * n[pixels]
        )
        value = material.curve(cos_d) * weight[..., None] * environment.radiance(world_i)
        total[pixels] += value.sum(axis=0)
        total_sq[pixels] += (value**2).sum(axis=0)

    # each pixel's sum runs in the same order whatever the number of workers: the image's bits do not depend on it
    bounds = np.linspace(0, n.shape[0], worker_count(workers) + 1).astype(int)
    parts = [slice(low, high) for low, high in zip(bounds[:-1], bounds[1:])]
    with one_blas_thread(), concurrent.futures.ThreadPoolExecutor(max_workers=len(parts)) as pool:
        for u1, u2 in _uniform_points(np.random.default_rng(seed), sampling, samples, n.shape[0]):
            for done in [pool.submit(accumulate, part, u1, u2) for part in parts]:
                done.result()
    mean = total / samples
    error = np.sqrt(np.maximum(total_sq / samples - mean**2, 0.0) / (samples - 1))
    image = np.zeros(normals.shape)
    deviation = np.zeros(normals.shape)
    image[mask], deviation[mask] = mean, error
    return image, deviation, time.perf_counter() - started


def tone_map(image: np.ndarray, exposure: float = 1.0) -> np.ndarray:
    """Linear display values in [0, 1]: exposure, then x / (1 + x) on each channel's excess over 0.8
    (identity below 0.8, so most of the sphere is compared unchanged)."""
    scaled = np.maximum(image * exposure, 0.0)
    knee = 0.8
    excess = np.maximum(scaled - knee, 0.0)
    return np.where(scaled <= knee, scaled, knee + (1.0 - knee) * excess / (excess + (1.0 - knee)))


def to_srgb8(linear: np.ndarray) -> np.ndarray:
    """8-bit sRGB (IEC 61966-2-1 transfer function) of linear values in [0, 1]."""
    linear = np.clip(linear, 0.0, 1.0)
    encoded = np.where(linear <= 0.0031308, 12.92 * linear, 1.055 * linear ** (1.0 / 2.4) - 0.055)
    return np.round(encoded * 255.0).astype(np.uint8)
