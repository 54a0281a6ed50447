"""Shader-side Fresnel generated from one basis: per-pixel coefficients, the direct-light curve, the table coordinates.

Public objects: ``ShaderConstants``, ``shader_constants``, ``SHADER_INCLUDES``, ``shader_includes``,
``sanitize_nk``, ``sanitize_gulbrandsen``, ``sanitize_unit``, ``coefficients_per_pixel_nk``,
``coefficients_per_pixel_gulbrandsen``, ``coefficients_per_pixel_model``, ``direct_fresnel``, ``lut_coordinates``,
``ltc_coordinates``, ``rect_light_specular``,
``linear_model_curve``, ``warped_cosine``, ``unwarped_cosine``, ``PER_PIXEL_MODELS``,
``CURVE_WARPS``, ``CURVE_SEGMENTS``, ``FINE_CURVE_SEGMENTS``, ``CURVE_TOLERANCE``.

Everything a shader needs to turn a texel's material parameters into the K coefficients of the basis, and the
coefficients into F(V·H) for a punctual light, depends on the basis alone: b_k at the fit angles, the constant
(K − 2) × (K − 2) inverse of the K-point system, the projections of the linear artist models' fixed functions, the
hemispherical averages, and the curves b_k themselves. :func:`shader_constants` computes them from a
:class:`~basis.Basis` of 2 … 8 terms, and :func:`shader_includes` writes them with the functions that use them as
one self-contained include per language (GLSL 3.30/4.50/ES 3.00, HLSL, WGSL), which every default build writes
beside its tables: coefficients and table cannot come from different bases (the include states the basis hash, and
so does every table header). A channel's coefficients are one vec4 for K ≤ 4 (zero-padded) and a ``FresnelTerms8``
record of two (terms 0-3, 4-7, as the two textures of the build hold them) for K > 4.

The Python functions here mirror the shaders operation for operation (in float64): engines' CPU tools get the
numbers the GPU computes, and the tests compare the two.

* **(η, κ) per pixel** (Belcour 2020, "Coefficients"): c0 = F(0°) in closed form, c1 = F(90°) − c0 (F(90°) = 1 but
  for η = 1, κ = 0), (c2 … c_(K−1)) = S⁻¹ (F(θ_i) − c0 − c1 b1(θ_i)) with the exact Fresnel equations (Hoffman
  2020, "1823: Fresnel's Equations") at the K − 2 fit angles: for the shipped basis two Fresnel evaluations (one
  vec2) and a constant 2 × 2 product.
* **Gulbrandsen (r, g)** → (η, κ) in closed form (Gulbrandsen 2014, eq. 7–9) → the same solve.
* **Linear artist models** (Schlick F0/F90; Hoffman 2019's F82; the F82 tint of Adobe, OpenPBR's
  ``specular_color`` and MaterialX's ``color82``, Hoffman 2023 eq. 3; Hoffman 2023's generalised Adobe with
  p = 5, eq. 6): F = Σ_n w_n t_n(μ) with t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶), so c = Σ_n w_n P_n with P_n the
  four-point coefficients of t_n, three generated constants; w is a few flops of the parameters. The projection
  is of the models' unclamped linear form (they agree with ``coefficients_from_model`` wherever the model's clamp
  to [0, 1] is inactive at the fit angles).
* **Direct light**: F(V·H) = Σ_k c_k b_k(θ_h), b_0 = 1 and b_1 … b_(K−1) as one polynomial in the warped cosine
  x = μ (1 + w)/(1 + w μ) (a Möbius map that stretches grazing, where the curves steepen: one polynomial in μ or θ
  needs degree 16–24 for 1e-4; in x, degree 12 holds the shipped basis to 2.2e-5), else (the higher terms of
  K > 4 bases) as piecewise polynomials in μ over :data:`CURVE_SEGMENTS` or :data:`FINE_CURVE_SEGMENTS`, within
  :data:`CURVE_TOLERANCE` of the basis' own spline in float64.

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
import functools
from collections.abc import Callable
from typing import NamedTuple

import numpy as np

from basis.angles import cos_theta
from basis.coefficients import coefficients_from_samples
from basis.eigenbasis import Basis, resolve_basis
from basis.models.formulas import F82_MU, adobe_dip_weight, f82_dip_weight, lazanyi_dip, schlick_weight
from basis.validation import ParameterError, as_float_array, check_choice, check_positive_int, safe_line

from .ltc import LtcGrid
from .ltc import rect_light_integral as ltc_rect_light_integral
from .lut import LutGrid

__all__ = [
    "CURVE_SEGMENTS",
    "CURVE_TOLERANCE",
    "CURVE_WARPS",
    "FINE_CURVE_SEGMENTS",
    "PER_PIXEL_MODELS",
    "SHADER_INCLUDES",
    "ShaderConstants",
    "coefficients_per_pixel_gulbrandsen",
    "coefficients_per_pixel_model",
    "coefficients_per_pixel_nk",
    "direct_fresnel",
    "linear_model_curve",
    "ltc_coordinates",
    "lut_coordinates",
    "rect_light_specular",
    "sanitize_gulbrandsen",
    "sanitize_nk",
    "sanitize_unit",
    "shader_constants",
    "shader_includes",
    "unwarped_cosine",
    "warped_cosine",
]

#: The direct-light curves are first fitted as one polynomial in x = μ (1 + w)/(1 + w μ), w the warp of least error
#: on this grid of strengths and then on a finer one around it (the curves bend fastest near grazing: the shipped
#: basis' b3 has slope 38 per radian at θ = π/2; the map spends the polynomial's resolution there). One polynomial
#: costs a division and no selects, where the three segments below cost llvmpipe 0.15–0.2 of Schlick's whole pass
#: more (benchmarks/shader_cost.py, 2026-12). On the shipped basis one polynomial in μ needs degree 16 for 4.2e-4,
#: in θ degree 24 for 2e-4, in √μ degree 16 for 4.7e-4; in x degree 12 reaches 2.2e-5 (w = 1.54).
CURVE_WARPS = tuple(2.0 ** (k / 2) for k in range(-6, 9))
#: Segment edges in μ = V·H of the direct-light polynomials where one warped polynomial of degree 14 does not hold
#: :data:`CURVE_TOLERANCE` (6- and 8-term bases), narrow near grazing; these three reach 2.9e-5 at degree 8 on the
#: shipped basis.
CURVE_SEGMENTS = (0.0, 0.08, 0.3, 1.0)
#: The segments of a basis whose curves these three do not hold (the higher terms of K > 4 bases wiggle near
#: grazing: a 6-term basis misses by 1.7e-4, an 8-term one by 1.5e-3 at degree 12); seven reach 6e-5 for K = 8.
FINE_CURVE_SEGMENTS = (0.0, 0.02, 0.05, 0.1, 0.18, 0.3, 0.5, 1.0)
#: The most the direct-light polynomials may differ from the basis' spline in float64 (the issue's 1e-4, with room
#: for float32 evaluation); the degree is the smallest that reaches it (6 … 14 warped, then 6 … 12 on segments).
CURVE_TOLERANCE = 5e-5
_DEGREES = range(6, 13)
_WARPED_DEGREES = range(6, 15)
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
    fit_mu: np.ndarray  # (K − 2,) cos θ_2 … cos θ_(K−1)
    fit_b1: np.ndarray  # (K − 2,) b1 at those angles
    inverse: np.ndarray  # (K − 2, K − 2) S⁻¹, S[i, j] = b_{j+2}(θ_{i+2})
    projections: np.ndarray  # (3, K) K-point coefficients of t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶)
    averages: np.ndarray  # (K,) hemispherical averages of b_k
    curve_degree: int
    curve_polynomials: np.ndarray  # (segments, degree + 1, K): b_k on a segment, powers of s = 2 (x − lo)/(hi − lo) − 1
    curve_error: float  # max |polynomial − spline| over the segments' dense grids, float64
    curve_segments: tuple[float, ...] = CURVE_SEGMENTS  # the polynomials' segment edges in x
    curve_warp: float = 0.0  # w of x = μ (1 + w)/(1 + w μ), the polynomials' variable (0: x = μ)
    amplification: float = 1.0  # Lebesgue constant of the solve: max over μ of Σ_i |(B(μ) S⁻¹)_i|
    ltc_size: int = 64  # the LTC table's size (``fresnel-lut build --ltc-size``) that fresnelLtcUV addresses
    grid: LutGrid = LutGrid(128, 128)  # the tables' grid: the include's coordinate function reads them on it

    @property
    def n_terms(self) -> int:
        return self.averages.shape[0]

    @property
    def float32_tolerance(self) -> float:
        """What float32 allows the per-pixel coefficients, against float64: the fit-angle Fresnel values carry
        ~2e-7 (a few float32 steps), amplified by the inverse (∞-norm condition number ``condition``; 4.8 for the
        shipped basis: 1e-5 with room), so 2e-6 · max(1, condition) rounded up to 1, 2 or 5 × 10^n."""
        return _round_up(2e-6 * max(1.0, self.condition))

    @property
    def float32_curve_tolerance(self) -> float:
        """What float32 allows the Fresnel curve Σ_k c_k b_k(μ) of per-pixel coefficients, against float64: sample
        errors of ~2e-7 carried by F(0) and amplified by the solve's Lebesgue constant ``amplification`` (1.3 for
        the shipped basis), rounded up to 1, 2 or 5 × 10^n."""
        return _round_up(2e-7 * (1.0 + self.amplification))

    @property
    def grazing_fit_angles(self) -> bool:
        """Whether every fit angle lies at or beyond 45° (those of every default basis do: 1.29–1.5 rad). There
        η² − κ² − sin²θ is best formed as (η − 1)(η + 1) − κ² + μ² for every η: its rounding is that of the larger
        of |η² − 1| and μ² ≤ sin²θ, where η² − sin²θ rounds at sin²θ; nearer normal incidence small η needs the
        other form (basis/fresnel.py chooses per η, as the shaders then do)."""
        mu = np.asarray(self.fit_mu)
        return bool(np.all(mu * mu <= (1.0 - mu) * (1.0 + mu)))

    @property
    def condition(self) -> float:
        """The ∞-norm condition number of S (1 for K = 2, where there is nothing to solve)."""
        if self.inverse.size == 0:
            return 1.0
        system = np.linalg.inv(self.inverse)
        return float(np.linalg.norm(system, np.inf) * np.linalg.norm(self.inverse, np.inf))


def _round_up(value: float) -> float:
    """The smallest of 1, 2, 5 × 10^n at or above ``value``."""
    exponent = np.floor(np.log10(value))
    for step in (1.0, 2.0, 5.0, 10.0):
        if step * 10.0**exponent >= value * (1.0 - 1e-12):
            return float(step * 10.0**exponent)
    raise AssertionError("unreachable")


def _linear_functions(mu: np.ndarray) -> np.ndarray:
    """(…, 3): the fixed functions of the linear artist models, t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶)."""
    fifth = schlick_weight(mu)
    return np.stack([1.0 - fifth, fifth, lazanyi_dip(mu)], axis=-1)


def shader_constants(basis: Basis | None = None, grid: LutGrid | None = None, ltc_size: int = 64) -> ShaderConstants:
    """The constants of :func:`shader_includes` for a basis of 2 … 8 terms (default: the shipped one) and the grid of
    its tables (default: the default build's 128 × 128)."""
    basis = resolve_basis(basis)
    system = basis.evaluate(basis.fit_angles)  # B[i, k] = b_k(θ_i)
    inverse = np.linalg.inv(system[2:, 2:])
    projections = coefficients_from_samples(_linear_functions(cos_theta(basis.fit_angles)).T, basis)
    degree, polynomials, error, segments, warp = _fit_curves(basis)
    curves = basis.evaluate_mu(np.linspace(0.0, 1.0, 2001))  # (μ, K)
    amplification = float(np.max(np.sum(np.abs(curves[:, 2:] @ inverse), axis=-1))) if basis.n_terms > 2 else 0.0
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
        segments,
        warp,
        amplification,
        check_positive_int("ltc_size", ltc_size, low=2, high=1024),
        LutGrid(128, 128) if grid is None else grid,
    )


