"""The shaders' arithmetic in Python, operation for operation (in float64): engines' CPU tools get the numbers the GPU
computes, and the tests compare the two.

Public objects: ``sanitize_nk``, ``sanitize_gulbrandsen``, ``sanitize_unit``, ``bits_clamp``, ``coefficients_per_pixel_nk``,
``coefficients_per_pixel_gulbrandsen``, ``coefficients_per_pixel_gulbrandsen_table``, ``coefficients_per_pixel_nk_table``,
``coefficients_per_pixel_model``,
``direct_fresnel``, ``direct_fresnel_table``, ``lut_coordinates``,
``ltc_coordinates``, ``rect_light_specular``, ``rect_light_punctual``, ``linear_rect_light_specular``, ``linear_model_curve``, ``linear_weights``, ``linear_split_sum``,
``linear_direct``.

* **(η, κ) per pixel** (Belcour 2020, "Coefficients"): c0 = F(0°) in closed form, c1 = F(90°) − c0 (F(90°) = 1 but
  for η = 1, κ = 0), (c2 … c_(K−1)) = S⁻¹ (F(θ_i) − c0 − c1 b1(θ_i)) with the exact Fresnel equations (Hoffman
  2020, "1823: Fresnel's Equations") at the K − 2 fit angles: for the shipped basis two Fresnel evaluations (one
  vec2) and a constant 2 × 2 product.
* **Gulbrandsen (r, g)** → (η, κ) in closed form (Gulbrandsen 2014, eq. 7–9) → the same solve; or c0 = r, c1 = 1 − r
  and the rest from one bilinear fetch of the coefficient table (:mod:`basis.coefficient_table`).
* **Linear artist models** (Schlick F0/F90; Hoffman 2019's F82; the F82 tint of Adobe, OpenPBR's
  ``specular_color`` and MaterialX's ``color82``, Hoffman 2023 eq. 3; Hoffman 2023's generalised Adobe with
  p = 5, eq. 6): F = Σ_n w_n t_n(μ) with t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶), so c = Σ_n w_n P_n with P_n the
  four-point coefficients of t_n, three generated constants; w is a few flops of the parameters. The projection
  is of the models' unclamped linear form (they agree with ``coefficients_from_model`` wherever the model's clamp
  to [0, 1] is inactive at the fit angles).

Inputs are sanitised as the shaders do (:func:`sanitize_nk`, :func:`sanitize_gulbrandsen`, :func:`sanitize_unit`):
NaN becomes the documented fallback, everything else is clamped into the documented range, so no texel value gives
NaN or inf.
"""

from __future__ import annotations

import numpy as np

from basis.coefficient_table import coefficients_from_coefficient_table
from basis.models.formulas import adobe_dip_weight, f82_dip_weight
from basis.validation import ParameterError, as_float_array, check_choice, check_range
from preintegrate.ltc import ltc_grid, rect_light_fresnel, rect_light_half_cosine
from preintegrate.multiple_scattering import weigh_schlick_texels

from ..shipped import COEFFICIENT_LUT_TERMS
from .constants import (
    ETA_LIMITS,
    KAPPA_LIMITS,
    PER_PIXEL_MODELS,
    REFLECTIVITY_LIMITS,
    ShaderConstants,
    linear_functions,
    segment_map,
    shader_constants,
    warped_cosine,
)

__all__ = [
    "bits_clamp",
    "coefficients_per_pixel_gulbrandsen",
    "coefficients_per_pixel_gulbrandsen_table",
    "coefficients_per_pixel_model",
    "coefficients_per_pixel_nk",
    "coefficients_per_pixel_nk_table",
    "direct_fresnel",
    "direct_fresnel_table",
    "linear_direct",
    "linear_model_curve",
    "linear_split_sum",
    "linear_weights",
    "ltc_coordinates",
    "lut_coordinates",
    "linear_rect_light_specular",
    "rect_light_punctual",
    "rect_light_specular",
    "sanitize_gulbrandsen",
    "sanitize_nk",
    "sanitize_unit",
]


def sanitize_unit(value, fallback: float = 0.0, low: float = 0.0, high: float = 1.0) -> np.ndarray:
    """A texel value as the shaders read it: NaN → ``fallback``, else clamped to [low, high] (±inf to the ends)."""
    value = as_float_array("value", value, finite=False)
    return np.where(np.isnan(value), fallback, np.clip(value, low, high))


