"""The shader hand-off (luts/fresnel_basis.{glsl,hlsl,wgsl}) against the Python API, through a numpy transcription.

The real compilers and GPU run are tests/luts/test_shaders_gpu.py; the transcription below follows the shader
(a level-0 fetch with bilinear filtering and clamp-to-edge at the half-texel remap of end-point texels,
u = (x (size − 1) + 0.5)/size of x = (√NdotV, r), then dot products), and the tests check both that the include's
remap constants are that remap in every language and that the transcription reproduces the Python API.
"""

import re
from pathlib import Path

import numpy as np
import pytest

from basis import coefficients_from_nk, default_basis
from basis.angles import cos_theta
from basis.fresnel import fresnel_conductor
from basis.gulbrandsen import gulbrandsen_to_nk
from handoff.exr import read_lut
from preintegrate.channels import basis_channels, schlick_channels
from preintegrate.quadrature import directional_albedo

LUTS = Path(__file__).resolve().parents[2] / "luts"
INCLUDES = {
    language: (LUTS / f"fresnel_basis.{language}").read_text(encoding="utf-8") for language in ("glsl", "hlsl", "wgsl")
}
BASIS_LUT, BASIS_HEADER = read_lut(LUTS / "ggx_basis_rgba.exr")
SCHLICK_LUT, _ = read_lut(LUTS / "ggx_schlick_rgba.exr")
GOLD = (np.array([0.18, 0.42, 1.37]), np.array([3.42, 2.35, 1.77]))


def texture_bilinear_clamp(lut: np.ndarray, u, v) -> np.ndarray:
    """GPU texture(): texel centres at (i + 0.5)/W, bilinear weights, clamp-to-edge addressing."""
    height, width = lut.shape[:2]
    x = np.clip(np.asarray(u, dtype=float), 0.0, 1.0) * width - 0.5
    y = np.clip(np.asarray(v, dtype=float), 0.0, 1.0) * height - 0.5
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    xa, xb = np.clip(x0, 0, width - 1), np.clip(x0 + 1, 0, width - 1)
    ya, yb = np.clip(y0, 0, height - 1), np.clip(y0 + 1, 0, height - 1)
    top = lut[ya, xa] * (1 - fx) + lut[ya, xb] * fx
    bottom = lut[yb, xa] * (1 - fx) + lut[yb, xb] * fx
    return top * (1 - fy) + bottom * fy


def lut_coordinates(lut: np.ndarray, n_dot_v, roughness) -> tuple[np.ndarray, np.ndarray]:
    """fresnelLutCoordinates(size, NdotV, r): x = (sqrt(clamp(NdotV)), clamp(r)); (x (size - 1) + 0.5) / size."""
    height, width = lut.shape[:2]
    x = np.sqrt(np.clip(np.asarray(n_dot_v, dtype=float), 0.0, 1.0))
    y = np.clip(np.asarray(roughness, dtype=float), 0.0, 1.0)
    return (x * (width - 1) + 0.5) / width, (y * (height - 1) + 0.5) / height


def fresnel_basis_split_sum(n_dot_v, roughness, coefficients) -> np.ndarray:
    """fresnelBasisSplitSum: b = texture(basisLut, coordinates); (dot(cR, b), dot(cG, b), dot(cB, b))."""
    b = texture_bilinear_clamp(BASIS_LUT, *lut_coordinates(BASIS_LUT, n_dot_v, roughness))
    return np.einsum("...k,...ck->...c", b, coefficients)


def fresnel_schlick_split_sum(n_dot_v, roughness, f0) -> np.ndarray:
    """fresnelSchlickSplitSum: scaleBias = texture(schlickLut, (NdotV, r)).rg; F0 * scale + bias."""
    scale_bias = texture_bilinear_clamp(SCHLICK_LUT, *lut_coordinates(SCHLICK_LUT, n_dot_v, roughness))
    return f0 * scale_bias[..., :1] + scale_bias[..., 1:2]  # .rg: R = scale, G = bias (B = E is not used here)


def _constant(text: str, name: str) -> np.ndarray:
    """The numbers of the constant ``name`` as an include of any language writes it."""
    found = re.search(rf"{name}\b[^=]*=\s*\w*\(([^)]*)\)", text)
    assert found, name
    return np.array([float(value) for value in found.group(1).split(",")])