def _fit_curves(basis: Basis) -> _CurveFit:
    """The direct-light curves of ``basis``: least-squares polynomials of b_k,
    the smallest degree that holds :data:`CURVE_TOLERANCE` as one polynomial in the warped cosine (warps
    :data:`CURVE_WARPS`, then a finer grid around the best), else on :data:`CURVE_SEGMENTS`, else on
    :data:`FINE_CURVE_SEGMENTS` in μ (else the closest fit tried, its error stated). Computed once per basis."""
    cached = _CURVE_FITS.get(basis.content_hash)
    if cached is None:
        cached = _CURVE_FITS[basis.content_hash] = _search_curves(basis)
    return cached


class _CurveFit(NamedTuple):
    """One fit of the direct-light curves (the fields of :class:`ShaderConstants` named ``curve_…``)."""

    degree: int
    polynomials: np.ndarray  # (segments, degree + 1, K)
    error: float  # max |polynomial − spline| over the segments' dense grids
    segments: tuple[float, ...]  # edges in x
    warp: float  # w of x = μ (1 + w)/(1 + w μ)


_CURVE_FITS: dict[str, _CurveFit] = {}


def _search_curves(basis: Basis) -> _CurveFit:
    """What :func:`_fit_curves` returns, computed: the candidates are compared on their Chebyshev form's error
    (the same to rounding), the one returned is converted to the powers the shaders evaluate and measured so."""
    best = None
    for degree in _WARPED_DEGREES:
        fit = min((_chebyshev_fit(basis, (0.0, 1.0), degree, warp) for warp in CURVE_WARPS), key=lambda fit: fit.error)
        if fit.error <= 10.0 * CURVE_TOLERANCE:  # the finer grid gains up to 5x (degree 12 of the shipped basis)
            # a coarse step (√2) either side, 2^(1/32) apart
            fine = [fit.warp * 2.0 ** (k / 32) for k in range(-16, 17)]
            fit = min((_chebyshev_fit(basis, (0.0, 1.0), degree, warp) for warp in fine), key=lambda fit: fit.error)
        if fit.error <= CURVE_TOLERANCE:
            return _fit_segments(basis, fit.segments, fit.degree, fit.warp)
        best = fit if best is None or fit.error < best.error else best
    for segments in (CURVE_SEGMENTS, FINE_CURVE_SEGMENTS):
        for degree in _DEGREES:
            fit = _chebyshev_fit(basis, segments, degree, 0.0)
            if fit.error <= CURVE_TOLERANCE:
                return _fit_segments(basis, fit.segments, fit.degree, fit.warp)
            best = fit if fit.error < best.error else best
    return _fit_segments(basis, best.segments, best.degree, best.warp)


def _chebyshev_fit(basis: Basis, segments: tuple[float, ...], degree: int, warp: float) -> _CurveFit:
    """A candidate of the search: the least-squares polynomials of :func:`_fit_segments` in Chebyshev form
    (``polynomials`` holds Chebyshev coefficients, through the degree's pseudo-inverse, the same to rounding), with
    that form's error; b_0 = 1, which the shaders do not evaluate, is left out of it."""
    vandermonde, projector = _chebyshev_projector(degree)
    polynomials, error = [], 0.0
    for low, high in zip(segments[:-1], segments[1:]):
        values = basis.evaluate_mu(unwarped_cosine(low + 0.5 * (_CURVE_S + 1.0) * (high - low), warp))
        chebyshev = projector @ values  # (degree + 1, K)
        polynomials.append(chebyshev)
        error = max(error, float(np.max(np.abs(vandermonde @ chebyshev[:, 1:] - values[:, 1:]))))
    return _CurveFit(degree, np.array(polynomials), error, tuple(segments), float(warp))


#: The fits' sample points in s ∈ [−1, 1] on every segment, end points included.
_CURVE_S = np.linspace(-1.0, 1.0, _CURVE_SAMPLES)


@functools.lru_cache(maxsize=None)
def _chebyshev_projector(degree: int) -> tuple[np.ndarray, np.ndarray]:
    """(Chebyshev Vandermonde matrix of :data:`_CURVE_S`, its pseudo-inverse) of one degree."""
    vandermonde = np.polynomial.chebyshev.chebvander(_CURVE_S, degree)
    return vandermonde, np.linalg.pinv(vandermonde)


def _fit_segments(basis: Basis, segments: tuple[float, ...], degree: int, warp: float) -> _CurveFit:
    """The least-squares polynomials of one degree on each segment of x, the warp ``warp``, in powers of s (what the
    shaders evaluate, measured so): as :func:`_fit_curves`."""
    polynomials, error = [], 0.0
    s = _CURVE_S
    for low, high in zip(segments[:-1], segments[1:]):
        values = basis.evaluate_mu(unwarped_cosine(low + 0.5 * (s + 1.0) * (high - low), warp))
        chebyshev = np.polynomial.chebyshev.chebfit(s, values, degree)  # (degree + 1, K), well conditioned
        power = np.stack([np.polynomial.chebyshev.cheb2poly(chebyshev[:, k]) for k in range(basis.n_terms)], axis=-1)
        power[:, 0] = 0.0
        power[0, 0] = 1.0  # b_0 = 1 (every basis file's): the shaders do not evaluate it
        polynomials.append(power)
        error = max(error, float(np.max(np.abs(np.polynomial.polynomial.polyval(s, power).T - values))))
    return _CurveFit(degree, np.array(polynomials), error, tuple(segments), float(warp))


def warped_cosine(mu: np.ndarray, warp: float) -> np.ndarray:
    """x = μ (1 + w)/(1 + w μ): [0, 1] onto [0, 1], slope 1 + w at grazing and 1/(1 + w) at normal incidence."""
    return mu * (1.0 + warp) / (1.0 + warp * mu)


def unwarped_cosine(x: np.ndarray, warp: float) -> np.ndarray:
    """μ of x (the inverse of :func:`warped_cosine`), clipped to [0, 1] against rounding."""
    return np.clip(x / (1.0 + warp - warp * x), 0.0, 1.0)


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
    return constants.grid.texture_coordinates(sanitize_unit(n_dot_v, 1.0), sanitize_unit(roughness, 0.5))


def ltc_coordinates(n_dot_v, roughness, constants: ShaderConstants | None = None) -> np.ndarray:
    """(…, 2) texture coordinates of (NdotV, r) on the LTC table, as ``fresnelLtcUV`` computes them."""
    constants = shader_constants() if constants is None else constants
    return LtcGrid(constants.ltc_size).coordinates(sanitize_unit(n_dot_v, 1.0), sanitize_unit(roughness, 0.5))