def bits_clamp(value, low: float, high: float) -> np.ndarray:
    """``fresnelBitsClamp`` (and ``fresnelUnitClamp``, low = 0): clamped to [low, high], 0 ≤ low < high, as one
    integer clamp of the float's bits does it: NaN → ``high`` or ``low`` by its sign bit, −0 and negatives → ``low``,
    +inf → ``high``."""
    value = as_float_array("value", value, finite=False)
    return np.where(np.isnan(value), np.where(np.signbit(value), low, high), np.clip(value, low, high))


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
    if constants.grazing_fit_angles:
        t = (eta - 1.0) * (eta + 1.0) - kappa2 + mu2
    else:
        near_one = np.abs(eta - 1.0) < 0.5
        t = np.where(near_one, (eta - 1.0) * (eta + 1.0), eta * eta) - kappa2 + np.where(near_one, mu2, -sin2)
    e4 = 4.0 * eta * eta * kappa2
    s = np.sqrt(t * t + e4)
    u = s + np.abs(t)
    with np.errstate(divide="ignore", invalid="ignore"):
        two_a2 = np.where(t >= 0.0, u, e4 / u)
    two_a_mu = np.sqrt(2.0) * mu * np.sqrt(two_a2)
    r = s * mu2 + sin2 * sin2
    return (s + mu2 - two_a_mu) * r / ((s + mu2 + two_a_mu) * (r + two_a_mu * sin2))


def coefficients_per_pixel_nk(eta, kappa, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 4) coefficients of (η, κ) texels, as ``fresnelCoefficientsNK`` computes them (inputs sanitised)."""
    eta, kappa = sanitize_nk(eta, kappa)
    return _coefficients_eta_kappa2(*np.broadcast_arrays(eta, kappa * kappa), constants)


def _coefficients_eta_kappa2(eta: np.ndarray, kappa2: np.ndarray, constants: ShaderConstants | None) -> np.ndarray:
    """``fresnelCoefficientsEtaKappa2``: the K-point solve of (η, κ²) in range, F(0) in closed form."""
    return _coefficients_solve(((eta - 1.0) ** 2 + kappa2) / ((eta + 1.0) ** 2 + kappa2), eta, kappa2, constants)


def _coefficients_solve(
    f0: np.ndarray, eta: np.ndarray, kappa2: np.ndarray, constants: ShaderConstants | None
) -> np.ndarray:
    """``fresnelCoefficientsSolve``: c0 = F(0) = ``f0``, c1 = F(90°) − c0, the rest through the constant inverse."""
    constants = shader_constants() if constants is None else constants
    f90 = np.where((eta == 1.0) & (kappa2 == 0.0), 0.0, 1.0)
    samples = _fresnel_at_fit_angles(eta, kappa2, constants)  # (…, 2)
    rest = samples - f0[..., None] - (f90 - f0)[..., None] * constants.fit_b1
    c23 = rest @ constants.inverse.T
    return np.concatenate([f0[..., None], (f90 - f0)[..., None], c23], axis=-1)


def _gulbrandsen_eta_kappa2(reflectivity: np.ndarray, edge_tint: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Gulbrandsen 2014 eq. 7-9 as the shaders write it. With q = √r, n = g n_min + (1 − g) n_max and
    κ² = (r (n + 1)² − (n − 1)²)/(1 − r) factors exactly into g (n_max − n_min)(n − 1/n_max), each factor a sum of
    positive terms: n_max − n_min = 2q (1 + q)/((1 − q)(1 + r)), n − 1/n_max = g 2q (1 − q)/((1 + r)(1 + q))
    + (1 − g) 4q/(1 − r), whose product is 4 g r/((1 + r)(1 − q)) (g (1 − q)/(1 + r) + 2 (1 − g)/(1 − q)): two
    reciprocals. Float32 then holds κ where the textbook form cancels (r → 0 with g → 1: 6e-4 in c2), and
    n_max = (1 + q)/(1 − q) holds n − 1 (which F depends on as r → 0) to a few ulps: (1 + q)²/(1 − r) misses the
    Fresnel curve by 5.9e-7 at r = 1e-7 in float32, this by 3.4e-7 at worst."""
    g, r = edge_tint, reflectivity
    q = np.sqrt(r)
    over_1pr, over_1mq = 1.0 / (1.0 + r), 1.0 / (1.0 - q)
    eta = g * (1.0 - r) * over_1pr + (1.0 - g) * (1.0 + q) * over_1mq
    return eta, 4.0 * g * r * over_1pr * over_1mq * (g * (1.0 - q) * over_1pr + 2.0 * (1.0 - g) * over_1mq)