@pytest.mark.parametrize("language", ["glsl", "hlsl", "wgsl"])
def test_the_include_remaps_as_the_transcription(language):
    """Every language's include reads the tables through u = x (W − 1)/W + 0.5/W of x = √NdotV and
    v = r (H − 1)/H + 0.5/H of r in [0, 1] (FRESNEL_LUT_COLUMNS, FRESNEL_LUT_ROWS), the transcription's remap, and
    states the tables' basis."""
    text = INCLUDES[language]
    height, width = BASIS_LUT.shape[:2]
    np.testing.assert_allclose(_constant(text, "FRESNEL_LUT_COLUMNS"), [(width - 1) / width, 0.5 / width], rtol=1e-8)
    rows = [0.0, 1.0, (height - 1) / height, 0.5 / height]
    np.testing.assert_allclose(_constant(text, "FRESNEL_LUT_ROWS"), rows, rtol=1e-8)
    assert "sqrt(fresnelSanitize(NdotV, 1.0, 0.0, 1.0))" in text
    assert f"fresnel:basis_hash = {BASIS_HEADER['basis_hash']}" in text
    assert BASIS_HEADER["basis_hash"] == default_basis().content_hash


@pytest.mark.parametrize("i, j", [(0, 0), (5, 77), (64, 64), (127, 3), (90, 127)])
def test_texels_equal_the_python_api(i, j):
    """At a texel (√μo = i/127, r = j/127, the edges included) the shader's value is Σ c_k LUT_k of that texel; it
    equals the Python API's quadrature of the basis channels to float32 storage (|Δ| ≤ 1e-6)."""
    coefficients = coefficients_from_nk(*GOLD)
    mu_o, roughness = (i / 127) ** 2, j / 127
    shader = fresnel_basis_split_sum(mu_o, roughness, coefficients)
    np.testing.assert_allclose(shader, coefficients @ BASIS_LUT[j, i], rtol=0, atol=1e-12)
    api = coefficients @ directional_albedo(basis_channels().functions, mu_o, roughness**2)
    np.testing.assert_allclose(shader, api, rtol=0, atol=1e-6)


def test_between_texels_against_exact_fresnel():
    """Random (NdotV, r) in [0.02, 1] × [0.05, 1]: the shader's F̄ for gold and for the talk's Figure 2 material
    (Gulbrandsen r = 0.44, g = (0, 1, 0)) vs the split-sum integral of the exact Fresnel curve. Allowed: the
    model's own max |ΔF| over θ for the material (F̄ averages F with total weight ≤ 1) plus the bilinear
    interpolation of a 128² table (bound 4e-3). The same check for Schlick, with its own curve error."""
    rng = np.random.default_rng(5)
    n_dot_v, roughness = rng.uniform(0.02, 1.0, 40), rng.uniform(0.05, 1.0, 40)
    mu = cos_theta(np.linspace(0.0, 0.5 * np.pi, 2001))
    for eta, kappa in (GOLD, gulbrandsen_to_nk(np.full(3, 0.44), np.array([0.0, 1.0, 0.0]))):
        curves = fresnel_conductor(mu, eta[:, None], kappa[:, None])  # (3, angles)
        exact = directional_albedo(lambda x: fresnel_conductor(x[..., None], eta, kappa), n_dot_v, roughness**2)
        coefficients = coefficients_from_nk(eta, kappa)
        basis_curve_error = np.max(np.abs(coefficients @ default_basis().evaluate_mu(mu).T - curves), axis=1)
        shader = fresnel_basis_split_sum(n_dot_v, roughness, coefficients)
        assert np.all(np.abs(shader - exact) <= basis_curve_error + 4e-3)
        f0 = curves[:, 0]
        schlick_curve_error = np.max(np.abs(f0[:, None] + (1 - f0[:, None]) * (1 - mu) ** 5 - curves), axis=1)
        schlick = fresnel_schlick_split_sum(n_dot_v, roughness, f0)
        assert np.all(np.abs(schlick - exact) <= schlick_curve_error + 4e-3)


def test_schlick_texel_equals_quadrature():
    """Schlick shader at a texel = F0 · scale + bias of the Python quadrature (|Δ| ≤ 1e-6)."""
    f0 = np.array([0.04, 0.5, 0.95])
    mu_o, roughness = (40 / 127) ** 2, 100 / 127
    scale_bias = directional_albedo(schlick_channels().functions, mu_o, roughness**2)
    np.testing.assert_allclose(
        fresnel_schlick_split_sum(mu_o, roughness, f0), f0 * scale_bias[0] + scale_bias[1], atol=1e-6
    )


def test_hlsl_types_the_schlick_table_one_way():
    """Issue 26 item 20: the HLSL include typed the Schlick table Texture2D<float2> in one function and <float4> in
    another, so one texture could not serve both."""
    declarations = re.findall(r"Texture2D<(\w+)> schlickLut", INCLUDES["hlsl"])
    assert declarations and set(declarations) == {"float4"}