def rect_light_specular(
    ltc_table, basis_table, normal, view, position, corners, roughness, coefficients, constants=None
) -> np.ndarray:
    """(…, 3) ``fresnelBasisRectLight``: the LTC integral of the quad ``corners`` (…, 4, 3) seen from ``position``
    with ``normal`` and ``view`` (…, 3), read from ``ltc_table`` (the LTC table, :mod:`preintegrate.ltc`), times the
    split sum Σ_k c_k b̄_k of ``basis_table`` (H, W, K) for ``coefficients`` (…, 3, K) — bilinear fetches as a GPU
    makes them."""
    constants = shader_constants() if constants is None else constants
    normal, view = as_float_array("normal", normal), as_float_array("view", view)
    n_dot_v = np.clip(np.sum(normal * view, axis=-1), 0.0, 1.0)
    sine = np.linalg.norm(np.cross(normal, view), axis=-1)
    roughness = sanitize_unit(roughness, 0.5)
    integral = ltc_rect_light_integral(
        LtcGrid(constants.ltc_size).lookup(ltc_table, n_dot_v, roughness, sine), normal, view, position, corners
    )
    low, high, _, _ = constants.grid.row_mapping
    terms = constants.grid.lookup(as_float_array("basis_table", basis_table), n_dot_v, np.clip(roughness, low, high))
    return integral[..., None] * np.einsum("...ck,...k->...c", as_float_array("coefficients", coefficients), terms)


def linear_model_curve(model: str, mu, **parameters) -> np.ndarray:
    """F(μ) of a model of :data:`PER_PIXEL_MODELS` in the linear form the shaders project (unclamped), parameters
    sanitised to [0, 1]; μ broadcast against them: what :func:`coefficients_per_pixel_model` approximates."""
    check_choice("model", model, list(PER_PIXEL_MODELS))
    clean = {name: sanitize_unit(parameters[name]) for name in PER_PIXEL_MODELS[model][0]}
    return np.sum(_model_weights(model, clean) * _linear_functions(sanitize_unit(mu)), axis=-1)


def direct_fresnel(coefficients, v_dot_h, constants: ShaderConstants | None = None) -> np.ndarray:
    """F(V·H) = Σ_k c_k b_k for a punctual light, as ``fresnelBasisDirect`` computes it: coefficients (…, 4) and
    V·H (…) (clamped to [0, 1]) → (…), the curves from the generated polynomials in the warped cosine."""
    constants = shader_constants() if constants is None else constants
    coefficients = as_float_array("coefficients", coefficients)
    x = warped_cosine(sanitize_unit(v_dot_h, 1.0), constants.curve_warp)
    edges = np.asarray(constants.curve_segments)
    segment = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, len(edges) - 2)
    scale, offset = _segment_map(edges)
    s = x * scale[segment] + offset[segment]
    polynomials = constants.curve_polynomials[segment]  # (…, degree + 1, K)
    curves = polynomials[..., -1, :]
    for power in range(constants.curve_degree - 1, -1, -1):  # Horner, as the shaders
        curves = curves * s[..., None] + polynomials[..., power, :]
    return np.sum(coefficients * curves, axis=-1)


# ----------------------------------------------------------------------------- the includes
def _number(value: float) -> str:
    """A constant as a float32 literal of every shading language; a value that none can hold (NaN, inf, beyond
    float32) is refused here, before any include is written, so that a generated include always compiles."""
    value = float(value)
    if not np.isfinite(value) or abs(value) > np.finfo(np.float32).max:
        raise ParameterError(f"a shader constant must be a finite float32 number, got {value!r}")
    text = f"{value:.9g}"
    return text if any(mark in text for mark in ".en") else text + ".0"


def _exponent(value: float, digits: int = 0) -> str:
    """1e-5, 3.1e-5: a tolerance as the comments write it."""
    return f"{value:.{digits}e}".replace("e-0", "e-").replace("e+0", "e")


def _vector(values, prefix: str) -> str:
    return f"{prefix}(" + ", ".join(_number(value) for value in values) + ")"


@dataclasses.dataclass(frozen=True)
class _Spelling:
    """How one shading language spells what the includes need: scalar and vector types, constants, dot products and
    the record of eight terms (two vec4: terms 0-3 and 4-7) that holds a K > 4 basis' coefficients and curves."""

    language: str  # "glsl" | "hlsl" | "wgsl"
    n_terms: int

    @property
    def scalar(self) -> str:
        return "f32" if self.language == "wgsl" else "float"

    def type(self, width: int) -> str:
        if width == 1:
            return self.scalar
        return {"glsl": f"vec{width}", "hlsl": f"float{width}", "wgsl": f"vec{width}f"}[self.language]

    @property
    def four(self) -> str:
        return self.type(4)

    @property
    def wide(self) -> bool:
        return self.n_terms > 4

    @property
    def terms(self) -> str:
        """The type of one channel's coefficients (and of the curves' values)."""
        return "FresnelTerms8" if self.wide else self.four

    def constant(self, name: str, values, comment: str = "") -> str:
        values = np.atleast_1d(np.asarray(values, dtype=np.float64))
        kind = self.type(len(values))
        value = _number(values[0]) if len(values) == 1 else _vector(values, kind)
        line = {
            "glsl": f"const {kind} {name} = {value};",
            "hlsl": f"static const {kind} {name} = {value};",
            "wgsl": f"const {name}: {kind} = {value};",
        }[self.language]
        return line + (f"  // {comment}" if comment else "")

    def constant_terms(self, name: str, values, comment: str = "") -> list[str]:
        """``values`` (K,) as one vec4 ``name`` (K ≤ 4, zero-padded) or two, ``name`` and ``name_HI`` (terms 4-7)."""
        padded = np.zeros(8 if self.wide else 4)
        padded[: len(values)] = values
        lines = [self.constant(name, padded[:4], comment)]
        return lines + ([self.constant(f"{name}_HI", padded[4:], "terms 4-7")] if self.wide else [])

    def make_terms(self, low: str, high: str | None = None) -> str:
        if not self.wide:
            return low
        return f"{'fresnelTerms8' if self.language == 'hlsl' else 'FresnelTerms8'}({low}, {high})"

    def terms_value(self, expressions: list[str]) -> str:
        padded = list(expressions) + ["0.0"] * ((8 if self.wide else 4) - len(expressions))
        low = f"{self.four}({', '.join(padded[:4])})"
        return self.make_terms(low, f"{self.four}({', '.join(padded[4:])})" if self.wide else None)

    def dot_terms(self, coefficients: str, low: str, high: str | None = None) -> str:
        """Σ_k c_k x_k of one channel's coefficients and terms ``x`` (``low``, and ``high`` for terms 4-7)."""
        if not self.wide:
            return f"dot({coefficients}, {low})"
        return f"dot({coefficients}.lo, {low}) + dot({coefficients}.hi, {high})"

    def dot(self, left: str, right: str, width: int) -> str:
        return f"{left} * {right}" if width == 1 else f"dot({left}, {right})"

    def record(self) -> str:
        """The definition of ``FresnelTerms8`` (K > 4 only)."""
        if not self.wide:
            return ""
        if self.language == "wgsl":
            return "struct FresnelTerms8 {\n    lo: vec4f,  // terms 0-3\n    hi: vec4f,  // terms 4-7\n}\n"
        v4 = self.four
        text = f"struct FresnelTerms8\n{{\n    {v4} lo;  // terms 0-3\n    {v4} hi;  // terms 4-7\n}};\n"
        if self.language == "hlsl":
            text += (
                f"FresnelTerms8 fresnelTerms8({v4} lo, {v4} hi)\n{{\n    FresnelTerms8 terms;\n    terms.lo = lo;\n"
                "    terms.hi = hi;\n    return terms;\n}\n"
            )
        return text


def _fit_chunks(n_angles: int) -> list[tuple[str, slice]]:
    """The fit angles θ_2 … θ_(K−1) in vectors of at most four: (constant suffix, angles); none for K = 2."""
    if n_angles == 0:
        return []
    if n_angles <= 4:
        return [("", slice(0, n_angles))]
    return [("", slice(0, 4)), ("_HI", slice(4, n_angles))]


