"""Multiple-scattering compensation of single-scattering GGX, from the same LUTs, exact in the furnace.

Public objects: ``compensated_albedo``, ``compensate_lookup``, ``basis_albedo``, ``linear_model_albedo``,
``weigh_schlick_texels``, ``schlick_table_averages``, ``average_albedo``.

Single-scattering GGX loses the energy that bounces more than once on the microsurface: its albedo without
Fresnel, E(μo, α) (the Schlick table's B channel), is below 1 at high roughness. Engines add it back with
the Fdez-Agüera (2019) form of Kulla and Conty's (2017) compensation, per colour channel:

    E_ms = 1 − E,   F_ms = F̄_ss F_avg / (1 − E_ms F_avg),   F̄ = F̄_ss + F_ms E_ms,

with F̄_ss the single-scattering split sum and F_avg the hemispherical average of F. Engines take F_avg from
F0; with the basis it is exact for any curve the coefficients fit: F_avg = Σ c_k avg(b_k)
(:attr:`basis.eigenbasis.Basis.hemispherical_averages`, stored in ``basis.json``), and for a linear model
(Schlick with F90, F82, F82 tint, generalised Adobe with p = 5) it is exact in closed form, Σ w_n avg(t_n)
(:func:`schlick_table_averages`; OpenPBR's F_avg = r0 + (r90 − r0)/21 − a/126). In a white furnace
(F = 1: F̄_ss = E, F_avg = 1) the result is 1 exactly.

Kulla and Conty's original lobe, f_ms = (1 − E(μo))(1 − E(μi)) / (π (1 − E_avg)), also needs the
hemispherical average of the albedo, E_avg(α) = 2 ∫₀¹ E(μ, α) μ dμ: :func:`average_albedo`.

References
----------
:cite:`KullaConty2017` C. Kulla, A. Conty, "Revisiting Physically Based Shading at Imageworks", SIGGRAPH 2017
    course notes.
:cite:`FdezAguera2019` C. J. Fdez-Agüera, "A Multiple-Scattering Microfacet Model for Real-Time Image-based
    Lighting", JCGT 8(1), 2019 (the F_ss E_ss + F_ms E_ms form).
"""

from __future__ import annotations

import numpy as np

from basis.eigenbasis import Basis, resolve_basis
from basis.validation import ParameterError, as_float_array, check_broadcast, check_range, check_shape_last

from .channels import schlick_table_channels
from .ggx import roughness_to_alpha
from .lut import lut_lookup
from .quadrature import DEFAULT_ORDER, directional_albedo

__all__ = [
    "average_albedo",
    "basis_albedo",
    "compensate_lookup",
    "compensated_albedo",
    "linear_model_albedo",
    "schlick_table_averages",
    "weigh_schlick_texels",
]

#: Gauss–Legendre nodes in μ for E_avg: μ E(μ) is smooth; 64 nodes agree with 128 to 2.2e-9 over r in [0, 1].
AVERAGE_NODES = 64


def average_albedo(roughness, visibility: str = "height-correlated", order=DEFAULT_ORDER) -> np.ndarray:
    """E_avg(r) = 2 ∫₀¹ E(μ, α(r)) μ dμ (Kulla and Conty 2017), E the GGX albedo without Fresnel, for
    perceptual roughness ``roughness`` (any shape): the 1-D table of their multiple-scattering lobe
    (``luts/ggx_albedo_average.exr``). ``order``: the quadrature of each E."""
    roughness = check_range("roughness", roughness, 0.0, 1.0)
    nodes, weights = np.polynomial.legendre.leggauss(AVERAGE_NODES)
    mu, weights = 0.5 * (nodes + 1.0), 0.5 * weights
    albedo = directional_albedo(
        lambda x: np.ones(x.shape + (1,)),
        mu,
        roughness_to_alpha(roughness)[..., None],
        order=order,
        visibility=visibility,
    )[..., 0]
    return 2.0 * albedo @ (weights * mu)


def compensated_albedo(single_scattering, albedo, average_fresnel) -> np.ndarray:
    """F̄_ss + F_ms E_ms (module docstring): ``single_scattering`` F̄_ss (..., C), ``albedo`` E (...) of GGX
    without Fresnel, ``average_fresnel`` F_avg (..., C), broadcast."""
    single_scattering = as_float_array("single_scattering", single_scattering)
    albedo = check_range("albedo", albedo, 0.0, 1.0)[..., None]
    average_fresnel = check_range("average_fresnel", average_fresnel, 0.0, 1.0)
    check_broadcast(single_scattering=single_scattering, albedo=albedo, average_fresnel=average_fresnel)
    lost = 1.0 - albedo
    return single_scattering + single_scattering * average_fresnel / (1.0 - lost * average_fresnel) * lost


def basis_albedo(
    coefficients,
    mu_o,
    roughness,
    tables: tuple[np.ndarray, np.ndarray],
    basis: Basis | None = None,
    multiple_scattering: bool = True,
) -> np.ndarray:
    """F̄ per colour channel (..., 3) of a material's coefficients (3, K) at (μo, r) from ``tables`` = (basis table,
    Schlick table) of ``basis`` (the shipped ones: :func:`handoff.shipped.shipped_tables`), bilinear as a GPU reads
    them, compensated for multiple scattering unless ``multiple_scattering`` is False."""
    basis = resolve_basis(basis)
    coefficients = check_shape_last("coefficients", as_float_array("coefficients", coefficients), basis.n_terms)
    if coefficients.ndim < 2 or coefficients.shape[-2] != 3:
        raise ParameterError(
            f"coefficients must have shape (..., 3, {basis.n_terms}) (R, G, B rows), got {coefficients.shape}"
        )
    mu_o = check_range("mu_o", mu_o, 0.0, 1.0)
    roughness = check_range("roughness", roughness, 0.0, 1.0)
    basis_table, schlick_table = _check_tables(tables, basis.n_terms)
    single = lut_lookup(basis_table, mu_o, roughness) @ np.swapaxes(coefficients, -1, -2)
    if not multiple_scattering:
        return single
    return compensate_lookup(single, lut_lookup(schlick_table, mu_o, roughness), coefficients, basis)


