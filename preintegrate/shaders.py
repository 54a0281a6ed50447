"""Shader-side Fresnel generated from one basis: per-pixel coefficients, the direct-light curve, the table coordinates.

Public objects: ``ShaderConstants``, ``shader_constants``, ``SHADER_INCLUDES``, ``shader_includes``,
``sanitize_nk``, ``sanitize_gulbrandsen``, ``sanitize_unit``, ``coefficients_per_pixel_nk``,
``coefficients_per_pixel_gulbrandsen``, ``coefficients_per_pixel_model``, ``direct_fresnel``, ``lut_coordinates``,
``linear_model_curve``, ``PER_PIXEL_MODELS``,
``CURVE_SEGMENTS``, ``CURVE_TOLERANCE``.

Everything a shader needs to turn a texel's material parameters into the four coefficients of the basis, and the
coefficients into F(V·H) for a punctual light, depends on the basis alone: b_k at the fit angles, the constant 2 × 2
inverse of the four-point system, the projections of the linear artist models' fixed functions, the hemispherical
averages, and the curves b_k themselves. :func:`shader_constants` computes them from a :class:`~basis.Basis`, and
:func:`shader_includes` writes them with the functions that use them as one self-contained include per language
(GLSL 3.30/4.50/ES 3.00, HLSL, WGSL), which the default build writes beside its tables: coefficients and table
cannot come from different bases (the include states the basis hash, and so does every table header).

The Python functions here mirror the shaders operation for operation (in float64): engines' CPU tools get the
numbers the GPU computes, and the tests compare the two.

* **(η, κ) per pixel** (Belcour 2020, "Coefficients"): c0 = F(0°) in closed form, c1 = F(90°) − c0 (F(90°) = 1 but
  for η = 1, κ = 0), (c2, c3) = S⁻¹ (F(θ_i) − c0 − c1 b1(θ_i)) with the exact Fresnel equations (Hoffman 2020,
  "1823: Fresnel's Equations") at the two fit angles: two Fresnel evaluations and a constant 2 × 2 product.
* **Gulbrandsen (r, g)** → (η, κ) in closed form (Gulbrandsen 2014, eq. 7–9) → the same solve.
* **Linear artist models** (Schlick F0/F90; Hoffman 2019's F82; the F82 tint of Adobe, OpenPBR's
  ``specular_color`` and MaterialX's ``color82``, Hoffman 2023 eq. 3; Hoffman 2023's generalised Adobe with
  p = 5, eq. 6): F = Σ_n w_n t_n(μ) with t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶), so c = Σ_n w_n P_n with P_n the
  four-point coefficients of t_n, three generated constants; w is a few flops of the parameters. The projection
  is of the models' unclamped linear form (they agree with ``coefficients_from_model`` wherever the model's clamp
  to [0, 1] is inactive at the fit angles).
* **Direct light**: F(V·H) = Σ_k c_k b_k(θ_h), the curves as piecewise polynomials in μ over
  :data:`CURVE_SEGMENTS` (the curves steepen near grazing: one polynomial in μ or θ needs degree 16–24 for 1e-4),
  within :data:`CURVE_TOLERANCE` of the basis' own spline in float64.

Inputs are sanitised as the shaders do (:func:`sanitize_nk`, :func:`sanitize_gulbrandsen`, :func:`sanitize_unit`):
NaN becomes the documented fallback, everything else is clamped into the documented range, so no texel value gives
NaN or inf.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4-5 and "Coefficients". :cite:`Hoffman2020` "Fresnel Equations
Considered Harmful". :cite:`Gulbrandsen2014` JCGT 3(4), eq. 7-9. :cite:`Hoffman2019` eq. 4.
:cite:`Hoffman2023` "Generalization of Adobe's Fresnel Model", eq. 3 and 6.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from basis.angles import cos_theta
from basis.coefficients import coefficients_from_samples
from basis.eigenbasis import Basis, resolve_basis
from basis.models.formulas import F82_MU, adobe_dip_weight, f82_dip_weight, lazanyi_dip, schlick_weight
from basis.validation import ParameterError, as_float_array, check_choice

from .lut import LutGrid

__all__ = [
    "CURVE_SEGMENTS",
    "CURVE_TOLERANCE",
    "PER_PIXEL_MODELS",
    "SHADER_INCLUDES",
    "ShaderConstants",
    "coefficients_per_pixel_gulbrandsen",
    "coefficients_per_pixel_model",
    "coefficients_per_pixel_nk",
    "direct_fresnel",
    "linear_model_curve",
    "lut_coordinates",
    "sanitize_gulbrandsen",
    "sanitize_nk",
    "sanitize_unit",
    "shader_constants",
    "shader_includes",
]

#: Segment edges in μ = V·H of the direct-light polynomials: the curves bend fastest near grazing (the shipped
#: basis' b3 has slope 38 per radian at θ = π/2), so the segments are narrow there. Chosen by measurement on the
#: shipped basis: one polynomial in μ needs degree 16 for 4.2e-4, in θ degree 24 for 2e-4, in √μ degree 16 for
#: 4.7e-4; these three segments reach 2.9e-5 at degree 8.
CURVE_SEGMENTS = (0.0, 0.08, 0.3, 1.0)
#: The most the direct-light polynomials may differ from the basis' spline in float64 (the issue's 1e-4, with room
#: for float32 evaluation); the degree is the smallest of 6 … 12 that reaches it.
CURVE_TOLERANCE = 5e-5
_DEGREES = range(6, 13)
_CURVE_SAMPLES = 4001  # per segment, end points included: the fit's and the check's grid

#: Documented input ranges of the per-pixel functions (the Python API's, where float32 holds them).
ETA_LIMITS = (1e-4, 1e4)
KAPPA_LIMITS = (0.0, 1e4)
#: r < 1: η = (1 + √r)/(1 − √r) grows without bound as r → 1 (Gulbrandsen 2014).
REFLECTIVITY_LIMITS = (0.0, 0.9999)

#: Per-pixel linear models: name → (parameters, what each is) of the generated functions.
PER_PIXEL_MODELS = {
    "schlick": (("f0", "f90"), "Schlick 1994 with F90 (generalized-schlick, p = 5)"),
    "f82": (("f0", "f82"), "Hoffman 2019: the absolute reflectance at arccos(1/7)"),
    "f82-tint": (
        ("f0", "tint"),
        "Adobe / OpenPBR specular_color / MaterialX color82: a tint on Schlick at arccos(1/7)",
    ),
    "generalized-adobe": (("r0", "r90", "tint"), "Hoffman 2023 eq. 6 with p = 5"),
}


@dataclasses.dataclass(frozen=True)
class ShaderConstants:
    """What the shader includes of one basis hold (all float64 here; the includes print them with 9 digits)."""

    basis_hash: str
    fit_mu: np.ndarray  # (2,) cos θ2, cos θ3
    fit_b1: np.ndarray  # (2,) b1(θ2), b1(θ3)
    inverse: np.ndarray  # (2, 2) S⁻¹, S[i, j] = b_{j+2}(θ_{i+2})
    projections: np.ndarray  # (3, 4) four-point coefficients of t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶)
    averages: np.ndarray  # (4,) hemispherical averages of b_k
    curve_degree: int
    curve_polynomials: np.ndarray  # (segments, degree + 1, 4): b_k on a segment, powers of s = 2 (μ − lo)/(hi − lo) − 1
    curve_error: float  # max |polynomial − spline| over the segments' dense grids, float64
    grid: LutGrid = LutGrid(128, 128)  # the tables' grid: the include's coordinate function reads them on it

    @property
    def row_mapping(self) -> tuple[float, float, float, float]:
        """(r_low, r_high, scale, offset): the table's v = clamp(r, r_low, r_high) · scale + offset (texel centres:
        v = r; end-point rows: v = ((r − low)/(high − low) (H − 1) + 0.5)/H, read exactly at both ends)."""
        if self.grid.rows == "centres":
            return 0.0, 1.0, 1.0, 0.0
        low, high = self.grid.roughness_range
        height = self.grid.height
        if height == 1:
            return low, low, 0.0, 0.5
        scale = (height - 1) / ((high - low) * height)
        return low, high, scale, 0.5 / height - low * scale


def _linear_functions(mu: np.ndarray) -> np.ndarray:
    """(…, 3): the fixed functions of the linear artist models, t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶)."""
    fifth = schlick_weight(mu)
    return np.stack([1.0 - fifth, fifth, lazanyi_dip(mu)], axis=-1)


def shader_constants(basis: Basis | None = None, grid: LutGrid | None = None) -> ShaderConstants:
    """The constants of :func:`shader_includes` for a four-term basis (default: the shipped one) and the grid of its
    tables (default: the default build's 128 × 128)."""
    basis = resolve_basis(basis)
    if basis.n_terms != 4:
        raise ParameterError(
            f"the shader functions hold four coefficients per channel; this basis has {basis.n_terms} "
            "terms (its tables still work with fresnelBasisSplitSum8 and CPU coefficients)"
        )
    system = basis.evaluate(basis.fit_angles)  # B[i, k] = b_k(θ_i)
    inverse = np.linalg.inv(system[2:, 2:])
    projections = coefficients_from_samples(_linear_functions(cos_theta(basis.fit_angles)).T, basis)
    degree, polynomials, error = _fit_curves(basis)
    return ShaderConstants(
        basis.content_hash,
        cos_theta(basis.fit_angles[2:]),
        system[2:, 1],
        inverse,
        projections,
        np.asarray(basis.hemispherical_averages),
        degree,
        polynomials,
        error,
        LutGrid(128, 128) if grid is None else grid,
    )


def _fit_curves(basis: Basis) -> tuple[int, np.ndarray, float]:
    """Least-squares polynomials of b_k on each segment of :data:`CURVE_SEGMENTS`, the smallest degree that holds
    :data:`CURVE_TOLERANCE` (or the largest tried, with its error stated)."""
    grids = []
    for low, high in zip(CURVE_SEGMENTS[:-1], CURVE_SEGMENTS[1:]):
        s = np.linspace(-1.0, 1.0, _CURVE_SAMPLES)
        grids.append((s, basis.evaluate_mu(low + 0.5 * (s + 1.0) * (high - low))))
    for degree in _DEGREES:
        polynomials, error = [], 0.0
        for s, values in grids:
            chebyshev = np.polynomial.chebyshev.chebfit(s, values, degree)  # (degree + 1, 4), well conditioned
            power = np.stack([np.polynomial.chebyshev.cheb2poly(chebyshev[:, k]) for k in range(4)], axis=-1)
            polynomials.append(power)
            error = max(error, float(np.max(np.abs(np.polynomial.polynomial.polyval(s, power).T - values))))
        if error <= CURVE_TOLERANCE or degree == _DEGREES[-1]:
            return degree, np.array(polynomials), error
    raise AssertionError("unreachable")


# ----------------------------------------------------------------------------- the Python mirrors
def sanitize_unit(value, fallback: float = 0.0, low: float = 0.0, high: float = 1.0) -> np.ndarray:
    """A texel value as the shaders read it: NaN → ``fallback``, else clamped to [low, high] (±inf to the ends)."""
    value = as_float_array("value", value, finite=False)
    return np.where(np.isnan(value), fallback, np.clip(value, low, high))


def sanitize_nk(eta, kappa) -> tuple[np.ndarray, np.ndarray]:
    """(η, κ) as the shaders read them: clamped to :data:`ETA_LIMITS` and :data:`KAPPA_LIMITS`; NaN η → 1.5 (glass),
    NaN κ → 0."""
    return sanitize_unit(eta, 1.5, *ETA_LIMITS), sanitize_unit(kappa, 0.0, *KAPPA_LIMITS)


def sanitize_gulbrandsen(reflectivity, edge_tint) -> tuple[np.ndarray, np.ndarray]:
    """(r, g) as the shaders read them: r in :data:`REFLECTIVITY_LIMITS`, g in [0, 1]; NaN → 0."""
    return sanitize_unit(reflectivity, 0.0, *REFLECTIVITY_LIMITS), sanitize_unit(edge_tint, 0.0)


def _fresnel_at_fit_angles(eta: np.ndarray, kappa2: np.ndarray, constants: ShaderConstants) -> np.ndarray:
    """(…, 2) exact Fresnel at the two fit angles as ``fresnelAtFitAngles`` computes it: Hoffman 2020's Fs and Fp/Fs
    with the angle terms constant, F = ½ Fs (1 + Fp/Fs) = (s + μ² − 2aμ) r / ((s + μ² + 2aμ)(r + 2aμ sin²θ)),
    r = s μ² + sin⁴θ: one division per angle (0 < μ < 1 keeps both denominators positive)."""
    mu = constants.fit_mu
    mu2, sin2 = mu * mu, (1.0 - mu) * (1.0 + mu)
    eta, kappa2 = eta[..., None], kappa2[..., None]
    near_one = np.abs(eta - 1.0) < 0.5
    t = np.where(near_one, (eta - 1.0) * (eta + 1.0), eta * eta) - kappa2 + np.where(near_one, mu2, -sin2)
    e4 = 4.0 * eta * eta * kappa2
    s = np.sqrt(t * t + e4)
    u = s + np.abs(t)
    with np.errstate(divide="ignore", invalid="ignore"):
        two_a2 = np.where(t >= 0.0, u, e4 / u)
    two_a_mu = 2.0 * mu * np.sqrt(0.5 * two_a2)
    r = s * mu2 + sin2 * sin2
    return np.clip((s + mu2 - two_a_mu) * r / ((s + mu2 + two_a_mu) * (r + two_a_mu * sin2)), 0.0, 1.0)


def coefficients_per_pixel_nk(eta, kappa, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 4) coefficients of (η, κ) texels, as ``fresnelCoefficientsNK`` computes them (inputs sanitised)."""
    eta, kappa = sanitize_nk(eta, kappa)
    return _coefficients_eta_kappa2(*np.broadcast_arrays(eta, kappa * kappa), constants)


def _coefficients_eta_kappa2(eta: np.ndarray, kappa2: np.ndarray, constants: ShaderConstants | None) -> np.ndarray:
    """``fresnelCoefficientsEtaKappa2``: the four-point solve of (η, κ²) in range."""
    constants = shader_constants() if constants is None else constants
    f0 = ((eta - 1.0) ** 2 + kappa2) / ((eta + 1.0) ** 2 + kappa2)
    f90 = np.where((eta == 1.0) & (kappa2 == 0.0), 0.0, 1.0)
    samples = _fresnel_at_fit_angles(eta, kappa2, constants)  # (…, 2)
    rest = samples - f0[..., None] - (f90 - f0)[..., None] * constants.fit_b1
    c23 = rest @ constants.inverse.T
    return np.concatenate([f0[..., None], (f90 - f0)[..., None], c23], axis=-1)


def _gulbrandsen_eta_kappa2(reflectivity: np.ndarray, edge_tint: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Gulbrandsen 2014 eq. 7-9 as the shaders write it. With q = √r, n = g n_min + (1 − g) n_max and
    κ² = (r (n + 1)² − (n − 1)²)/(1 − r) factors exactly into g (n_max − n_min)(n − 1/n_max), each factor a sum of
    positive terms: n_max − n_min = 2q (1 + q)/((1 − q)(1 + r)), n − 1/n_max = g 2q (1 − q)/((1 + r)(1 + q))
    + (1 − g) 4q/(1 − r). Float32 then holds κ where the textbook form cancels (r → 0 with g → 1: 6e-4 in c2)."""
    g, r = edge_tint, reflectivity
    q = np.sqrt(r)
    over_1pr, over_1mq, over_1pq = 1.0 / (1.0 + r), 1.0 / (1.0 - q), 1.0 / (1.0 + q)  # 1/(1 − r) = their product
    eta = g * (1.0 - r) * over_1pr + (1.0 - g) * (1.0 + q) * over_1mq
    spread = 2.0 * q * (1.0 + q) * over_1mq * over_1pr
    above = g * 2.0 * q * (1.0 - q) * over_1pr * over_1pq + (1.0 - g) * 4.0 * q * over_1mq * over_1pq
    return eta, g * spread * above


def coefficients_per_pixel_gulbrandsen(reflectivity, edge_tint, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 4) coefficients of (r, g) texels, as ``fresnelCoefficientsGulbrandsen`` computes them."""
    reflectivity, edge_tint = sanitize_gulbrandsen(reflectivity, edge_tint)
    return _coefficients_eta_kappa2(*_gulbrandsen_eta_kappa2(*np.broadcast_arrays(reflectivity, edge_tint)), constants)


def _model_weights(model: str, parameters: dict[str, np.ndarray]) -> np.ndarray:
    """(…, 3) weights w of t for a model of :data:`PER_PIXEL_MODELS` (parameters sanitised to [0, 1])."""
    # the dip weights a are the model registry's own formulas (basis.models.formulas), which the shaders' constants
    # FRESNEL_F82_SCHLICK_WEIGHT and FRESNEL_F82_DIP spell out for float32
    if model == "schlick":
        f0, f90 = parameters["f0"], parameters["f90"]
        return np.stack(np.broadcast_arrays(f0, f90, np.zeros_like(f0)), axis=-1)
    if model == "f82":  # Hoffman 2019 eq. 4
        f0 = parameters["f0"]
        return np.stack(np.broadcast_arrays(f0, np.ones_like(f0), -f82_dip_weight(f0, parameters["f82"])), axis=-1)
    if model == "f82-tint":  # Hoffman 2023 eq. 3
        f0 = parameters["f0"]
        return np.stack(np.broadcast_arrays(f0, np.ones_like(f0), -adobe_dip_weight(f0, parameters["tint"])), axis=-1)
    r0, r90, tint = parameters["r0"], parameters["r90"], parameters["tint"]  # Hoffman 2023 eq. 6, p = 5
    return np.stack(np.broadcast_arrays(r0, r90, -adobe_dip_weight(r0, tint, r90)), axis=-1)


def coefficients_per_pixel_model(model: str, constants: ShaderConstants | None = None, **parameters) -> np.ndarray:
    """(…, 4) coefficients of a linear artist model of :data:`PER_PIXEL_MODELS` (each parameter a number or array in
    [0, 1], NaN → 0), as the generated ``fresnelCoefficients…`` functions compute them: Σ_n w_n P_n."""
    check_choice("model", model, list(PER_PIXEL_MODELS))
    names = PER_PIXEL_MODELS[model][0]
    if set(parameters) != set(names):
        raise ParameterError(f"model {model!r} takes {list(names)}, got {sorted(parameters)}")
    constants = shader_constants() if constants is None else constants
    clean = {name: sanitize_unit(parameters[name]) for name in names}
    return _model_weights(model, clean) @ constants.projections


def lut_coordinates(n_dot_v, roughness, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 2) texture coordinates (u, v) of (NdotV, r) on the tables' grid, as ``fresnelBasisLutUV`` computes them."""
    constants = shader_constants() if constants is None else constants
    low, high, scale, offset = constants.row_mapping
    u = sanitize_unit(n_dot_v, 1.0)
    v = np.clip(sanitize_unit(roughness, 0.5), low, high) * scale + offset
    return np.stack(np.broadcast_arrays(u, v), axis=-1)


def linear_model_curve(model: str, mu, **parameters) -> np.ndarray:
    """F(μ) of a model of :data:`PER_PIXEL_MODELS` in the linear form the shaders project (unclamped), parameters
    sanitised to [0, 1]; μ broadcast against them: what :func:`coefficients_per_pixel_model` approximates."""
    check_choice("model", model, list(PER_PIXEL_MODELS))
    clean = {name: sanitize_unit(parameters[name]) for name in PER_PIXEL_MODELS[model][0]}
    return np.sum(_model_weights(model, clean) * _linear_functions(sanitize_unit(mu)), axis=-1)


def direct_fresnel(coefficients, v_dot_h, constants: ShaderConstants | None = None) -> np.ndarray:
    """F(V·H) = Σ_k c_k b_k for a punctual light, as ``fresnelBasisDirect`` computes it: coefficients (…, 4) and
    V·H (…) (clamped to [0, 1]) → (…), the curves from the generated piecewise polynomials."""
    constants = shader_constants() if constants is None else constants
    coefficients = as_float_array("coefficients", coefficients)
    mu = sanitize_unit(v_dot_h, 1.0)
    edges = np.asarray(CURVE_SEGMENTS)
    segment = np.clip(np.searchsorted(edges, mu, side="right") - 1, 0, len(edges) - 2)
    low, high = edges[segment], edges[segment + 1]
    s = 2.0 * (mu - low) / (high - low) - 1.0
    polynomials = constants.curve_polynomials[segment]  # (…, degree + 1, 4)
    curves = polynomials[..., -1, :]
    for power in range(constants.curve_degree - 1, -1, -1):  # Horner, as the shaders
        curves = curves * s[..., None] + polynomials[..., power, :]
    return np.sum(coefficients * curves, axis=-1)


# ----------------------------------------------------------------------------- the includes
def _number(value: float) -> str:
    text = f"{float(value):.9g}"
    return text if any(mark in text for mark in ".en") else text + ".0"


def _vector(values, prefix: str) -> str:
    return f"{prefix}(" + ", ".join(_number(value) for value in values) + ")"


def _header(constants: ShaderConstants, language: str, command: str) -> str:
    return (
        f"// fresnel-basis: per-pixel Fresnel of basis {constants.basis_hash} ({language}). Generated by `{command}` from the\n"
        "// basis' own file: do not edit, regenerate it (preintegrate/shaders.py). Self-contained: use it beside the\n"
        "// tables whose header says fresnel:basis_hash = " + constants.basis_hash + ".\n"
        "//\n"
        '// Per pixel, per colour channel (Belcour, Bati, Barla 2020, eq. 4-5 and "Coefficients"):\n'
        "//   fresnelCoefficientsNK(eta, kappa)               exact Fresnel at the two fit angles + a constant 2x2 inverse\n"
        "//   fresnelCoefficientsGulbrandsen(r, g)            Gulbrandsen 2014 eq. 7-9, then the same\n"
        "//   fresnelCoefficientsSchlick(f0, f90)             Schlick 1994 (F90 = 1: the usual Schlick)\n"
        "//   fresnelCoefficientsF82(f0, f82)                 Hoffman 2019's absolute F82\n"
        "//   fresnelCoefficientsF82Tint(f0, tint)            Adobe / OpenPBR specular_color / MaterialX color82 (a tint)\n"
        "//   fresnelCoefficientsGeneralizedAdobe(r0, r90, t) Hoffman 2023 eq. 6, p = 5\n"
        "// then: F for a punctual light = fresnelBasisDirect(VdotH, c); the image-based split sum and the\n"
        "// multiple-scattering average use the same c (fresnelBasisAverage). Inputs: NaN becomes a fallback, every\n"
        "// other value is clamped (eta to [1e-4, 1e4], kappa to [0, 1e4], r to [0, 0.9999], the rest to [0, 1]).\n"
        f"// Float32: coefficients within 1e-5 of float64; the direct-light curves within {constants.curve_error:.1e} of the\n"
        "// basis' spline (float64; tests/luts/test_shaders_per_pixel.py measures both on the GPU).\n"
    )


def _glsl(constants: ShaderConstants, command: str, hlsl: bool = False) -> str:
    """GLSL (3.30, 4.50, ES 3.00) or, with ``hlsl``, HLSL: the same statements with the other spellings."""
    v2, v3, v4, f = ("float2", "float3", "float4", "float") if hlsl else ("vec2", "vec3", "vec4", "float")
    const = "static const" if hlsl else "const"
    bits = "asuint" if hlsl else "floatBitsToUint"
    c, d = constants, constants.curve_degree
    select_twoA2 = "(t >= 0.0) ? u : e4 / u" if hlsl else "mix(e4 / u, u, greaterThanEqual(t, vec2(0.0)))"
    split_sum = (
        "// The split sum of the basis table at level 0, read through fresnelBasisLutUV.\n"
        + (
            "float3 fresnelBasisSplitSumUV(Texture2D<float4> lut, SamplerState linearClamp, float NdotV, float r, "
            "float4 cR, float4 cG, float4 cB)\n{\n    float4 b = lut.SampleLevel(linearClamp, fresnelBasisLutUV(NdotV, r), 0);\n"
            if hlsl
            else "vec3 fresnelBasisSplitSumUV(sampler2D lut, float NdotV, float r, vec4 cR, vec4 cG, vec4 cB)\n{\n"
            "    vec4 b = textureLod(lut, fresnelBasisLutUV(NdotV, r), 0.0);\n"
        )
        + f"    return {v3}(dot(cR, b), dot(cG, b), dot(cB, b));\n}}"
    )
    polynomial = c.curve_polynomials.reshape(-1, 4)
    array = (
        f"{const} {v4} FRESNEL_CURVES[{polynomial.shape[0]}] = {{\n"
        if hlsl
        else f"{const} {v4} FRESNEL_CURVES[{polynomial.shape[0]}] = {v4}[{polynomial.shape[0]}](\n"
    )
    array += ",\n".join("    " + _vector(row, v4) for row in polynomial) + ("\n};\n" if hlsl else "\n);\n")
    return (
        _header(c, "HLSL" if hlsl else "GLSL 3.30 / 4.50 / ES 3.00", command)
        + f"""
{const} uint FRESNEL_BASIS_HASH = 0x{c.basis_hash[:8]}u;  // the first 8 hex digits of {c.basis_hash}
{const} {v2} FRESNEL_FIT_MU = {_vector(c.fit_mu, v2)};       // cos(theta_2), cos(theta_3)
{const} {v2} FRESNEL_FIT_MU2 = {_vector(c.fit_mu**2, v2)};      // cos^2 of the fit angles
{const} {v2} FRESNEL_FIT_SIN2 = {_vector((1.0 - c.fit_mu) * (1.0 + c.fit_mu), v2)};     // sin^2 of the fit angles
{const} {v2} FRESNEL_FIT_B1 = {_vector(c.fit_b1, v2)};       // b1 at the fit angles
{const} {v2} FRESNEL_FIT_INVERSE_0 = {_vector(c.inverse[0], v2)}; // rows of S^-1, S[i][j] = b_(j+2)(theta_(i+2))
{const} {v2} FRESNEL_FIT_INVERSE_1 = {_vector(c.inverse[1], v2)};
{const} {v4} FRESNEL_PROJECTION_SCALE = {_vector(c.projections[0], v4)}; // coefficients of 1 - (1 - mu)^5
{const} {v4} FRESNEL_PROJECTION_BIAS = {_vector(c.projections[1], v4)};  // coefficients of (1 - mu)^5
{const} {v4} FRESNEL_PROJECTION_DIP = {_vector(c.projections[2], v4)};   // coefficients of mu (1 - mu)^6
{const} {v4} FRESNEL_BASIS_AVERAGES = {_vector(c.averages, v4)};   // 2 * integral of b_k(mu) mu dmu
{const} {v4} FRESNEL_CURVE_EDGES = {_vector(CURVE_SEGMENTS, v4)};
{const} int FRESNEL_CURVE_DEGREE = {d};
// b_k(mu) on segment j: sum_p FRESNEL_CURVES[j * {d + 1} + p] * s^p, s = 2 (mu - lo) / (hi - lo) - 1
{array}
// A texel value as the shaders read it: NaN -> fallback (tested by its bits: fast-math compilers may drop x != x),
// everything else clamped to [lo, hi].
{f} fresnelSanitize({f} x, {f} fallback, {f} lo, {f} hi)
{{
    return (({bits}(x) & 0x7fffffffu) > 0x7f800000u) ? fallback : clamp(x, lo, hi);
}}

// Exact unpolarised Fresnel reflectance of eta + i kappa at mu = cos(theta) (Hoffman 2020, "1823: Fresnel's
// Equations"), written as basis/fresnel.py writes it: finite at mu = 0 and for kappa >> eta.
{f} fresnelExact({f} mu, {f} eta, {f} kappa)
{{
    {f} mu2 = mu * mu;
    {f} sin2 = (1.0 - mu) * (1.0 + mu);
    bool nearOne = abs(eta - 1.0) < 0.5;
    {f} t = (nearOne ? (eta - 1.0) * (eta + 1.0) : eta * eta) - kappa * kappa + (nearOne ? mu2 : -sin2);
    {f} fourEta2Kappa2 = 4.0 * (eta * kappa) * (eta * kappa);
    {f} s = sqrt(t * t + fourEta2Kappa2);                      // a^2 + b^2
    {f} u = s + abs(t);
    {f} twoA2 = (t >= 0.0) ? u : ((u > 0.0) ? fourEta2Kappa2 / u : 0.0);
    {f} twoAMu = 2.0 * mu * sqrt(0.5 * twoA2);                  // 2 a mu
    {f} fsDen = s + mu2 + twoAMu;
    {f} fs = (fsDen > 0.0) ? (s + mu2 - twoAMu) / fsDen : ((eta == 1.0 && kappa == 0.0) ? 0.0 : 1.0);
    {f} r = s * mu2 + sin2 * sin2;
    {f} ratioDen = r + twoAMu * sin2;
    {f} ratio = (ratioDen > 0.0) ? (r - twoAMu * sin2) / ratioDen : 1.0;
    return clamp(0.5 * fs * (1.0 + ratio), 0.0, 1.0);
}}

// Exact Fresnel at both fit angles at once, the angle terms constant: F = (s + mu^2 - 2a mu) r /
// ((s + mu^2 + 2a mu)(r + 2a mu sin^2)), r = s mu^2 + sin^4 (Hoffman's Fs times (1 + Fp/Fs) / 2: one division).
{v2} fresnelAtFitAngles({f} eta, {f} kappa2)
{{
    bool nearOne = abs(eta - 1.0) < 0.5;
    {f} base = (nearOne ? (eta - 1.0) * (eta + 1.0) : eta * eta) - kappa2;
    {v2} t = base + (nearOne ? FRESNEL_FIT_MU2 : -FRESNEL_FIT_SIN2);
    {f} e4 = 4.0 * eta * eta * kappa2;
    {v2} s = sqrt(t * t + e4);
    {v2} u = s + abs(t);
    {v2} twoA2 = {select_twoA2};
    {v2} twoAMu = 2.0 * FRESNEL_FIT_MU * sqrt(0.5 * twoA2);
    {v2} r = s * FRESNEL_FIT_MU2 + FRESNEL_FIT_SIN2 * FRESNEL_FIT_SIN2;
    return clamp((s + FRESNEL_FIT_MU2 - twoAMu) * r / ((s + FRESNEL_FIT_MU2 + twoAMu) * (r + twoAMu * FRESNEL_FIT_SIN2)),
                 0.0, 1.0);
}}

// Four-point coefficients of (eta, kappa^2), already in range: c0 = F(0) in closed form, c1 = F(90) - c0, then the
// constant 2x2 inverse.
{v4} fresnelCoefficientsEtaKappa2({f} eta, {f} kappa2)
{{
    {f} f0 = ((eta - 1.0) * (eta - 1.0) + kappa2) / ((eta + 1.0) * (eta + 1.0) + kappa2);
    {f} f90 = (eta == 1.0 && kappa2 == 0.0) ? 0.0 : 1.0;
    {v2} rest = fresnelAtFitAngles(eta, kappa2) - f0 - (f90 - f0) * FRESNEL_FIT_B1;
    return {v4}(f0, f90 - f0, dot(FRESNEL_FIT_INVERSE_0, rest), dot(FRESNEL_FIT_INVERSE_1, rest));
}}

// Four-point coefficients of one channel's (eta, kappa).
{v4} fresnelCoefficientsNK({f} eta, {f} kappa)
{{
    kappa = fresnelSanitize(kappa, 0.0, 0.0, 1e4);
    return fresnelCoefficientsEtaKappa2(fresnelSanitize(eta, 1.5, 1e-4, 1e4), kappa * kappa);
}}

// Gulbrandsen's (r, g) -> (eta, kappa^2) (JCGT 2014, eq. 7-9), with q = sqrt(r): kappa^2 = (r (n + 1)^2 - (n - 1)^2)
// / (1 - r) factored exactly into g (n_max - n_min)(n - 1/n_max), sums of positive terms (no float32 cancellation).
{v2} fresnelGulbrandsenToEtaKappa2({f} r, {f} g)
{{
    r = fresnelSanitize(r, 0.0, 0.0, 0.9999);
    g = fresnelSanitize(g, 0.0, 0.0, 1.0);
    {f} q = sqrt(r);
    {f} over1pr = 1.0 / (1.0 + r), over1mq = 1.0 / (1.0 - q), over1pq = 1.0 / (1.0 + q);  // 1/(1 - r) = their product
    {f} n = g * (1.0 - r) * over1pr + (1.0 - g) * (1.0 + q) * over1mq;
    {f} spread = 2.0 * q * (1.0 + q) * over1mq * over1pr;
    {f} above = g * 2.0 * q * (1.0 - q) * over1pr * over1pq + (1.0 - g) * 4.0 * q * over1mq * over1pq;
    return {v2}(n, g * spread * above);
}}

{v4} fresnelCoefficientsGulbrandsen({f} r, {f} g)
{{
    {v2} nk2 = fresnelGulbrandsenToEtaKappa2(r, g);
    return fresnelCoefficientsEtaKappa2(nk2.x, nk2.y);
}}

// Linear artist models: c = w0 P_scale + w1 P_bias + w2 P_dip (the projections of their fixed functions).
{v4} fresnelCoefficientsLinear({f} w0, {f} w1, {f} w2)
{{
    return w0 * FRESNEL_PROJECTION_SCALE + w1 * FRESNEL_PROJECTION_BIAS + w2 * FRESNEL_PROJECTION_DIP;
}}

{const} {f} FRESNEL_F82_SCHLICK_WEIGHT = {_number((1.0 - F82_MU) ** 5)};  // (1 - 1/7)^5
{const} {f} FRESNEL_F82_DIP = {_number(lazanyi_dip(F82_MU))};              // (1/7) (1 - 1/7)^6

{v4} fresnelCoefficientsSchlick({f} f0, {f} f90)
{{
    return fresnelCoefficientsLinear(fresnelSanitize(f0, 0.0, 0.0, 1.0), fresnelSanitize(f90, 0.0, 0.0, 1.0), 0.0);
}}

{v4} fresnelCoefficientsF82({f} f0, {f} f82)
{{
    f0 = fresnelSanitize(f0, 0.0, 0.0, 1.0);
    f82 = fresnelSanitize(f82, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT - f82) / FRESNEL_F82_DIP);
}}

{v4} fresnelCoefficientsF82Tint({f} f0, {f} tint)
{{
    f0 = fresnelSanitize(f0, 0.0, 0.0, 1.0);
    tint = fresnelSanitize(tint, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0,
                                     -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

{v4} fresnelCoefficientsGeneralizedAdobe({f} r0, {f} r90, {f} tint)
{{
    r0 = fresnelSanitize(r0, 0.0, 0.0, 1.0);
    r90 = fresnelSanitize(r90, 0.0, 0.0, 1.0);
    tint = fresnelSanitize(tint, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(r0, r90,
                                     -(r0 + (r90 - r0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

// The curves b_0 .. b_3 at mu = V.H (piecewise polynomials, Horner).
{v4} fresnelBasisCurves({f} mu)
{{
    mu = fresnelSanitize(mu, 1.0, 0.0, 1.0);
    int j = (mu < FRESNEL_CURVE_EDGES.y) ? 0 : ((mu < FRESNEL_CURVE_EDGES.z) ? 1 : 2);
    {f} lo = (j == 0) ? FRESNEL_CURVE_EDGES.x : ((j == 1) ? FRESNEL_CURVE_EDGES.y : FRESNEL_CURVE_EDGES.z);
    {f} hi = (j == 0) ? FRESNEL_CURVE_EDGES.y : ((j == 1) ? FRESNEL_CURVE_EDGES.z : FRESNEL_CURVE_EDGES.w);
    {f} s = 2.0 * (mu - lo) / (hi - lo) - 1.0;
    int base = j * {d + 1};
    {v4} b = FRESNEL_CURVES[base + {d}];
    for (int p = {d - 1}; p >= 0; --p)
    {{
        b = b * s + FRESNEL_CURVES[base + p];
    }}
    return b;
}}

// Fresnel of a punctual light for each colour channel: F(V.H) = sum_k c_k b_k(theta_h).
{v3} fresnelBasisDirect({f} VdotH, {v4} cR, {v4} cG, {v4} cB)
{{
    {v4} b = fresnelBasisCurves(VdotH);
    return {v3}(dot(cR, b), dot(cG, b), dot(cB, b));
}}

// The tables' coordinates (the grid of the build that wrote this include: {c.grid.width} x {c.grid.height}, rows at
// {c.grid.rows}): u = NdotV, v = clamp(r, lo, hi) * scale + offset, so that a change of grid is these constants.
{const} {v4} FRESNEL_LUT_ROWS = {_vector(c.row_mapping, v4)};  // lo, hi, scale, offset
{v2} fresnelBasisLutUV({f} NdotV, {f} perceptualRoughness)
{{
    {f} r = clamp(fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0), FRESNEL_LUT_ROWS.x, FRESNEL_LUT_ROWS.y);
    return {v2}(fresnelSanitize(NdotV, 1.0, 0.0, 1.0), r * FRESNEL_LUT_ROWS.z + FRESNEL_LUT_ROWS.w);
}}

{split_sum}

// The hemispherical average F_avg = sum_k c_k avg(b_k) (multiple-scattering compensation), clamped to [0, 1].
{v3} fresnelBasisAverage({v4} cR, {v4} cG, {v4} cB)
{{
    return clamp({v3}(dot(cR, FRESNEL_BASIS_AVERAGES), dot(cG, FRESNEL_BASIS_AVERAGES), dot(cB, FRESNEL_BASIS_AVERAGES)),
                 0.0, 1.0);
}}

// All three channels at once, for (eta, kappa) and (r, g) texture reads.
void fresnelCoefficientsNK3({v3} eta, {v3} kappa, out {v4} cR, out {v4} cG, out {v4} cB)
{{
    cR = fresnelCoefficientsNK(eta.x, kappa.x);
    cG = fresnelCoefficientsNK(eta.y, kappa.y);
    cB = fresnelCoefficientsNK(eta.z, kappa.z);
}}

void fresnelCoefficientsGulbrandsen3({v3} r, {v3} g, out {v4} cR, out {v4} cG, out {v4} cB)
{{
    cR = fresnelCoefficientsGulbrandsen(r.x, g.x);
    cG = fresnelCoefficientsGulbrandsen(r.y, g.y);
    cB = fresnelCoefficientsGulbrandsen(r.z, g.z);
}}
"""
    )


def glsl_include(constants: ShaderConstants, command: str) -> str:
    return _glsl(constants, command)


def hlsl_include(constants: ShaderConstants, command: str) -> str:
    return _glsl(constants, command, hlsl=True)


def wgsl_include(constants: ShaderConstants, command: str) -> str:
    """The same functions in WGSL (no NaN test by x != x either: the bits are tested through bitcast)."""
    c, d = constants, constants.curve_degree
    polynomial = c.curve_polynomials.reshape(-1, 4)
    rows = ",\n".join("    " + _vector(row, "vec4f") for row in polynomial)
    return (
        _header(c, "WGSL", command)
        + f"""
const FRESNEL_BASIS_HASH: u32 = 0x{c.basis_hash[:8]}u;  // the first 8 hex digits of {c.basis_hash}
const FRESNEL_FIT_MU = {_vector(c.fit_mu, "vec2f")};
const FRESNEL_FIT_MU2 = {_vector(c.fit_mu**2, "vec2f")};
const FRESNEL_FIT_SIN2 = {_vector((1.0 - c.fit_mu) * (1.0 + c.fit_mu), "vec2f")};
const FRESNEL_FIT_B1 = {_vector(c.fit_b1, "vec2f")};
const FRESNEL_FIT_INVERSE_0 = {_vector(c.inverse[0], "vec2f")};
const FRESNEL_FIT_INVERSE_1 = {_vector(c.inverse[1], "vec2f")};
const FRESNEL_PROJECTION_SCALE = {_vector(c.projections[0], "vec4f")};
const FRESNEL_PROJECTION_BIAS = {_vector(c.projections[1], "vec4f")};
const FRESNEL_PROJECTION_DIP = {_vector(c.projections[2], "vec4f")};
const FRESNEL_BASIS_AVERAGES = {_vector(c.averages, "vec4f")};
const FRESNEL_CURVE_EDGES = {_vector(CURVE_SEGMENTS, "vec4f")};
const FRESNEL_CURVE_DEGREE: i32 = {d};
const FRESNEL_F82_SCHLICK_WEIGHT: f32 = {_number((1.0 - F82_MU) ** 5)};
const FRESNEL_F82_DIP: f32 = {_number(lazanyi_dip(F82_MU))};
var<private> FRESNEL_CURVES: array<vec4f, {polynomial.shape[0]}> = array<vec4f, {polynomial.shape[0]}>(
{rows}
);

fn fresnelSanitize(x: f32, fallback: f32, lo: f32, hi: f32) -> f32 {{
    return select(clamp(x, lo, hi), fallback, (bitcast<u32>(x) & 0x7fffffffu) > 0x7f800000u);
}}

fn fresnelExact(mu: f32, eta: f32, kappa: f32) -> f32 {{
    let mu2 = mu * mu;
    let sin2 = (1.0 - mu) * (1.0 + mu);
    let nearOne = abs(eta - 1.0) < 0.5;
    let t = select(eta * eta, (eta - 1.0) * (eta + 1.0), nearOne) - kappa * kappa + select(-sin2, mu2, nearOne);
    let fourEta2Kappa2 = 4.0 * (eta * kappa) * (eta * kappa);
    let s = sqrt(t * t + fourEta2Kappa2);
    let u = s + abs(t);
    let twoA2 = select(select(0.0, fourEta2Kappa2 / u, u > 0.0), u, t >= 0.0);
    let twoAMu = 2.0 * mu * sqrt(0.5 * twoA2);
    let fsDen = s + mu2 + twoAMu;
    let fs = select(select(1.0, 0.0, eta == 1.0 && kappa == 0.0), (s + mu2 - twoAMu) / fsDen, fsDen > 0.0);
    let r = s * mu2 + sin2 * sin2;
    let ratioDen = r + twoAMu * sin2;
    let ratio = select(1.0, (r - twoAMu * sin2) / ratioDen, ratioDen > 0.0);
    return clamp(0.5 * fs * (1.0 + ratio), 0.0, 1.0);
}}

fn fresnelAtFitAngles(eta: f32, kappa2: f32) -> vec2f {{
    let nearOne = abs(eta - 1.0) < 0.5;
    let base = select(eta * eta, (eta - 1.0) * (eta + 1.0), nearOne) - kappa2;
    let t = base + select(-FRESNEL_FIT_SIN2, FRESNEL_FIT_MU2, nearOne);
    let e4 = 4.0 * eta * eta * kappa2;
    let s = sqrt(t * t + e4);
    let u = s + abs(t);
    let twoA2 = select(e4 / u, u, t >= vec2f(0.0));
    let twoAMu = 2.0 * FRESNEL_FIT_MU * sqrt(0.5 * twoA2);
    let r = s * FRESNEL_FIT_MU2 + FRESNEL_FIT_SIN2 * FRESNEL_FIT_SIN2;
    return clamp((s + FRESNEL_FIT_MU2 - twoAMu) * r / ((s + FRESNEL_FIT_MU2 + twoAMu) * (r + twoAMu * FRESNEL_FIT_SIN2)),
                 vec2f(0.0), vec2f(1.0));
}}

fn fresnelCoefficientsEtaKappa2(eta: f32, kappa2: f32) -> vec4f {{
    let f0 = ((eta - 1.0) * (eta - 1.0) + kappa2) / ((eta + 1.0) * (eta + 1.0) + kappa2);
    let f90 = select(1.0, 0.0, eta == 1.0 && kappa2 == 0.0);
    let rest = fresnelAtFitAngles(eta, kappa2) - f0 - (f90 - f0) * FRESNEL_FIT_B1;
    return vec4f(f0, f90 - f0, dot(FRESNEL_FIT_INVERSE_0, rest), dot(FRESNEL_FIT_INVERSE_1, rest));
}}

fn fresnelCoefficientsNK(etaIn: f32, kappaIn: f32) -> vec4f {{
    let kappa = fresnelSanitize(kappaIn, 0.0, 0.0, 1e4);
    return fresnelCoefficientsEtaKappa2(fresnelSanitize(etaIn, 1.5, 1e-4, 1e4), kappa * kappa);
}}

fn fresnelGulbrandsenToEtaKappa2(rIn: f32, gIn: f32) -> vec2f {{
    let r = fresnelSanitize(rIn, 0.0, 0.0, 0.9999);
    let g = fresnelSanitize(gIn, 0.0, 0.0, 1.0);
    let q = sqrt(r);
    let over1pr = 1.0 / (1.0 + r);
    let over1mq = 1.0 / (1.0 - q);
    let over1pq = 1.0 / (1.0 + q);
    let n = g * (1.0 - r) * over1pr + (1.0 - g) * (1.0 + q) * over1mq;
    let spread = 2.0 * q * (1.0 + q) * over1mq * over1pr;
    let above = g * 2.0 * q * (1.0 - q) * over1pr * over1pq + (1.0 - g) * 4.0 * q * over1mq * over1pq;
    return vec2f(n, g * spread * above);
}}

fn fresnelCoefficientsGulbrandsen(r: f32, g: f32) -> vec4f {{
    let nk2 = fresnelGulbrandsenToEtaKappa2(r, g);
    return fresnelCoefficientsEtaKappa2(nk2.x, nk2.y);
}}

fn fresnelCoefficientsLinear(w0: f32, w1: f32, w2: f32) -> vec4f {{
    return w0 * FRESNEL_PROJECTION_SCALE + w1 * FRESNEL_PROJECTION_BIAS + w2 * FRESNEL_PROJECTION_DIP;
}}

fn fresnelCoefficientsSchlick(f0: f32, f90: f32) -> vec4f {{
    return fresnelCoefficientsLinear(fresnelSanitize(f0, 0.0, 0.0, 1.0), fresnelSanitize(f90, 0.0, 0.0, 1.0), 0.0);
}}

fn fresnelCoefficientsF82(f0In: f32, f82In: f32) -> vec4f {{
    let f0 = fresnelSanitize(f0In, 0.0, 0.0, 1.0);
    let f82 = fresnelSanitize(f82In, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT - f82) / FRESNEL_F82_DIP);
}}

fn fresnelCoefficientsF82Tint(f0In: f32, tintIn: f32) -> vec4f {{
    let f0 = fresnelSanitize(f0In, 0.0, 0.0, 1.0);
    let tint = fresnelSanitize(tintIn, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

fn fresnelCoefficientsGeneralizedAdobe(r0In: f32, r90In: f32, tintIn: f32) -> vec4f {{
    let r0 = fresnelSanitize(r0In, 0.0, 0.0, 1.0);
    let r90 = fresnelSanitize(r90In, 0.0, 0.0, 1.0);
    let tint = fresnelSanitize(tintIn, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(r0, r90, -(r0 + (r90 - r0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

fn fresnelBasisCurves(muIn: f32) -> vec4f {{
    let mu = fresnelSanitize(muIn, 1.0, 0.0, 1.0);
    let j = select(select(2, 1, mu < FRESNEL_CURVE_EDGES.z), 0, mu < FRESNEL_CURVE_EDGES.y);
    let lo = select(select(FRESNEL_CURVE_EDGES.z, FRESNEL_CURVE_EDGES.y, j == 1), FRESNEL_CURVE_EDGES.x, j == 0);
    let hi = select(select(FRESNEL_CURVE_EDGES.w, FRESNEL_CURVE_EDGES.z, j == 1), FRESNEL_CURVE_EDGES.y, j == 0);
    let s = 2.0 * (mu - lo) / (hi - lo) - 1.0;
    let base = j * {d + 1};
    var b = FRESNEL_CURVES[base + {d}];
    for (var p: i32 = {d - 1}; p >= 0; p = p - 1) {{
        b = b * s + FRESNEL_CURVES[base + p];
    }}
    return b;
}}

fn fresnelBasisDirect(VdotH: f32, cR: vec4f, cG: vec4f, cB: vec4f) -> vec3f {{
    let b = fresnelBasisCurves(VdotH);
    return vec3f(dot(cR, b), dot(cG, b), dot(cB, b));
}}

const FRESNEL_LUT_ROWS = {_vector(c.row_mapping, "vec4f")};  // lo, hi, scale, offset ({c.grid.width} x {c.grid.height}, rows at {c.grid.rows})

fn fresnelBasisLutUV(NdotV: f32, perceptualRoughness: f32) -> vec2f {{
    let r = clamp(fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0), FRESNEL_LUT_ROWS.x, FRESNEL_LUT_ROWS.y);
    return vec2f(fresnelSanitize(NdotV, 1.0, 0.0, 1.0), r * FRESNEL_LUT_ROWS.z + FRESNEL_LUT_ROWS.w);
}}

fn fresnelBasisSplitSumUV(lut: texture_2d<f32>, linearClamp: sampler, NdotV: f32, r: f32, cR: vec4f, cG: vec4f,
                          cB: vec4f) -> vec3f {{
    let b = textureSampleLevel(lut, linearClamp, fresnelBasisLutUV(NdotV, r), 0.0);
    return vec3f(dot(cR, b), dot(cG, b), dot(cB, b));
}}

fn fresnelBasisAverage(cR: vec4f, cG: vec4f, cB: vec4f) -> vec3f {{
    return clamp(vec3f(dot(cR, FRESNEL_BASIS_AVERAGES), dot(cG, FRESNEL_BASIS_AVERAGES), dot(cB, FRESNEL_BASIS_AVERAGES)),
                 vec3f(0.0), vec3f(1.0));
}}
"""
    )


#: Registry: language → (file name, generator(constants, command) → text) of the generated includes.
SHADER_INCLUDES: dict[str, tuple[str, Callable[[ShaderConstants, str], str]]] = {
    "glsl": ("fresnel_basis_material.glsl", glsl_include),
    "hlsl": ("fresnel_basis_material.hlsl", hlsl_include),
    "wgsl": ("fresnel_basis_material.wgsl", wgsl_include),
}


def shader_includes(
    basis: Basis | None = None, command: str = "fresnel-lut build", grid: LutGrid | None = None
) -> list[tuple[str, str]]:
    """(file name, text) of every generated include for ``basis`` (default: the shipped one) and its tables' grid."""
    constants = shader_constants(basis, grid)
    return [(name, generate(constants, command)) for name, generate in SHADER_INCLUDES.values()]