def _fit_parts(constants: ShaderConstants, spelling: _Spelling) -> tuple[str, str, str]:
    """(constants, functions, coefficient statements) of the K − 2 fit angles: each vector of angles gets its
    fresnelAtFitAngles function; c_(2+j) = Σ_i S⁻¹[j, i] (F(θ_i) − c0 − c1 b1(θ_i))."""
    c, sp = constants, spelling
    chunks = _fit_chunks(len(c.fit_mu))
    lines, functions, rests = [], [], []
    for suffix, part in chunks:
        mu = c.fit_mu[part]
        width = len(mu)
        lines += [
            sp.constant(f"FRESNEL_FIT_MU_ROOT2{suffix}", np.sqrt(2.0) * mu, "sqrt(2) cos(theta_i) of the fit angles"),
            sp.constant(f"FRESNEL_FIT_MU2{suffix}", mu**2, "cos^2"),
            sp.constant(f"FRESNEL_FIT_SIN2{suffix}", (1.0 - mu) * (1.0 + mu), "sin^2"),
            sp.constant(f"FRESNEL_FIT_B1{suffix}", c.fit_b1[part], "b1 at the fit angles"),
        ]
        name = "fresnelAtFitAngles" + ("Hi" if suffix else "")
        kind, m, m2, s2 = (
            sp.type(width),
            f"FRESNEL_FIT_MU_ROOT2{suffix}",
            f"FRESNEL_FIT_MU2{suffix}",
            f"FRESNEL_FIT_SIN2{suffix}",
        )
        numerator, denominator = f"(s + {m2} - twoAMu) * r", f"(s + {m2} + twoAMu) * (r + twoAMu * {s2})"
        if width == 2:  # one division for both angles: den.x den.y < 1e31 over the documented (η, κ)
            declare = "let" if sp.language == "wgsl" else kind
            quotient = (
                f"    {declare} den = {denominator};\n"
                f"    {'let' if sp.language == 'wgsl' else 'float'} inverse = 1.0 / (den.x * den.y);\n"
            )
            result = f"{numerator} * den.yx * inverse"
        else:
            quotient, result = "", f"{numerator} / ({denominator})"
        if sp.language == "wgsl":
            difference = (
                f"    let t = (eta - 1.0) * (eta + 1.0) - kappa2 + {m2};  // eta^2 - kappa^2 - sin^2\n"
                if c.grazing_fit_angles
                else "    let nearOne = abs(eta - 1.0) < 0.5;\n"
                "    let base = select(eta * eta, (eta - 1.0) * (eta + 1.0), nearOne) - kappa2;\n"
                f"    let t = base + select(-{s2}, {m2}, nearOne);\n"
            )
            functions.append(
                f"fn {name}(eta: f32, kappa2: f32) -> {kind} {{\n"
                + difference
                + "    let e4 = 4.0 * eta * eta * kappa2;\n"
                "    let s = sqrt(t * t + e4);\n"
                "    let u = s + abs(t);\n"
                f"    let twoA2 = select(e4 / u, u, t >= {kind}(0.0));\n"
                f"    let twoAMu = {m} * sqrt(twoA2);\n"
                f"    let r = s * {m2} + {s2} * {s2};\n{quotient}"
                f"    return {result};\n}}\n"
            )
        else:
            select = (
                f"mix(e4 / u, u, greaterThanEqual(t, {kind}(0.0)))"
                if sp.language == "glsl" and width > 1
                else "(t >= 0.0) ? u : e4 / u"
            )
            difference = (
                f"    {kind} t = (eta - 1.0) * (eta + 1.0) - kappa2 + {m2};  // eta^2 - kappa^2 - sin^2\n"
                if c.grazing_fit_angles
                else "    bool nearOne = abs(eta - 1.0) < 0.5;\n"
                "    float base = (nearOne ? (eta - 1.0) * (eta + 1.0) : eta * eta) - kappa2;\n"
                f"    {kind} t = base + (nearOne ? {m2} : -{s2});\n"
            )
            functions.append(
                f"{kind} {name}(float eta, float kappa2)\n{{\n"
                + difference
                + "    float e4 = 4.0 * eta * eta * kappa2;\n"
                f"    {kind} s = sqrt(t * t + e4);\n"
                f"    {kind} u = s + abs(t);\n"
                f"    {kind} twoA2 = {select};\n"
                f"    {kind} twoAMu = {m} * sqrt(twoA2);  // 2 a mu\n"
                f"    {kind} r = s * {m2} + {s2} * {s2};\n{quotient}"
                f"    return {result};\n}}\n"
            )
        rest = "rest" + ("Hi" if suffix else "")
        declare = f"let {rest}" if sp.language == "wgsl" else f"{kind} {rest}"
        rests.append(f"    {declare} = {name}(eta, kappa2) - f0 - (f90 - f0) * FRESNEL_FIT_B1{suffix};\n")
    solved = []
    for j, row in enumerate(c.inverse):
        terms = []
        for suffix, part in chunks:
            width = part.stop - part.start
            lines.append(
                sp.constant(f"FRESNEL_FIT_INVERSE_{j}{suffix}", row[part], f"row {j} of S^-1" if not suffix else "")
            )
            terms.append(sp.dot(f"FRESNEL_FIT_INVERSE_{j}{suffix}", "rest" + ("Hi" if suffix else ""), width))
        solved.append(" + ".join(terms))
    statements = "".join(rests) + f"    return {sp.terms_value(['f0', 'f90 - f0', *solved])};\n"
    return "\n".join(lines), "\n".join(functions), statements


def _choose(spelling: _Spelling, conditions: list[str], values: list[str]) -> str:
    """The value of the first true condition, else the last value: nested selects (values[i] where conditions[i]
    is the first that holds), branch-free and with every index a literal."""
    if len(values) == 1:
        return values[0]
    rest = _choose(spelling, conditions[1:], values[1:])
    if spelling.language == "wgsl":
        return f"select({rest}, {values[0]}, {conditions[0]})"
    return f"({conditions[0]} ? {values[0]} : {rest})"


def _curve_parts(constants: ShaderConstants, spelling: _Spelling) -> tuple[str, str]:
    """(arrays, Horner statements) of the direct-light polynomials of b_1 … b_(K−1) (b_0 = 1 is not evaluated):
    terms 1-3 in FRESNEL_CURVES, 4-7 in FRESNEL_CURVES_HI. Unrolled; with segments, each power's coefficients chosen
    among them by selects on literal indices: an index that varies per pixel into a constant array is an indirect
    load per lane (llvmpipe measured it at half the cost of Schlick's whole pass; divergent constant-memory reads
    on GPUs) where selects are a few ALU ops."""
    c, sp, d = constants, spelling, constants.curve_degree
    k = c.n_terms
    polynomial = c.curve_polynomials.reshape(-1, k)  # (segments · (degree + 1), K)
    parts = [("", "b" if not sp.wide else "bLo", polynomial[:, 1 : min(k, 4)])]
    if sp.wide:
        parts.append(("_HI", "bHi", polynomial[:, 4:]))
    count = polynomial.shape[0]
    arrays = []
    for suffix, _, rows in parts:
        kind = sp.type(rows.shape[1])
        body = ",\n".join("    " + (_number(row[0]) if rows.shape[1] == 1 else _vector(row, kind)) for row in rows)
        if sp.language == "wgsl":
            arrays.append(
                f"var<private> FRESNEL_CURVES{suffix}: array<{kind}, {count}> = array<{kind}, {count}>(\n{body}\n);"
            )
        elif sp.language == "hlsl":
            arrays.append(f"static const {kind} FRESNEL_CURVES{suffix}[{count}] = {{\n{body}\n}};")
        else:
            arrays.append(f"const {kind} FRESNEL_CURVES{suffix}[{count}] = {kind}[{count}](\n{body}\n);")
    segments = len(c.curve_segments) - 1
    conditions = _segment_conditions(c.curve_segments)

    def coefficient(suffix: str, power: int) -> str:
        return _choose(sp, conditions, [f"FRESNEL_CURVES{suffix}[{j * (d + 1) + power}]" for j in range(segments)])

    statements = ""
    for suffix, name, rows in parts:
        declare = "var " if sp.language == "wgsl" else sp.type(rows.shape[1]) + " "
        statements += f"    {declare}{name} = {coefficient(suffix, d)};\n"
    for power in range(d - 1, -1, -1):
        statements += "".join(f"    {name} = {name} * s + {coefficient(suffix, power)};\n" for suffix, name, _ in parts)
    v4 = sp.four
    low = f"{v4}(1.0, {parts[0][1]}{', 0.0' * (4 - min(k, 4))})"
    if not sp.wide:
        return "\n".join(arrays), statements + f"    return {low};\n"
    high = f"{v4}(bHi{', 0.0' * (8 - k)})"
    return "\n".join(arrays), statements + f"    return {sp.make_terms(low, high)};\n"


def _segment_conditions(edges) -> list[str]:
    """The shader variables below1 … below(n − 1): μ lies below inner edge i (what ``_choose`` selects on)."""
    return [f"below{i}" for i in range(1, len(edges) - 1)]


def _segment_map(edges) -> tuple[np.ndarray, np.ndarray]:
    """(scale, offset) per segment: s = μ · scale + offset maps [lo, hi] onto [−1, 1] without a division."""
    low, high = np.asarray(edges[:-1], dtype=np.float64), np.asarray(edges[1:], dtype=np.float64)
    return 2.0 / (high - low), -(high + low) / (high - low)


def _combination_parts(constants: ShaderConstants, spelling: _Spelling) -> tuple[list[str], list[str], str, str, str]:
    """(projection constants, the linear models' sums, averages constant, the direct-light and average
    expressions) of every language: the three channels' Σ_k c_k x_k of the terms b (or b.lo, b.hi) and of the
    averages. WGSL's constants go without the comments."""
    c, sp = constants, spelling
    comment = sp.language != "wgsl"
    meanings = ("1 - (1 - mu)^5", "(1 - mu)^5", "mu (1 - mu)^6")
    projections = [
        line
        for name, row, what in zip(("SCALE", "BIAS", "DIP"), c.projections, meanings)
        for line in sp.constant_terms(f"FRESNEL_PROJECTION_{name}", row, f"coefficients of {what}" if comment else "")
    ]
    linear = [
        f"w0 * FRESNEL_PROJECTION_SCALE{s} + w1 * FRESNEL_PROJECTION_BIAS{s} + w2 * FRESNEL_PROJECTION_DIP{s}"
        for s in ([""] + (["_HI"] if sp.wide else []))
    ]
    averages = "\n".join(
        sp.constant_terms("FRESNEL_BASIS_AVERAGES", c.averages, "2 * integral of b_k(mu) mu dmu" if comment else "")
    )
    terms = ("b", None) if not sp.wide else ("b.lo", "b.hi")
    channels = ("cR", "cG", "cB")
    direct = f"{sp.type(3)}(" + ", ".join(sp.dot_terms(channel, *terms) for channel in channels) + ")"
    average = (
        f"{sp.type(3)}("
        + ", ".join(sp.dot_terms(ch, "FRESNEL_BASIS_AVERAGES", "FRESNEL_BASIS_AVERAGES_HI") for ch in channels)
        + ")"
    )
    return projections, linear, averages, direct, average