def compensate_lookup(single_scattering, schlick_texels, coefficients, basis: Basis) -> np.ndarray:
    """:func:`compensated_albedo` of a basis split sum (..., 3) from Schlick-table texels (..., ≥ 2): E =
    scale + bias (the B channel where there is one), F_avg = Σ c_k avg(b_k); both clipped to [0, 1], which
    float32 rounding and out-of-gamut colours (an sRGB F_avg above 1) can leave."""
    # one definition of E with the shaders: the stored B channel (a scene's two-channel table: scale + bias)
    stored = (
        schlick_texels[..., 2] if schlick_texels.shape[-1] >= 3 else schlick_texels[..., 0] + schlick_texels[..., 1]
    )
    albedo = np.clip(stored, 0.0, 1.0)
    average = np.clip(np.asarray(coefficients) @ basis.hemispherical_averages, 0.0, 1.0)
    return compensated_albedo(single_scattering, albedo, average)


def schlick_table_averages() -> np.ndarray:
    """2 ∫₀¹ f_k(μ) μ dμ of the Schlick table's functions R, G, B, A (1 − (1 − μ)⁵, (1 − μ)⁵, 1, μ (1 − μ)⁶):
    (20/21, 1/21, 1, 1/126), by Gauss-Legendre, exact for these polynomials. A linear model's F_avg is its weights
    (:func:`preintegrate.channels.schlick_table_weights`) times these.

    >>> (1 / schlick_table_averages()).round(9).tolist()
    [1.05, 21.0, 1.0, 126.0]
    """
    nodes, weights = np.polynomial.legendre.leggauss(AVERAGE_NODES)
    mu = 0.5 * (nodes + 1.0)
    return (weights * mu) @ schlick_table_channels().functions(mu)


def linear_model_albedo(weights, mu_o, roughness, schlick_table, multiple_scattering: bool = True) -> np.ndarray:
    """F̄ per colour channel (..., 3) of a linear model's material at (μo, r): ``weights`` (..., 3, 4) of the Schlick
    table's R, G, B, A (:func:`preintegrate.channels.schlick_table_weights`), ``schlick_table`` (H, W, 4) read
    bilinearly as a GPU reads it; compensated for multiple scattering unless ``multiple_scattering`` is False."""
    mu_o = check_range("mu_o", mu_o, 0.0, 1.0)
    roughness = check_range("roughness", roughness, 0.0, 1.0)
    schlick_table = as_float_array("Schlick table", schlick_table)
    if schlick_table.ndim != 3 or schlick_table.shape[2] != 4 or min(schlick_table.shape[:2]) < 2:
        raise ParameterError(f"Schlick table must have shape (H ≥ 2, W ≥ 2, 4), got {schlick_table.shape}")
    return weigh_schlick_texels(weights, lut_lookup(schlick_table, mu_o, roughness), multiple_scattering)


def weigh_schlick_texels(weights, texels, multiple_scattering: bool = True) -> np.ndarray:
    """F̄ (..., 3) of a linear model from Schlick-table texels (..., 4): Σ_k w_k texel_k with ``weights`` (..., 3, 4),
    compensated (E = B, the exact F_avg = Σ_k w_k avg_k clipped to [0, 1]) if ``multiple_scattering``: the
    include's ``fresnelLinearSplitSum`` and ``fresnelLinearMultipleScattering``."""
    weights = check_shape_last("weights", as_float_array("weights", weights), 4)
    texels = check_shape_last("texels", as_float_array("texels", texels), 4)
    single = np.einsum("...ck,...k->...c", weights, texels)
    if not multiple_scattering:
        return single
    average = np.clip(weights @ schlick_table_averages(), 0.0, 1.0)
    return compensated_albedo(single, np.clip(texels[..., 2], 0.0, 1.0), average)


def _check_tables(tables, terms: int) -> tuple[np.ndarray, np.ndarray]:
    """(basis table (H, W, K), Schlick table (H', W', ≥ 2)), finite, or an error naming what is wrong."""
    if not isinstance(tables, (tuple, list)) or len(tables) != 2:
        raise ParameterError(f"tables must be (basis table, Schlick table), got {type(tables).__name__}")
    basis_table = as_float_array("basis table", tables[0])
    schlick_table = as_float_array("Schlick table", tables[1])
    if basis_table.ndim != 3 or basis_table.shape[2] != terms or min(basis_table.shape[:2]) < 2:
        raise ParameterError(f"basis table must have shape (H ≥ 2, W ≥ 2, {terms}), got {basis_table.shape}")
    if schlick_table.ndim != 3 or schlick_table.shape[2] < 2 or min(schlick_table.shape[:2]) < 2:
        raise ParameterError(f"Schlick table must have shape (H ≥ 2, W ≥ 2, 2 to 4), got {schlick_table.shape}")
    return basis_table, schlick_table