def coefficients_per_pixel_gulbrandsen(reflectivity, edge_tint, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 4) coefficients of (r, g) texels, as ``fresnelCoefficientsGulbrandsen`` computes them."""
    reflectivity, edge_tint = np.broadcast_arrays(*sanitize_gulbrandsen(reflectivity, edge_tint))
    # Gulbrandsen's mapping is built so that F(0) = r: the shaders skip the closed form
    return _coefficients_solve(reflectivity, *_gulbrandsen_eta_kappa2(reflectivity, edge_tint), constants)


def coefficients_per_pixel_gulbrandsen_table(
    table, reflectivity, edge_tint, constants: ShaderConstants | None = None, weight_bits: int | None = None
) -> np.ndarray:
    """(…, K) coefficients of (r, g) texels read from the coefficient table (H, W, K − 1) as
    ``fresnelCoefficientsGulbrandsenTable`` reads it (exact bilinear weights, or rounded to ``weight_bits`` as GPUs
    that filter with 8-bit weights round them); a basis of more than five terms, which has no table, solves as the
    include does (and a two-term basis reads nothing: ``table`` may be None for both)."""
    constants = shader_constants() if constants is None else constants
    reflectivity, edge_tint = np.broadcast_arrays(
        bits_clamp(reflectivity, *REFLECTIVITY_LIMITS), bits_clamp(edge_tint, 0.0, 1.0)
    )
    if constants.n_terms == 2:  # c0 and c1 alone: nothing to read
        return np.stack([reflectivity, np.where(reflectivity > 0.0, 1.0 - reflectivity, 0.0)], axis=-1)
    if constants.n_terms not in COEFFICIENT_LUT_TERMS:
        return coefficients_per_pixel_gulbrandsen(reflectivity, edge_tint, constants)
    table = as_float_array("table", table)
    if table.ndim != 3 or table.shape[-1] != constants.n_terms - 1:
        raise ParameterError(f"table must be (H, W, {constants.n_terms - 1}) for this basis, got {table.shape}")
    return coefficients_from_coefficient_table(table, reflectivity, edge_tint, weight_bits)


def linear_weights(model: str, **parameters) -> np.ndarray:
    """(…, 3) weights w of t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶) of a model of :data:`PER_PIXEL_MODELS`, each
    parameter a number or array sanitised to [0, 1] (NaN → 0), as ``fresnelLinear<Model>`` computes them: the
    Schlick table's (R, G, A) times w is the model's exact split sum.

    >>> linear_weights("f82-tint", f0=0.9, tint=0.5).round(4).tolist()
    [0.9, 1.0, -8.3515]
    """
    check_choice("model", model, list(PER_PIXEL_MODELS))
    names = PER_PIXEL_MODELS[model][0]
    if set(parameters) != set(names):
        raise ParameterError(f"model {model!r} takes {list(names)}, got {sorted(parameters)}")
    clean = {name: sanitize_unit(parameters[name]) for name in names}
    # the dip weights a are the model registry's own formulas (basis.models.formulas), which the shaders' constants
    # FRESNEL_F82_SCHLICK_WEIGHT and FRESNEL_F82_DIP spell out for float32
    if model == "schlick":
        f0, f90 = clean["f0"], clean["f90"]
        return np.stack(np.broadcast_arrays(f0, f90, np.zeros_like(f0)), axis=-1)
    if model == "f82":  # Hoffman 2019 eq. 4
        f0 = clean["f0"]
        return np.stack(np.broadcast_arrays(f0, np.ones_like(f0), -f82_dip_weight(f0, clean["f82"])), axis=-1)
    if model == "f82-tint":  # Hoffman 2023 eq. 3
        f0 = clean["f0"]
        return np.stack(np.broadcast_arrays(f0, np.ones_like(f0), -adobe_dip_weight(f0, clean["tint"])), axis=-1)
    r0, r90, tint = clean["r0"], clean["r90"], clean["tint"]  # Hoffman 2023 eq. 6, p = 5
    return np.stack(np.broadcast_arrays(r0, r90, -adobe_dip_weight(r0, tint, r90)), axis=-1)


def _table_texels(name: str, table, n_dot_v, roughness, constants: ShaderConstants) -> np.ndarray:
    """The texels of a table on the include's grid as ``fresnelBasisLutUV`` reads them: (NdotV, r) sanitised, r
    clamped to the grid's rows (a scene's cropped rows), bilinear."""
    low, high, _, _ = constants.grid.row_mapping
    roughness = np.clip(sanitize_unit(roughness, 0.5), low, high)
    return constants.grid.lookup(as_float_array(name, table), sanitize_unit(n_dot_v, 1.0), roughness)


def linear_split_sum(schlick_table, n_dot_v, roughness, weights, constants=None, multiple_scattering=False):
    """(…, 3) ``fresnelLinearSplitSum`` (or ``fresnelLinearMultipleScattering``) of weights (…, 3, 3), one w per
    colour channel, from the Schlick table (H, W, 4) read bilinearly at the include's coordinates
    (:func:`preintegrate.multiple_scattering.weigh_schlick_texels` with no weight on B)."""
    constants = shader_constants() if constants is None else constants
    texels = _table_texels("schlick_table", schlick_table, n_dot_v, roughness, constants)
    weights = as_float_array("weights", weights)
    on_table = np.insert(weights, 2, 0.0, axis=-1)  # R, G, (B = E), A
    return weigh_schlick_texels(on_table, texels, multiple_scattering)


def linear_direct(weights, v_dot_h) -> np.ndarray:
    """(…, 3) ``fresnelLinearDirect``: F(V·H) = Σ_n w_n t_n(μ) per colour channel, weights (…, 3, 3), clamped to
    [0, 1] as the models are (:func:`basis.models.formulas.fresnel_Hoffman2019`)."""
    terms = linear_functions(sanitize_unit(v_dot_h, 1.0))[..., None, :]
    return np.clip(np.sum(as_float_array("weights", weights) * terms, axis=-1), 0.0, 1.0)


def coefficients_per_pixel_nk_table(
    table, eta, kappa, constants: ShaderConstants | None = None, weight_bits: int | None = None
) -> np.ndarray:
    """(…, K) coefficients of (η, κ) texels through Gulbrandsen's (r, g) and the coefficient table, as
    ``fresnelCoefficientsNKTable`` computes them: r = F(0) (at most 0.9999), g = (1 + q − η (1 − q))(1 + r) /
    (2 q (1 + q)), q = √r (:func:`basis.gulbrandsen.nk_to_gulbrandsen`'s g without its cancellation), clamped to
    [0, 1]; 0 at r = 0."""
    eta, kappa = np.broadcast_arrays(bits_clamp(eta, *ETA_LIMITS), bits_clamp(kappa, *KAPPA_LIMITS))
    kappa2 = kappa * kappa
    r = np.minimum(((eta - 1.0) ** 2 + kappa2) / ((eta + 1.0) ** 2 + kappa2), REFLECTIVITY_LIMITS[1])
    q = np.sqrt(r)
    with np.errstate(divide="ignore", invalid="ignore"):
        g = np.where(q > 0.0, (1.0 + q - eta * (1.0 - q)) * (1.0 + r) / (2.0 * q * (1.0 + q)), 0.0)
    return coefficients_per_pixel_gulbrandsen_table(table, r, np.clip(g, 0.0, 1.0), constants, weight_bits)


def direct_fresnel_table(table, coefficients, v_dot_h, weight_bits: int | None = None) -> np.ndarray:
    """``fresnelBasisDirectTable``: F(V·H) = c0 + Σ_k c_k t_k with t the curve table (1, W, K − 1) read linearly at
    V·H (through :func:`bits_clamp`) on its end points (the filter weight rounded to ``weight_bits`` if given):
    coefficients (…, K), V·H (…) → (…)."""
    table = as_float_array("table", table)
    coefficients = as_float_array("coefficients", coefficients)
    if table.ndim != 3 or table.shape[0] != 1 or table.shape[-1] != coefficients.shape[-1] - 1:
        raise ParameterError(f"table must be (1, W, {coefficients.shape[-1] - 1}), got {table.shape}")
    position = bits_clamp(v_dot_h, 0.0, 1.0) * (table.shape[1] - 1)
    left = np.minimum(np.floor(position).astype(int), table.shape[1] - 2)
    weight = (position - left)[..., None]
    if weight_bits is not None:
        weight = np.round(weight * 2.0**weight_bits) / 2.0**weight_bits
    read = table[0, left] * (1.0 - weight) + table[0, left + 1] * weight
    curves = np.concatenate([np.ones(read.shape[:-1] + (1,)), read], axis=-1)
    return np.sum(coefficients * curves, axis=-1)


def coefficients_per_pixel_model(model: str, constants: ShaderConstants | None = None, **parameters) -> np.ndarray:
    """(…, 4) coefficients of a linear artist model of :data:`PER_PIXEL_MODELS` (each parameter a number or array in
    [0, 1], NaN → 0), as the generated ``fresnelCoefficients…`` functions compute them: Σ_n w_n P_n."""
    constants = shader_constants() if constants is None else constants
    return linear_weights(model, **parameters) @ constants.projections


def lut_coordinates(n_dot_v, roughness, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 2) texture coordinates (u, v) of (NdotV, r) on the tables' grid, as ``fresnelBasisLutUV`` computes them."""
    constants = shader_constants() if constants is None else constants
    return constants.grid.texture_coordinates(sanitize_unit(n_dot_v, 1.0), sanitize_unit(roughness, 0.5))


def ltc_coordinates(n_dot_v, roughness, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 2) texture coordinates of (NdotV, r) on the LTC table, as ``fresnelLtcUV`` computes them."""
    constants = shader_constants() if constants is None else constants
    return ltc_grid(constants.ltc_size).texture_coordinates(sanitize_unit(n_dot_v, 1.0), sanitize_unit(roughness, 0.5))


def _rect_light(ltc_table, normal, view, position, corners, roughness, albedo_of, constants):
    """(LTC integral (…), V·H* (…), r' (…), table texels (…, C)) as ``fresnelLtcRectLight`` and ``fresnelLtcVdotH``
    compute them (:func:`preintegrate.ltc.rect_light_half_cosine`), the integral toward the lobe's limit with E =
    ``albedo_of(n_dot_v, roughness)``, which returns (E (…), the table's texels)."""
    normal, view = as_float_array("normal", normal), as_float_array("view", view)
    n_dot_v = np.clip(np.sum(normal * view, axis=-1), 0.0, 1.0)
    sine = np.linalg.norm(np.cross(normal, view), axis=-1)
    roughness = sanitize_unit(roughness, 0.5)
    albedo, texels = albedo_of(n_dot_v, roughness)
    stored = ltc_grid(constants.ltc_size).lookup(ltc_table, n_dot_v, roughness, sine)
    integral, v_dot_h, spread = rect_light_half_cosine(stored, normal, view, position, corners, roughness, albedo)
    return integral, v_dot_h, spread, texels


def rect_light_specular(
    ltc_table, basis_table, normal, view, position, corners, roughness, coefficients, constants=None
) -> np.ndarray:
    """(…, 3) ``fresnelBasisRectLight``: the LTC integral of the quad ``corners`` (…, 4, 3) seen from ``position``
    with ``normal`` and ``view`` (…, 3), read from ``ltc_table`` (the LTC table, :mod:`preintegrate.ltc`), times
    E mix(F̃, F̄ / E, w): F̄ = Σ_k c_k b̄_k of ``basis_table`` (H, W, K) for ``coefficients`` (…, 3, K), E = b̄0, F̃ F
    averaged over the light (:func:`rect_light_punctual` at V·H* and r', preintegrate.ltc.punctual_roughness), w the
    integral, itself taken toward the lobe's punctual limit with E — bilinear fetches as a GPU makes them."""
    constants = shader_constants() if constants is None else constants

    def albedo_of(n_dot_v, roughness):
        terms = _table_texels("basis_table", basis_table, n_dot_v, roughness, constants)
        return terms[..., 0], terms

    integral, v_dot_h, spread, terms = _rect_light(
        ltc_table, normal, view, position, corners, roughness, albedo_of, constants
    )
    coefficients = as_float_array("coefficients", coefficients)
    average = np.einsum("...ck,...k->...c", coefficients, terms)
    punctual = terms[..., :1] * rect_light_punctual(basis_table, coefficients, v_dot_h, constants, spread)
    return rect_light_fresnel(integral, average, punctual)


def rect_light_punctual(basis_table, coefficients, v_dot_h, constants=None, spread=0.0) -> np.ndarray:
    """(…, 3) F̃ of ``fresnelBasisRectLight`` for coefficients (…, 3, K): F averaged over a GGX lobe of perceptual
    roughness ``spread`` r' (…, in [0, 1]; 0, the default, is F(V·H*) itself) seen at ``v_dot_h``, the split sum of
    ``basis_table`` at (V·H*, r') over its albedo there, bilinear as a GPU reads it (``fresnelBasisSmoothed``), where
    its grid holds the mirror row (:attr:`preintegrate.lut.LutGrid.holds_mirror`: there, at r' = 0, the split sum is
    the curve itself); else F(V·H*) from the direct-light polynomial (:func:`direct_fresnel`), r' left out."""
    constants = shader_constants() if constants is None else constants
    coefficients = as_float_array("coefficients", coefficients)
    v_dot_h = as_float_array("v_dot_h", v_dot_h)
    if not constants.grid.holds_mirror:
        return direct_fresnel(coefficients, v_dot_h[..., None], constants)
    spread = np.broadcast_to(check_range("spread", spread, 0.0, 1.0), v_dot_h.shape)
    terms = _table_texels("basis_table", basis_table, v_dot_h, spread, constants)
    return np.einsum("...ck,...k->...c", coefficients, terms) / np.maximum(terms[..., :1], 1e-4)


def linear_rect_light_specular(
    ltc_table, schlick_table, normal, view, position, corners, roughness, weights, constants=None
) -> np.ndarray:
    """(…, 3) ``fresnelLinearRectLight``: as :func:`rect_light_specular` for a linear model's weights (…, 3, 3), with
    its exact split sum and F̃ from the same Schlick table at (V·H*, r') over its B there (``fresnelLinearSmoothed``;
    F(V·H*) itself where the grid does not hold the mirror row), E the table's B."""
    constants = shader_constants() if constants is None else constants

    def albedo_of(n_dot_v, roughness):
        texels = _table_texels("schlick_table", schlick_table, n_dot_v, roughness, constants)
        return texels[..., 2], texels

    integral, v_dot_h, spread, texels = _rect_light(
        ltc_table, normal, view, position, corners, roughness, albedo_of, constants
    )
    weights = as_float_array("weights", weights)
    with_dip = np.insert(weights, 2, 0.0, axis=-1)
    average = weigh_schlick_texels(with_dip, texels, multiple_scattering=False)
    if constants.grid.holds_mirror:
        smoothed = _table_texels("schlick_table", schlick_table, v_dot_h, spread, constants)
        punctual = weigh_schlick_texels(with_dip, smoothed, multiple_scattering=False) * (
            texels[..., 2:3] / np.maximum(smoothed[..., 2:3], 1e-4)
        )
    else:
        punctual = texels[..., 2:3] * linear_direct(weights, v_dot_h)
    return rect_light_fresnel(integral, average, punctual)


def linear_model_curve(model: str, mu, **parameters) -> np.ndarray:
    """F(μ) of a model of :data:`PER_PIXEL_MODELS` in the linear form the shaders project (unclamped), parameters
    sanitised to [0, 1]; μ broadcast against them: what :func:`coefficients_per_pixel_model` approximates."""
    check_choice("model", model, list(PER_PIXEL_MODELS))
    return np.sum(linear_weights(model, **parameters) * linear_functions(sanitize_unit(mu)), axis=-1)


def direct_fresnel(coefficients, v_dot_h, constants: ShaderConstants | None = None) -> np.ndarray:
    """F(V·H) = Σ_k c_k b_k for a punctual light, as ``fresnelBasisDirect`` computes it: coefficients (…, 4) and
    V·H (…) (clamped to [0, 1]) → (…), the curves from the generated polynomials in the warped cosine."""
    constants = shader_constants() if constants is None else constants
    coefficients = as_float_array("coefficients", coefficients)
    x = warped_cosine(sanitize_unit(v_dot_h, 1.0), constants.curve_warp)
    edges = np.asarray(constants.curve_segments)
    segment = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)
    scale, offset = segment_map(edges)
    s = x * scale[segment] + offset[segment]
    polynomials = constants.curve_polynomials[segment]  # (…, degree + 1, K)
    curves = polynomials[..., -1, :]
    for power in range(constants.curve_degree - 1, -1, -1):  # Horner, as the shaders
        curves = curves * s[..., None] + polynomials[..., power, :]
    return np.sum(coefficients * curves, axis=-1)