def _segment_parts(constants: ShaderConstants, spelling: _Spelling) -> tuple[str, str]:
    """(constants, statements giving the polynomials' variable: x, the warped cosine of μ; the conditions below1 … of
    x's segment; s on it): x < edge_i for the inner edges, then s = x · scale + offset of the segment, the first
    whose upper edge lies above x (what ``direct_fresnel`` computes). One segment: no conditions, no selects."""
    edges, sp, warp = constants.curve_segments, spelling, constants.curve_warp
    wgsl, hlsl = sp.language == "wgsl", sp.language == "hlsl"
    const = "const" if not hlsl else "static const"
    declarations = []
    if warp:
        declarations.append(sp.constant("FRESNEL_CURVE_WARP", warp, "" if wgsl else "w of x = mu (1 + w) / (1 + w mu)"))
        x = "mu * (1.0 + FRESNEL_CURVE_WARP) / (1.0 + FRESNEL_CURVE_WARP * mu)"
    else:
        x = "mu"
    count = len(edges)
    if count == 4:
        kind = "vec4f" if wgsl else sp.four
        declarations.append(
            f"const FRESNEL_CURVE_EDGES = {_vector(edges, kind)};"
            if wgsl
            else f"{const} {kind} FRESNEL_CURVE_EDGES = {_vector(edges, kind)};"
        )
        inner = [f"FRESNEL_CURVE_EDGES.{axis}" for axis in "yz"]
    elif count > 2:
        values = ", ".join(_number(edge) for edge in edges)
        declarations.append(
            {
                "wgsl": f"const FRESNEL_CURVE_EDGES = array<f32, {count}>({values});",
                "hlsl": f"static const float FRESNEL_CURVE_EDGES[{count}] = {{{values}}};",
                "glsl": f"const float FRESNEL_CURVE_EDGES[{count}] = float[{count}]({values});",
            }[sp.language]
        )
        inner = [f"FRESNEL_CURVE_EDGES[{i}]" for i in range(1, count - 1)]
    else:
        inner = []
    conditions = _segment_conditions(edges)
    scale, offset = _segment_map(edges)
    if conditions:
        s = (
            f"x * {_choose(sp, conditions, [_number(value) for value in scale])} "
            f"+ {_choose(sp, conditions, [_number(value) for value in offset])}"
        )
    else:
        s = f"x * {_number(scale[0])} {'-' if offset[0] < 0 else '+'} {_number(abs(offset[0]))}"
    declare = "let" if wgsl else "float"
    statements = f"    {declare} x = {x};\n"
    if conditions:
        if wgsl:
            statements += "".join(f"    let {name} = x < {edge};\n" for name, edge in zip(conditions, inner))
        else:
            statements += (
                "    bool " + ", ".join(f"{name} = x < {edge}" for name, edge in zip(conditions, inner)) + ";\n"
            )
    return "\n".join(declarations), statements + f"    {declare} s = {s};\n"


def _column_coordinate(constants: ShaderConstants) -> tuple[str, str]:
    """(what the comment calls it, its expression) of the table's column coordinate x of the sanitised NdotV."""
    mu = "fresnelSanitize(NdotV, 1.0, 0.0, 1.0)"
    if constants.grid.columns == "root-endpoints":
        return "sqrt(NdotV)", f"sqrt({mu})"
    return "NdotV", mu


def _header(constants: ShaderConstants, language: str, command: str) -> str:
    k, m = constants.n_terms, constants.n_terms - 2
    solve = (
        f"exact Fresnel at the {m} fit angle{'s' if m != 1 else ''} + a constant {m}x{m} inverse"
        if m
        else "F(0), 1 - F(0)"
    )
    kind = "one vec4 per channel" if k <= 4 else "FresnelTerms8 per channel (.lo terms 0-3, .hi terms 4-7)"
    return (
        f"// fresnel-basis: per-pixel Fresnel of basis {constants.basis_hash} ({language}, {k} terms). Generated by\n"
        f"// `{safe_line(command)}` from the basis' own file: do not edit, regenerate it (preintegrate/shaders.py). Self-contained:\n"
        "// use it beside the tables whose header says fresnel:basis_hash = " + constants.basis_hash + ".\n"
        "//\n"
        f'// Per pixel, per colour channel, {kind} (Belcour, Bati, Barla 2020, eq. 4-5 and "Coefficients"):\n'
        f"//   fresnelCoefficientsNK(eta, kappa)               {solve}\n"
        "//   fresnelCoefficientsGulbrandsen(r, g)            Gulbrandsen 2014 eq. 7-9, then the same\n"
        "//   fresnelCoefficientsSchlick(f0, f90)             Schlick 1994 (F90 = 1: the usual Schlick)\n"
        "//   fresnelCoefficientsF82(f0, f82)                 Hoffman 2019's absolute F82\n"
        "//   fresnelCoefficientsF82Tint(f0, tint)            Adobe / OpenPBR specular_color / MaterialX color82 (a tint)\n"
        "//   fresnelCoefficientsGeneralizedAdobe(r0, r90, t) Hoffman 2023 eq. 6, p = 5\n"
        "// then: F for a punctual light = fresnelBasisDirect(VdotH, c); the image-based split sum and the\n"
        "// multiple-scattering average use the same c (fresnelBasisAverage). Inputs: NaN becomes a fallback, every\n"
        "// other value is clamped (eta to [1e-4, 1e4], kappa to [0, 1e4], r to [0, 0.9999], the rest to [0, 1]).\n"
        f"// Float32: coefficients within {_exponent(constants.float32_tolerance)} of float64, the Fresnel curve they give "
        f"within {_exponent(constants.float32_curve_tolerance)}; the\n"
        f"// direct-light curves within {_exponent(constants.curve_error, 1)} of the basis' spline (float64; tests/luts/ measures all three\n"
        "// on the GPU).\n"
    )


