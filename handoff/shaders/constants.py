"""What a shader include of one basis holds, computed from the basis: the fit angles and the constant inverse of the
K-point system, the projections of the linear artist models, the hemispherical averages, and the direct-light
curves fitted as polynomials in the warped cosine (Belcour, Bati, Barla 2020, eq. 4-5 and "Coefficients").

Public objects: ``ShaderConstants``, ``shader_constants``, ``warped_cosine``, ``unwarped_cosine``, ``linear_functions``,
``segment_map``, ``PER_PIXEL_MODELS``, ``CURVE_WARPS``, ``CURVE_SEGMENTS``, ``FINE_CURVE_SEGMENTS``, ``CURVE_TOLERANCE``,
``ETA_LIMITS``, ``KAPPA_LIMITS``, ``REFLECTIVITY_LIMITS``.

The direct-light curves: F(V·H) = Σ_k c_k b_k(θ_h), b_0 = 1 and b_1 … b_(K−1) as one polynomial in the warped
cosine x = μ (1 + w)/(1 + w μ) (a Möbius map that stretches grazing, where the curves steepen: one polynomial in μ
or θ needs degree 16–24 for 1e-4; in x, degree 12 holds the shipped basis to 2.2e-5), else (the higher terms of
K > 4 bases) as piecewise polynomials in μ over :data:`CURVE_SEGMENTS` or :data:`FINE_CURVE_SEGMENTS`, within
:data:`CURVE_TOLERANCE` of the basis' own spline in float64.
"""

from __future__ import annotations

import dataclasses
import functools
from typing import NamedTuple

import numpy as np

from basis.angles import cos_theta
from basis.coefficients import coefficients_from_samples
from basis.eigenbasis import Basis, resolve_basis
from basis.models.formulas import lazanyi_dip, schlick_weight
from basis.validation import check_positive_int
from preintegrate.lut import LutGrid

__all__ = [
    "CURVE_SEGMENTS",
    "CURVE_TOLERANCE",
    "CURVE_WARPS",
    "ETA_LIMITS",
    "FINE_CURVE_SEGMENTS",
    "KAPPA_LIMITS",
    "PER_PIXEL_MODELS",
    "REFLECTIVITY_LIMITS",
    "ShaderConstants",
    "linear_functions",
    "segment_map",
    "shader_constants",
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
    # role → (scale u, scale v, offset u, offset v) of each table in one atlas (handoff.atlas), None: a texture each
    atlas: dict | None = None
    # whether the include offers the per-pixel tables' functions (a build with --pixel-tables writes their tables for
    # this basis; a scene, which writes none for its own basis, leaves them out)
    pixel_tables: bool = True

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


def linear_functions(mu: np.ndarray) -> np.ndarray:
    """(…, 3): the fixed functions of the linear artist models, t = (1 − (1 − μ)⁵, (1 − μ)⁵, μ (1 − μ)⁶)."""
    fifth = schlick_weight(mu)
    return np.stack([1.0 - fifth, fifth, lazanyi_dip(mu)], axis=-1)


def shader_constants(
    basis: Basis | None = None,
    grid: LutGrid | None = None,
    ltc_size: int = 64,
    atlas: dict | None = None,
    pixel_tables: bool = True,
) -> ShaderConstants:
    """The constants of :func:`shader_includes` for a basis of 2 … 8 terms (default: the shipped one), the grid of
    its tables (default: the default build's 128 × 128) and, for an include that reads one atlas, each table's map into
    it (role → (scale u, scale v, offset u, offset v); :class:`handoff.atlas.AtlasLayout`); ``pixel_tables`` False
    leaves the functions of the per-pixel tables out of the include (a scene's basis has none)."""
    basis = resolve_basis(basis)
    system = basis.evaluate(basis.fit_angles)  # B[i, k] = b_k(θ_i)
    inverse = np.linalg.inv(system[2:, 2:])
    projections = coefficients_from_samples(linear_functions(cos_theta(basis.fit_angles)).T, basis)
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
        None if atlas is None else dict(atlas),
        bool(pixel_tables),
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


def segment_map(edges) -> tuple[np.ndarray, np.ndarray]:
    """(scale, offset) per segment: s = x · scale + offset maps [lo, hi] onto [−1, 1] without a division."""
    low, high = np.asarray(edges[:-1], dtype=np.float64), np.asarray(edges[1:], dtype=np.float64)
    return 2.0 / (high - low), -(high + low) / (high - low)


def warped_cosine(mu: np.ndarray, warp: float) -> np.ndarray:
    """x = μ (1 + w)/(1 + w μ): [0, 1] onto [0, 1], slope 1 + w at grazing and 1/(1 + w) at normal incidence."""
    return mu * (1.0 + warp) / (1.0 + warp * mu)


def unwarped_cosine(x: np.ndarray, warp: float) -> np.ndarray:
    """μ of x (the inverse of :func:`warped_cosine`), clipped to [0, 1] against rounding."""
    return np.clip(x / (1.0 + warp - warp * x), 0.0, 1.0)