def _glsl(constants: ShaderConstants, command: str, hlsl: bool = False) -> str:
    """GLSL (3.30, 4.50, ES 3.00) or, with ``hlsl``, HLSL: the same statements with the other spellings."""
    sp = _Spelling("hlsl" if hlsl else "glsl", constants.n_terms)
    v2, v3, v4, f, T = sp.type(2), sp.type(3), sp.four, "float", sp.terms
    const = "static const" if hlsl else "const"
    bits = "asuint" if hlsl else "floatBitsToUint"
    c, d = constants, constants.curve_degree
    fit_constants, fit_functions, solve = _fit_parts(c, sp)
    curve_arrays, horner = _curve_parts(c, sp)
    edges, segment = _segment_parts(c, sp)
    column_x, column_x_code = _column_coordinate(c)
    second = ", sampler2D lut2" if not hlsl else ", Texture2D<float4> lut2"
    if hlsl:
        fetch = "lut.SampleLevel(linearClamp, uv, 0)"
        signature = f"Texture2D<float4> lut{second if sp.wide else ''}, SamplerState linearClamp"
    else:
        fetch = "textureLod(lut, uv, 0.0)"
        signature = f"sampler2D lut{second if sp.wide else ''}"
    fetch_terms = sp.make_terms(fetch, fetch.replace("lut.", "lut2.").replace("(lut,", "(lut2,")) if sp.wide else fetch
    projections, linear, averages, direct, average = _combination_parts(c, sp)
    return (
        _header(c, "HLSL" if hlsl else "GLSL 3.30 / 4.50 / ES 3.00", command)
        + f"""
{const} uint FRESNEL_BASIS_HASH = 0x{c.basis_hash[:8]}u;  // the first 8 hex digits of {c.basis_hash}
{sp.record()}{fit_constants}
{chr(10).join(projections)}
{averages}
{edges}
{const} int FRESNEL_CURVE_DEGREE = {d};
// b_1 .. b_{c.n_terms - 1} (b_0 = 1) on segment j of x: sum_p FRESNEL_CURVES[j * {d + 1} + p] * s^p, s = 2 (x - lo) / (hi - lo) - 1
{curve_arrays}
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

// Exact Fresnel at the fit angles, the angle terms constant: F = (s + mu^2 - 2a mu) r /
// ((s + mu^2 + 2a mu)(r + 2a mu sin^2)), r = s mu^2 + sin^4 (Hoffman's Fs times (1 + Fp/Fs) / 2: one division).
{fit_functions}
// Coefficients of (eta, kappa^2), already in range, whose F(0) is f0: c0 = f0, c1 = F(90) - c0, then the constant
// inverse of the fit angles.
{T} fresnelCoefficientsSolve({f} f0, {f} eta, {f} kappa2)
{{
    {f} f90 = (eta == 1.0 && kappa2 == 0.0) ? 0.0 : 1.0;
{solve}}}

// The same with F(0) in closed form.
{T} fresnelCoefficientsEtaKappa2({f} eta, {f} kappa2)
{{
    return fresnelCoefficientsSolve(((eta - 1.0) * (eta - 1.0) + kappa2) / ((eta + 1.0) * (eta + 1.0) + kappa2), eta,
                                    kappa2);
}}

// Four-point coefficients of one channel's (eta, kappa).
{T} fresnelCoefficientsNK({f} eta, {f} kappa)
{{
    kappa = fresnelSanitize(kappa, 0.0, 0.0, 1e4);
    return fresnelCoefficientsEtaKappa2(fresnelSanitize(eta, 1.5, 1e-4, 1e4), kappa * kappa);
}}

// Gulbrandsen's (r, g) -> (eta, kappa^2) (JCGT 2014, eq. 7-9) for r in [0, 0.9999], g in [0, 1], with q = sqrt(r):
// kappa^2 = (r (n + 1)^2 - (n - 1)^2) / (1 - r) factored exactly into g (n_max - n_min)(n - 1/n_max)
// = 4 g r / ((1 + r)(1 - q)) (g (1 - q) / (1 + r) + 2 (1 - g) / (1 - q)), a product and a sum of positive terms (no
// float32 cancellation). n_max = (1 + q) / (1 - q) keeps n - 1 to a few ulps as r -> 0.
{v2} fresnelGulbrandsenToEtaKappa2({f} r, {f} g)
{{
    {f} q = sqrt(r);
    {f} over1pr = 1.0 / (1.0 + r), over1mq = 1.0 / (1.0 - q);
    {f} n = g * (1.0 - r) * over1pr + (1.0 - g) * (1.0 + q) * over1mq;
    return {v2}(n, 4.0 * g * r * over1pr * over1mq * (g * (1.0 - q) * over1pr + 2.0 * (1.0 - g) * over1mq));
}}

// Gulbrandsen's F(0) is r itself: no closed-form F(0) needed.
{T} fresnelCoefficientsGulbrandsen({f} r, {f} g)
{{
    r = fresnelSanitize(r, 0.0, 0.0, 0.9999);
    {v2} nk2 = fresnelGulbrandsenToEtaKappa2(r, fresnelSanitize(g, 0.0, 0.0, 1.0));
    return fresnelCoefficientsSolve(r, nk2.x, nk2.y);
}}

// Linear artist models: c = w0 P_scale + w1 P_bias + w2 P_dip (the projections of their fixed functions).
{T} fresnelCoefficientsLinear({f} w0, {f} w1, {f} w2)
{{
    return {sp.make_terms(*linear)};
}}

{const} {f} FRESNEL_F82_SCHLICK_WEIGHT = {_number((1.0 - F82_MU) ** 5)};  // (1 - 1/7)^5
{const} {f} FRESNEL_F82_DIP = {_number(lazanyi_dip(F82_MU))};              // (1/7) (1 - 1/7)^6

{T} fresnelCoefficientsSchlick({f} f0, {f} f90)
{{
    return fresnelCoefficientsLinear(fresnelSanitize(f0, 0.0, 0.0, 1.0), fresnelSanitize(f90, 0.0, 0.0, 1.0), 0.0);
}}

{T} fresnelCoefficientsF82({f} f0, {f} f82)
{{
    f0 = fresnelSanitize(f0, 0.0, 0.0, 1.0);
    f82 = fresnelSanitize(f82, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT - f82) / FRESNEL_F82_DIP);
}}

{T} fresnelCoefficientsF82Tint({f} f0, {f} tint)
{{
    f0 = fresnelSanitize(f0, 0.0, 0.0, 1.0);
    tint = fresnelSanitize(tint, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0,
                                     -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

{T} fresnelCoefficientsGeneralizedAdobe({f} r0, {f} r90, {f} tint)
{{
    r0 = fresnelSanitize(r0, 0.0, 0.0, 1.0);
    r90 = fresnelSanitize(r90, 0.0, 0.0, 1.0);
    tint = fresnelSanitize(tint, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(r0, r90,
                                     -(r0 + (r90 - r0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

// The curves b_0 .. b_{c.n_terms - 1} at mu = V.H (polynomials in x, Horner).
{T} fresnelBasisCurves({f} mu)
{{
    mu = fresnelSanitize(mu, 1.0, 0.0, 1.0);
{segment}{horner}}}

// Fresnel of a punctual light for each colour channel: F(V.H) = sum_k c_k b_k(theta_h).
{v3} fresnelBasisDirect({f} VdotH, {T} cR, {T} cG, {T} cB)
{{
    {T} b = fresnelBasisCurves(VdotH);
    return {direct};
}}

// The tables' coordinates (the grid of the build that wrote this include: {c.grid.width} x {c.grid.height}, columns at
// {c.grid.columns}, rows at {c.grid.rows}): u = {column_x} * scale + offset, v = clamp(r, lo, hi) * scale + offset
// (the half-texel remap of end-point texels), so that a change of grid is these constants.
{const} {v2} FRESNEL_LUT_COLUMNS = {_vector(c.grid.column_mapping, v2)};  // scale, offset
{const} {v4} FRESNEL_LUT_ROWS = {_vector(c.grid.row_mapping, v4)};  // lo, hi, scale, offset
{v2} fresnelBasisLutUV({f} NdotV, {f} perceptualRoughness)
{{
    {f} r = clamp(fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0), FRESNEL_LUT_ROWS.x, FRESNEL_LUT_ROWS.y);
    {f} x = {column_x_code};
    return {v2}(x * FRESNEL_LUT_COLUMNS.x + FRESNEL_LUT_COLUMNS.y, r * FRESNEL_LUT_ROWS.z + FRESNEL_LUT_ROWS.w);
}}

// The split sum of the basis table{"s two textures" if sp.wide else ""} at level 0, read through fresnelBasisLutUV.
{v3} fresnelBasisSplitSumUV({signature}, {f} NdotV, {f} r, {T} cR, {T} cG, {T} cB)
{{
    {v2} uv = fresnelBasisLutUV(NdotV, r);
    {T} b = {fetch_terms};
    return {direct};
}}

// The hemispherical average F_avg = sum_k c_k avg(b_k) (multiple-scattering compensation), clamped to [0, 1].
{v3} fresnelBasisAverage({T} cR, {T} cG, {T} cB)
{{
    return clamp({average},
                 0.0, 1.0);
}}

// All three channels at once, for (eta, kappa) and (r, g) texture reads.
void fresnelCoefficientsNK3({v3} eta, {v3} kappa, out {T} cR, out {T} cG, out {T} cB)
{{
    cR = fresnelCoefficientsNK(eta.x, kappa.x);
    cG = fresnelCoefficientsNK(eta.y, kappa.y);
    cB = fresnelCoefficientsNK(eta.z, kappa.z);
}}

void fresnelCoefficientsGulbrandsen3({v3} r, {v3} g, out {T} cR, out {T} cG, out {T} cB)
{{
    cR = fresnelCoefficientsGulbrandsen(r.x, g.x);
    cG = fresnelCoefficientsGulbrandsen(r.y, g.y);
    cB = fresnelCoefficientsGulbrandsen(r.z, g.z);
}}
"""
    )


def _area_glsl(constants: ShaderConstants, hlsl: bool = False) -> str:
    """The rectangular light (linearly transformed cosines, :mod:`preintegrate.ltc`) in GLSL or HLSL."""
    sp = _Spelling("hlsl" if hlsl else "glsl", constants.n_terms)
    v2, v3, v4, T = sp.type(2), sp.type(3), sp.four, sp.terms
    m3 = "float3x3" if hlsl else "mat3"
    const = "static const" if hlsl else "const"
    size = constants.ltc_size
    if hlsl:
        textures = "Texture2D<float4> ltcLut, Texture2D<float4> lut" + (", Texture2D<float4> lut2" if sp.wide else "")
        samplers = ", SamplerState linearClamp"
        fetch_ltc = "ltcLut.SampleLevel(linearClamp, fresnelLtcUVSine(NdotV, length(cross(N, V)), r), 0)"
        matrix = "float3x3(t.x, 0.0, t.z, 0.0, 1.0, 0.0, t.y, 0.0, t.w)"  # HLSL constructors take rows
        frame = "float3x3(T1, T2, N)"
        multiply = "mul(m, {x})"
        split = "fresnelBasisSplitSumUV(lut, " + ("lut2, " if sp.wide else "") + "linearClamp, NdotV, r, cR, cG, cB)"
        schlick_textures = "Texture2D<float4> ltcLut, Texture2D<float4> schlickLut, SamplerState linearClamp"
        fetch_schlick = "schlickLut.SampleLevel(linearClamp, fresnelBasisLutUV(NdotV, r), 0).rg"
        corners = "float3 corners[4]"
        arc = "atan2"
    else:
        textures = "sampler2D ltcLut, sampler2D lut" + (", sampler2D lut2" if sp.wide else "")
        samplers = ""
        fetch_ltc = "textureLod(ltcLut, fresnelLtcUVSine(NdotV, length(cross(N, V)), r), 0.0)"
        matrix = "mat3(vec3(t.x, 0.0, t.y), vec3(0.0, 1.0, 0.0), vec3(t.z, 0.0, t.w))"  # GLSL constructors take columns
        frame = "transpose(mat3(T1, T2, N))"
        multiply = "m * {x}"
        split = "fresnelBasisSplitSumUV(lut, " + ("lut2, " if sp.wide else "") + "NdotV, r, cR, cG, cB)"
        schlick_textures = "sampler2D ltcLut, sampler2D schlickLut"
        fetch_schlick = "textureLod(schlickLut, fresnelBasisLutUV(NdotV, r), 0.0).rg"
        corners = "vec3 corners[4]"
        arc = "atan"
    return f"""
// ---- Rectangular lights: linearly transformed cosines (Heitz, Dupuy, Hill, Neubelt 2016) with the same
// coefficients. The LTC table (ggx_ltc, `fresnel-lut build --ltc`) has the public tables' axes and packing
// (three.js LTC_Uv and ltc_1): u = r, v = sqrt(1 - NdotV), end points on texel centres, {size} x {size}.
{const} float FRESNEL_LTC_SIZE = {_number(size)};

{v2} fresnelLtcUV(float NdotV, float perceptualRoughness)
{{
    float r = fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0);
    float mu = fresnelSanitize(NdotV, 1.0, 0.0, 1.0);
    return {v2}(r, sqrt(1.0 - mu)) * ((FRESNEL_LTC_SIZE - 1.0) / FRESNEL_LTC_SIZE) + 0.5 / FRESNEL_LTC_SIZE;
}}

// The same from sin(theta_v) = |N x V| as well: sqrt(1 - NdotV) = sin / sqrt(1 + NdotV), which float32 holds as
// NdotV -> 1, where this axis is steepest (1 - NdotV cancels: 0.016 texels of error, 3e-4 in a sharp lobe's light).
{v2} fresnelLtcUVSine(float NdotV, float sinV, float perceptualRoughness)
{{
    float r = fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0);
    float mu = fresnelSanitize(NdotV, 1.0, 0.0, 1.0);
    float root = (mu > 0.0) ? min(sinV / sqrt(1.0 + mu), 1.0) : 1.0;
    return {v2}(r, root) * ((FRESNEL_LTC_SIZE - 1.0) / FRESNEL_LTC_SIZE) + 0.5 / FRESNEL_LTC_SIZE;
}}

// Lambert's edge term (p x q).z theta / sin(theta) of unit p, q; atan2 keeps short edges in float32.
float fresnelLtcEdge({v3} p, {v3} q)
{{
    {v3} c = cross(p, q);
    float s = length(c);
    return c.z * ((s > 1e-7) ? {arc}(s, dot(p, q)) / s : 1.0);
}}

{v3} fresnelLtcUnit({v3} v)
{{
    return v / max(length(v), 1e-30);
}}

// The integral of the clamped cosine over the quad m * c_i (Heitz 2016 eq. 11), clipped to the upper hemisphere
// edge by edge, the horizon edge from the exit to the entry point; one-sided: 0 when the quad faces away (its
// corners turn counter-clockwise seen from the point that it lights, as three.js winds them).
float fresnelLtcQuad({m3} m, {corners})
{{
    {v3} p[4];
    for (int i = 0; i < 4; ++i)
    {{
        p[i] = {multiply.format(x="corners[i]")};
    }}
    float sum = 0.0;
    {v3} exitPoint = {v3}(1.0, 0.0, 0.0), entryPoint = {v3}(0.0, 1.0, 0.0);
    bool exits = false, enters = false;
    for (int i = 0; i < 4; ++i)
    {{
        {v3} a = p[i], b = p[(i + 1) & 3];
        bool aboveA = a.z >= 0.0, aboveB = b.z >= 0.0;
        float denominator = a.z - b.z;
        {v3} x = a + (b - a) * (a.z / ((denominator != 0.0) ? denominator : 1.0));
        if (aboveA || aboveB)
        {{
            sum += fresnelLtcEdge(fresnelLtcUnit(aboveA ? a : x), fresnelLtcUnit(aboveB ? b : x));
        }}
        if (aboveA && !aboveB)
        {{
            exitPoint = x;
            exits = true;
        }}
        if (!aboveA && aboveB)
        {{
            entryPoint = x;
            enters = true;
        }}
    }}
    if (exits && enters)
    {{
        sum += fresnelLtcEdge(fresnelLtcUnit(exitPoint), fresnelLtcUnit(entryPoint));
    }}
    return max(-sum * 0.159154943, 0.0);  // 1 / (2 pi)
}}

// The LTC integral of a rectangular light with corners (world space) seen from P with normal N and view V:
// the frame T1 (the view's tangential part), T2 = N x T1, N, then the table's M^-1.
float fresnelLtcRect({"Texture2D<float4> ltcLut, SamplerState linearClamp" if hlsl else "sampler2D ltcLut"}, {v3} N, {v3} V, {v3} P, {corners}, float r)
{{
    float NdotV = clamp(dot(N, V), 0.0, 1.0);
    {v4} t = {fetch_ltc};
    {v3} T1 = V - N * dot(V, N);
    T1 -= N * dot(T1, N);  // again: float32 leaves a part along N that dominates a short tangent
    float tangential = length(T1);
    // a view within 1e-4 rad of the normal: any tangent (the LTC is isotropic there to float32's resolution)
    T1 = (tangential > 1e-4) ? T1 / tangential
                             : normalize(cross(N, (abs(N.x) < 0.9) ? {v3}(1.0, 0.0, 0.0) : {v3}(0.0, 1.0, 0.0)));
    {v3} T2 = cross(N, T1);
    {m3} m = {"mul(" + matrix + ", " + frame + ")" if hlsl else matrix + " * " + frame};
    {v3} local[4];
    for (int i = 0; i < 4; ++i)
    {{
        local[i] = corners[i] - P;
    }}
    return fresnelLtcQuad(m, local);
}}

// Specular of a rectangular light per colour channel: the LTC integral times the split sum of the same
// coefficients as the image-based and punctual paths (the LTC matrices do not depend on Fresnel).
{v3} fresnelBasisRectLight({textures}{samplers}, {v3} N, {v3} V, {v3} P, {corners}, float r, {T} cR, {T} cG,
                           {T} cB)
{{
    float NdotV = clamp(dot(N, V), 0.0, 1.0);
    return fresnelLtcRect(ltcLut{", linearClamp" if hlsl else ""}, N, V, P, corners, r) * {split};
}}

// Schlick's variant for comparison (the engines' F0 * scale + bias from the Schlick table, F90 = 1).
{v3} fresnelSchlickRectLight({schlick_textures}, {v3} N, {v3} V, {v3} P, {corners}, float r, {v3} f0)
{{
    float NdotV = clamp(dot(N, V), 0.0, 1.0);
    {v2} s = {fetch_schlick};
    return fresnelLtcRect(ltcLut{", linearClamp" if hlsl else ""}, N, V, P, corners, r) * (f0 * s.x + s.y);
}}
"""


def _area_wgsl(constants: ShaderConstants) -> str:
    """The rectangular light in WGSL."""
    sp = _Spelling("wgsl", constants.n_terms)
    T = sp.terms
    size = constants.ltc_size
    textures = "lut: texture_2d<f32>, " + ("lut2: texture_2d<f32>, " if sp.wide else "")
    split = "fresnelBasisSplitSumUV(lut, " + ("lut2, " if sp.wide else "") + "linearClamp, NdotV, r, cR, cG, cB)"
    return f"""
// Rectangular lights: linearly transformed cosines (Heitz 2016) with the same coefficients; the LTC table
// (ggx_ltc, `fresnel-lut build --ltc`) on the public tables' axes and packing, {size} x {size}.
const FRESNEL_LTC_SIZE: f32 = {_number(size)};

fn fresnelLtcUV(NdotV: f32, perceptualRoughness: f32) -> vec2f {{
    let r = fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0);
    let mu = fresnelSanitize(NdotV, 1.0, 0.0, 1.0);
    return vec2f(r, sqrt(1.0 - mu)) * ((FRESNEL_LTC_SIZE - 1.0) / FRESNEL_LTC_SIZE) + 0.5 / FRESNEL_LTC_SIZE;
}}

fn fresnelLtcUVSine(NdotV: f32, sinV: f32, perceptualRoughness: f32) -> vec2f {{
    let r = fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0);
    let mu = fresnelSanitize(NdotV, 1.0, 0.0, 1.0);
    let root = select(1.0, min(sinV / sqrt(1.0 + mu), 1.0), mu > 0.0);
    return vec2f(r, root) * ((FRESNEL_LTC_SIZE - 1.0) / FRESNEL_LTC_SIZE) + 0.5 / FRESNEL_LTC_SIZE;
}}

fn fresnelLtcEdge(p: vec3f, q: vec3f) -> f32 {{
    let c = cross(p, q);
    let s = length(c);
    return c.z * select(1.0, atan2(s, dot(p, q)) / max(s, 1e-30), s > 1e-7);
}}

fn fresnelLtcUnit(v: vec3f) -> vec3f {{
    return v / max(length(v), 1e-30);
}}

fn fresnelLtcQuad(m: mat3x3f, corners: array<vec3f, 4>) -> f32 {{
    var p: array<vec3f, 4>;
    for (var i = 0; i < 4; i = i + 1) {{
        p[i] = m * corners[i];
    }}
    var sum = 0.0;
    var exitPoint = vec3f(1.0, 0.0, 0.0);
    var entryPoint = vec3f(0.0, 1.0, 0.0);
    var exits = false;
    var enters = false;
    for (var i = 0; i < 4; i = i + 1) {{
        let a = p[i];
        let b = p[(i + 1) & 3];
        let aboveA = a.z >= 0.0;
        let aboveB = b.z >= 0.0;
        let denominator = a.z - b.z;
        let x = a + (b - a) * (a.z / select(1.0, denominator, denominator != 0.0));
        if (aboveA || aboveB) {{
            sum = sum + fresnelLtcEdge(fresnelLtcUnit(select(x, a, aboveA)), fresnelLtcUnit(select(x, b, aboveB)));
        }}
        if (aboveA && !aboveB) {{
            exitPoint = x;
            exits = true;
        }}
        if (!aboveA && aboveB) {{
            entryPoint = x;
            enters = true;
        }}
    }}
    if (exits && enters) {{
        sum = sum + fresnelLtcEdge(fresnelLtcUnit(exitPoint), fresnelLtcUnit(entryPoint));
    }}
    return max(-sum * 0.159154943, 0.0);
}}

fn fresnelLtcRect(ltcLut: texture_2d<f32>, linearClamp: sampler, N: vec3f, V: vec3f, P: vec3f,
                  corners: array<vec3f, 4>, r: f32) -> f32 {{
    let NdotV = clamp(dot(N, V), 0.0, 1.0);
    let t = textureSampleLevel(ltcLut, linearClamp, fresnelLtcUVSine(NdotV, length(cross(N, V)), r), 0.0);
    let first = V - N * dot(V, N);
    let tangent = first - N * dot(first, N);
    let tangential = length(tangent);
    let other = select(vec3f(0.0, 1.0, 0.0), vec3f(1.0, 0.0, 0.0), abs(N.x) < 0.9);
    let T1 = select(normalize(cross(N, other)), tangent / max(tangential, 1e-30), tangential > 1e-4);
    let T2 = cross(N, T1);
    let m = mat3x3f(vec3f(t.x, 0.0, t.y), vec3f(0.0, 1.0, 0.0), vec3f(t.z, 0.0, t.w)) * transpose(mat3x3f(T1, T2, N));
    var local: array<vec3f, 4>;
    for (var i = 0; i < 4; i = i + 1) {{
        local[i] = corners[i] - P;
    }}
    return fresnelLtcQuad(m, local);
}}

fn fresnelBasisRectLight(ltcLut: texture_2d<f32>, {textures}linearClamp: sampler, N: vec3f, V: vec3f, P: vec3f,
                         corners: array<vec3f, 4>, r: f32, cR: {T}, cG: {T}, cB: {T}) -> vec3f {{
    let NdotV = clamp(dot(N, V), 0.0, 1.0);
    return fresnelLtcRect(ltcLut, linearClamp, N, V, P, corners, r) * {split};
}}

fn fresnelSchlickRectLight(ltcLut: texture_2d<f32>, schlickLut: texture_2d<f32>, linearClamp: sampler, N: vec3f,
                           V: vec3f, P: vec3f, corners: array<vec3f, 4>, r: f32, f0: vec3f) -> vec3f {{
    let NdotV = clamp(dot(N, V), 0.0, 1.0);
    let s = textureSampleLevel(schlickLut, linearClamp, fresnelBasisLutUV(NdotV, r), 0.0).rg;
    return fresnelLtcRect(ltcLut, linearClamp, N, V, P, corners, r) * (f0 * s.x + s.y);
}}
"""


def glsl_include(constants: ShaderConstants, command: str) -> str:
    return _glsl(constants, command) + _area_glsl(constants)


def hlsl_include(constants: ShaderConstants, command: str) -> str:
    return _glsl(constants, command, hlsl=True) + _area_glsl(constants, hlsl=True)


def wgsl_include(constants: ShaderConstants, command: str) -> str:
    """The same functions in WGSL (no NaN test by x != x either: the bits are tested through bitcast)."""
    return _wgsl_material(constants, command) + _area_wgsl(constants)


def _wgsl_material(constants: ShaderConstants, command: str) -> str:
    c, d = constants, constants.curve_degree
    sp = _Spelling("wgsl", c.n_terms)
    T = sp.terms
    fit_constants, fit_functions, solve = _fit_parts(c, sp)
    curve_arrays, horner = _curve_parts(c, sp)
    edges, segment = _segment_parts(c, sp)
    column_x, column_x_code = _column_coordinate(c)
    projections, linear, averages, direct, average = _combination_parts(c, sp)
    fetch = "textureSampleLevel(lut, linearClamp, uv, 0.0)"
    fetch_terms = sp.make_terms(fetch, fetch.replace("(lut,", "(lut2,")) if sp.wide else fetch
    textures = "lut: texture_2d<f32>, " + ("lut2: texture_2d<f32>, " if sp.wide else "")
    return (
        _header(c, "WGSL", command)
        + f"""
const FRESNEL_BASIS_HASH: u32 = 0x{c.basis_hash[:8]}u;  // the first 8 hex digits of {c.basis_hash}
{sp.record()}{fit_constants}
{chr(10).join(projections)}
{averages}
{edges}
const FRESNEL_CURVE_DEGREE: i32 = {d};
const FRESNEL_F82_SCHLICK_WEIGHT: f32 = {_number((1.0 - F82_MU) ** 5)};
const FRESNEL_F82_DIP: f32 = {_number(lazanyi_dip(F82_MU))};
{curve_arrays}

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

{fit_functions}
fn fresnelCoefficientsSolve(f0: f32, eta: f32, kappa2: f32) -> {T} {{
    let f90 = select(1.0, 0.0, eta == 1.0 && kappa2 == 0.0);
{solve}}}

fn fresnelCoefficientsEtaKappa2(eta: f32, kappa2: f32) -> {T} {{
    return fresnelCoefficientsSolve(((eta - 1.0) * (eta - 1.0) + kappa2) / ((eta + 1.0) * (eta + 1.0) + kappa2), eta,
                                    kappa2);
}}

fn fresnelCoefficientsNK(etaIn: f32, kappaIn: f32) -> {T} {{
    let kappa = fresnelSanitize(kappaIn, 0.0, 0.0, 1e4);
    return fresnelCoefficientsEtaKappa2(fresnelSanitize(etaIn, 1.5, 1e-4, 1e4), kappa * kappa);
}}

fn fresnelGulbrandsenToEtaKappa2(r: f32, g: f32) -> vec2f {{
    let q = sqrt(r);
    let over1pr = 1.0 / (1.0 + r);
    let over1mq = 1.0 / (1.0 - q);
    let n = g * (1.0 - r) * over1pr + (1.0 - g) * (1.0 + q) * over1mq;
    return vec2f(n, 4.0 * g * r * over1pr * over1mq * (g * (1.0 - q) * over1pr + 2.0 * (1.0 - g) * over1mq));
}}

fn fresnelCoefficientsGulbrandsen(rIn: f32, gIn: f32) -> {T} {{
    let r = fresnelSanitize(rIn, 0.0, 0.0, 0.9999);
    let nk2 = fresnelGulbrandsenToEtaKappa2(r, fresnelSanitize(gIn, 0.0, 0.0, 1.0));
    return fresnelCoefficientsSolve(r, nk2.x, nk2.y);
}}

fn fresnelCoefficientsLinear(w0: f32, w1: f32, w2: f32) -> {T} {{
    return {sp.make_terms(*linear)};
}}

fn fresnelCoefficientsSchlick(f0: f32, f90: f32) -> {T} {{
    return fresnelCoefficientsLinear(fresnelSanitize(f0, 0.0, 0.0, 1.0), fresnelSanitize(f90, 0.0, 0.0, 1.0), 0.0);
}}

fn fresnelCoefficientsF82(f0In: f32, f82In: f32) -> {T} {{
    let f0 = fresnelSanitize(f0In, 0.0, 0.0, 1.0);
    let f82 = fresnelSanitize(f82In, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT - f82) / FRESNEL_F82_DIP);
}}

fn fresnelCoefficientsF82Tint(f0In: f32, tintIn: f32) -> {T} {{
    let f0 = fresnelSanitize(f0In, 0.0, 0.0, 1.0);
    let tint = fresnelSanitize(tintIn, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(f0, 1.0, -(f0 + (1.0 - f0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

fn fresnelCoefficientsGeneralizedAdobe(r0In: f32, r90In: f32, tintIn: f32) -> {T} {{
    let r0 = fresnelSanitize(r0In, 0.0, 0.0, 1.0);
    let r90 = fresnelSanitize(r90In, 0.0, 0.0, 1.0);
    let tint = fresnelSanitize(tintIn, 0.0, 0.0, 1.0);
    return fresnelCoefficientsLinear(r0, r90, -(r0 + (r90 - r0) * FRESNEL_F82_SCHLICK_WEIGHT) * (1.0 - tint) / FRESNEL_F82_DIP);
}}

fn fresnelBasisCurves(muIn: f32) -> {T} {{
    let mu = fresnelSanitize(muIn, 1.0, 0.0, 1.0);
{segment}{horner}}}

fn fresnelBasisDirect(VdotH: f32, cR: {T}, cG: {T}, cB: {T}) -> vec3f {{
    let b = fresnelBasisCurves(VdotH);
    return {direct};
}}

// {c.grid.width} x {c.grid.height}, columns at {c.grid.columns}, rows at {c.grid.rows}: u = {column_x} * scale + offset, v = clamp(r, lo, hi) * scale + offset
const FRESNEL_LUT_COLUMNS = {_vector(c.grid.column_mapping, "vec2f")};  // scale, offset
const FRESNEL_LUT_ROWS = {_vector(c.grid.row_mapping, "vec4f")};  // lo, hi, scale, offset

fn fresnelBasisLutUV(NdotV: f32, perceptualRoughness: f32) -> vec2f {{
    let r = clamp(fresnelSanitize(perceptualRoughness, 0.5, 0.0, 1.0), FRESNEL_LUT_ROWS.x, FRESNEL_LUT_ROWS.y);
    let x = {column_x_code};
    return vec2f(x * FRESNEL_LUT_COLUMNS.x + FRESNEL_LUT_COLUMNS.y, r * FRESNEL_LUT_ROWS.z + FRESNEL_LUT_ROWS.w);
}}

fn fresnelBasisSplitSumUV({textures}linearClamp: sampler, NdotV: f32, r: f32, cR: {T}, cG: {T},
                          cB: {T}) -> vec3f {{
    let uv = fresnelBasisLutUV(NdotV, r);
    let b = {fetch_terms};
    return {direct};
}}

fn fresnelBasisAverage(cR: {T}, cG: {T}, cB: {T}) -> vec3f {{
    return clamp({average},
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
    basis: Basis | None = None, command: str = "fresnel-lut build", grid: LutGrid | None = None, ltc_size: int = 64
) -> list[tuple[str, str]]:
    """(file name, text) of every generated include for ``basis`` (default: the shipped one), its tables' grid and
    the LTC table's size."""
    constants = shader_constants(basis, grid, ltc_size)
    return [(name, generate(constants, command)) for name, generate in SHADER_INCLUDES.values()]
