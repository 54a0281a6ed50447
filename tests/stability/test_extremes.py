"""Stiff and extreme regimes: α → 0, μo → 0 and μo = 1, κ → ∞ and F0 → 1, η → 1, η < 1, Gulbrandsen r → 1.

Each regime is compared with a reference that does not share the library's code path, with the tolerance
stated in the test's docstring, and checked for jumps in the parameter that approaches the limit:

* the split-sum quadrature against the same integral at a much higher order (``QuadratureOrder.uniform(128)``,
  converged to ~1e-12 here), against adaptive cubature over the half vector (tests/references/integration.py),
  and against the mirror limit F̄_k → f_k(μo)·E with |F̄_k − f_k E| ≤ 2(α/μo)² ln(1/α) (test_quadrature.py);
* Fresnel values against the complex-amplitude form, its cancellation-free 1 − F, and the 60-digit Decimal
  evaluation of tests/references/fresnel.py, and against closed forms (F0, Gulbrandsen's n_min, n_max, κ);
* coefficients against those of reference samples, and reconstruction errors against the Lebesgue bound
  (1 + Λ) · ½ range(F), which holds for any target because the four-point scheme reproduces constants.

``SCHEDULE_TOLERANCE`` = 1e-6 is the accuracy this suite already expects of the default quadrature schedule
(test_quadrature.py, test_cli.py; README: 4.0e-7 on the 128 × 128 LUT grid).
"""

from __future__ import annotations

import numpy as np
import pytest

from basis import (
    coefficients_from_gulbrandsen,
    coefficients_from_nk,
    default_basis,
    fresnel_conductor,
    gulbrandsen_to_nk,
)
from basis.angles import cos_theta
from basis.coefficients import coefficients_from_samples, fit_matrix, reconstruct, reconstruction_error
from basis.training import MIN_SPAN, GramAccumulator
from basis.validation import ParameterError
from preintegrate.channels import basis_channels
from preintegrate.quadrature import QuadratureOrder, directional_albedo
from tests.references.fresnel import fresnel_complex, fresnel_decimal, one_minus_fresnel_complex
from tests.references.integration import reference_albedo_half_vector

EPS = float(np.finfo(np.float64).eps)
SCHEDULE_TOLERANCE = 1e-6
HIGH_ORDER = QuadratureOrder.uniform(128)
FIT_MU = cos_theta(default_basis().fit_angles)
THETA = np.linspace(0.0, 0.5 * np.pi, 2001)
MU = cos_theta(THETA)
#: max_θ Σ_i |ℓ_i(θ)| for the reconstruction Σ_i F(θ_i) ℓ_i(θ) at the shipped fit angles (measured 1.48).
LEBESGUE = float(np.max(np.sum(np.abs(default_basis().evaluate(THETA) @ np.linalg.inv(fit_matrix())), axis=1)))
_BASIS = basis_channels().functions


def channels(x):
    """Channel 0: f = 1 (the no-Fresnel albedo E); 1–4: the basis b0 … b3."""
    x = np.asarray(x, dtype=np.float64)
    return np.concatenate([np.ones(x.shape + (1,)), _BASIS(x)], axis=-1)


def mirror_bound(mu_o, alpha):
    """|F̄_k − f_k(μo) E| ≤ 2 (α/μo)² ln(1/α) (second-order spread of ω_o·h; test_quadrature.py)."""
    return 2.0 * (alpha / mu_o) ** 2 * np.log(1.0 / alpha)


def assert_no_jumps(values, ratio=0.25, atol=1e-12):
    """On a fine grid a smooth sequence has |Δ²| ≪ |Δ|; an isolated jump J makes |Δ²| ≈ |Δ| ≈ J."""
    values = np.asarray(values)
    first, second = np.abs(np.diff(values, axis=0)), np.abs(np.diff(values, 2, axis=0))
    assert np.max(second) <= ratio * np.max(first) + atol, (np.max(second), np.max(first))


def lebesgue_bound(curves):
    """(1 + Λ) · ½ (max − min) over θ, per curve: no four-point fit of that curve can be worse."""
    return (1.0 + LEBESGUE) * 0.5 * np.ptp(curves, axis=-1)


# ============================================================================= α → 0
ALPHA_SMALL = np.geomspace(1e-6, 1e-3, 13)
MU_SMALL_ALPHA = np.array([1e-3, 0.01, 0.1, 0.5, 1.0])


def test_alpha_to_zero_default_matches_order_128():
    """α ∈ [1e-6, 1e-3] (13 values) × μo ∈ {1e-3 … 1}: the default schedule equals order 128 within 1e-6 on f = 1
    and the four basis channels (no quadrature breakdown as the GGX lobe narrows)."""
    values = directional_albedo(channels, MU_SMALL_ALPHA[None, :], ALPHA_SMALL[:, None])
    reference = directional_albedo(channels, MU_SMALL_ALPHA[None, :], ALPHA_SMALL[:, None], order=HIGH_ORDER)
    assert np.all(np.isfinite(values))
    np.testing.assert_allclose(values, reference, rtol=0, atol=SCHEDULE_TOLERANCE)


@pytest.mark.parametrize("mu_o", [0.05, 0.5, 1.0])
def test_alpha_1e4_matches_half_vector_cubature(mu_o):
    """α = 1e-4: default schedule equals adaptive cubature over the half vector (independent code; ~1e-9) within 1e-6."""
    np.testing.assert_allclose(
        directional_albedo(channels, mu_o, 1e-4), reference_albedo_half_vector(channels, mu_o, 1e-4), rtol=0, atol=1e-6
    )


def test_alpha_approaches_the_mirror_branch_continuously():
    """α from 1e-6 down to 1e-12 (13 values) joins the α = 0 branch (F̄ = f(μo), the mirror): |F̄(α) − F̄(0)| ≤
    2 · 2(α/μo)² ln(1/α) + 1e-6 (mirror limit for f_k and for 1 − E, plus the schedule's accuracy)."""
    alphas = np.geomspace(1e-6, 1e-12, 13)
    mu_o = np.array([1e-3, 0.1, 0.5, 1.0])
    values = directional_albedo(channels, mu_o[None, :], alphas[:, None])
    mirror = directional_albedo(channels, mu_o, 0.0)
    np.testing.assert_array_equal(mirror, channels(mu_o))
    bound = 2.0 * mirror_bound(mu_o[None, :], alphas[:, None]) + SCHEDULE_TOLERANCE
    assert np.all(np.abs(values - mirror[None]) <= bound[..., None])


@pytest.mark.parametrize("alpha", [1e-14, 1e-16, 1e-20, 1e-30])
def test_alpha_below_1e13_default_matches_order_128(alpha):
    """α ∈ {1e-14 … 1e-30}, μo ∈ {0.1, 0.5, 1}: default schedule within 1e-6 of order 128 (which is within 3e-14 of
    the mirror value f(μo) there)."""
    mu_o = np.array([0.1, 0.5, 1.0])
    reference = directional_albedo(channels, mu_o, alpha, order=HIGH_ORDER)
    np.testing.assert_allclose(reference, channels(mu_o), rtol=0, atol=1e-12)
    np.testing.assert_allclose(directional_albedo(channels, mu_o, alpha), reference, rtol=0, atol=SCHEDULE_TOLERANCE)


def test_tiny_alpha_albedo_at_most_one():
    """α = 10^(−9 … −12) on 16 values × μo = 0 … 1 (21 values): the no-Fresnel albedo E ≤ 1 + 2^-24."""
    alphas = np.geomspace(1e-9, 1e-12, 16)
    mu_o = np.linspace(0.0, 1.0, 21)
    albedo = directional_albedo(lambda x: np.ones(np.shape(x) + (1,)), mu_o[None, :], alphas[:, None])[..., 0]
    assert np.max(albedo) <= 1.0 + 2.0**-24, np.max(albedo) - 1.0


def albedo_at_equal_small_angles():
    """E(1e-6, 1e-6) at order 128 (0.8920754915), the limit of E(s, s) as s → 0."""
    return directional_albedo(channels, 1e-6, 1e-6, order=HIGH_ORDER)[0]


@pytest.mark.parametrize("mu_o, alpha", [(0.0, 1e-100), (0.0, 1e-150), (1e-10, 1e-10), (1e-12, 1e-12)])
def test_grazing_with_vanishing_alpha(mu_o, alpha):
    """μo = 0 with α down to 1e-150: E = 1 (grazing limit; order 128 gives 1 to 1e-12); μo = α = 1e-10, 1e-12:
    E = E(1e-6, 1e-6) (for μo, α ≪ 1 the albedo depends on α/μo only); atol 1e-6."""
    expected = 1.0 if mu_o == 0.0 else albedo_at_equal_small_angles()
    np.testing.assert_allclose(directional_albedo(channels, mu_o, alpha)[0], expected, rtol=0, atol=SCHEDULE_TOLERANCE)


@pytest.mark.parametrize("mu_o, alpha", [(1e-15, 1e-15), (1e-20, 1e-20), (1e-150, 1e-150), (1e-20, 1e-21)])
def test_tiny_view_cosine_with_comparable_alpha(mu_o, alpha):
    """μo = α (or α = μo/10) below 1e-13: E equals its value at the same ratio α/μo at μo = 1e-6 (atol 1e-6)."""
    expected = directional_albedo(channels, 1e-6, 1e-6 * alpha / mu_o, order=HIGH_ORDER)[0]
    np.testing.assert_allclose(directional_albedo(channels, mu_o, alpha)[0], expected, rtol=0, atol=SCHEDULE_TOLERANCE)


@pytest.mark.parametrize("mu_o, alpha", [(0.0, 1e-160), (0.0, 1e-200), (0.0, 1e-300), (0.0, 5e-324), (1e-150, 1e-150)])
def test_grazing_with_underflowing_alpha(mu_o, alpha):
    """μo = 0 or μo = α with α² at or below the smallest normal double: E as in test_grazing_with_vanishing_alpha
    (atol 1e-6). Positive α below 1e-150 is integrated as 1e-150 (documented), so μo = α is tested at 1e-150."""
    expected = 1.0 if mu_o == 0.0 else albedo_at_equal_small_angles()
    np.testing.assert_allclose(directional_albedo(channels, mu_o, alpha)[0], expected, rtol=0, atol=SCHEDULE_TOLERANCE)


# ============================================================================= μo → 0 and μo = 1
MU_GRAZING = np.geomspace(1e-6, 1e-1, 11)


def test_grazing_view_default_matches_order_128():
    """μo ∈ [1e-6, 0.1] (11 values) × α ∈ {1e-3, 0.1, 0.5, 1}: default schedule within 1e-6 of order 128; finite."""
    alphas = np.array([1e-3, 0.1, 0.5, 1.0])
    values = directional_albedo(channels, MU_GRAZING[None, :], alphas[:, None])
    reference = directional_albedo(channels, MU_GRAZING[None, :], alphas[:, None], order=HIGH_ORDER)
    assert np.all(np.isfinite(values))
    np.testing.assert_allclose(values, reference, rtol=0, atol=SCHEDULE_TOLERANCE)


@pytest.mark.parametrize("mu_o, alpha", [(1e-3, 1e-2), (1e-3, 10**-2.5), (0.5 / 256, (30.5 / 256) ** 2)])
def test_stiff_tier_default_matches_order_128(mu_o, alpha):
    """(μo, α) in the stiff tier between the 128-grid texels: default schedule within 1e-6 of order 128."""
    np.testing.assert_allclose(
        directional_albedo(channels, mu_o, alpha),
        directional_albedo(channels, mu_o, alpha, order=HIGH_ORDER),
        rtol=0,
        atol=SCHEDULE_TOLERANCE,
    )


@pytest.mark.parametrize("boundary", ["mu 1e-3", "mu 0.1", "alpha 1e-4"])
def test_schedule_tier_boundaries_do_not_jump(boundary):
    """Across the schedule's tier boundaries (μo = 1e-3, μo = 0.1, α = 1e-4; the neighbouring double vs the
    boundary) F̄ changes by ≤ 1e-6 on every channel (order 128 changes by < 1e-15 there)."""
    if boundary.startswith("mu"):
        edge = float(boundary.split()[1])
        mu_o, alpha = (
            np.array([np.nextafter(edge, 0.0), edge])[None, :],
            np.array([1e-5, 1e-3, 0.05, 0.5, 1.0])[:, None],
        )
        values = directional_albedo(channels, mu_o, alpha)
        jump = np.abs(values[:, 1] - values[:, 0])
    else:
        mu_o, alpha = np.array([0.01, 0.2, 0.5, 1.0])[None, :], np.array([np.nextafter(1e-4, 0.0), 1e-4])[:, None]
        values = directional_albedo(channels, mu_o, alpha)
        jump = np.abs(values[1] - values[0])
    assert np.max(jump) <= SCHEDULE_TOLERANCE


@pytest.mark.parametrize("alpha", [1e-6, 1e-3, 0.1, 1.0])
def test_normal_view_is_continuous(alpha):
    """μo = 1 exactly (sin θo = 0; the horizon cut divides by it) joins μo = 1 − δ, δ = 1e-16 … 1e-4, without a
    jump. Order 128 is smooth: |F̄(1 − δ) − F̄(1)| ≤ 0.5 δ + 1e-13 (measured slope ≤ 0.2). The default schedule
    adds its quadrature error, which grows like sin θo (piece B has width ∝ θo): ≤ 0.5 δ + 4e-6 sin θo (measured
    2e-6 sin θo), → 0 as δ → 0. F̄(1) is within 1e-6 of order 128."""
    deltas = np.geomspace(1e-16, 1e-4, 13)
    mu_o = np.concatenate([[1.0], 1.0 - deltas])
    sin_o = np.sqrt(deltas * (2.0 - deltas))
    reference = directional_albedo(channels, mu_o, alpha, order=HIGH_ORDER)
    assert np.all(np.abs(reference[1:] - reference[0]) <= (0.5 * deltas + 1e-13)[:, None])
    values = directional_albedo(channels, mu_o, alpha)
    assert np.all(np.abs(values[1:] - values[0]) <= (0.5 * deltas + 4e-6 * sin_o)[:, None])
    np.testing.assert_allclose(values[0], reference[0], rtol=0, atol=SCHEDULE_TOLERANCE)


# ============================================================================= κ → ∞, F0 → 1
KAPPA_LARGE = np.geomspace(1.0, 1e6, 25)
ETA_WITH_KAPPA = np.array([0.05, 1.0, 3.0, 50.0])


def test_large_kappa_end_coefficients_are_exact():
    """κ = 1 … 1e6 (F0 → 1) × η ∈ {0.05, 1, 3, 50}: finite; c0 = F0 = ((η−1)² + κ²)/((η+1)² + κ²) and
    c1 = 1 − F0 = 4η/((η+1)² + κ²) (cancellation-free closed form) to 2 ulp(1) = 4.4e-16 absolute."""
    eta, kappa = np.meshgrid(ETA_WITH_KAPPA, KAPPA_LARGE, indexing="ij")
    coefficients = coefficients_from_nk(eta, kappa)
    assert np.all(np.isfinite(coefficients))
    denominator = (eta + 1.0) ** 2 + kappa**2
    np.testing.assert_allclose(coefficients[..., 0], ((eta - 1.0) ** 2 + kappa**2) / denominator, rtol=0, atol=2 * EPS)
    np.testing.assert_allclose(coefficients[..., 1], 4.0 * eta / denominator, rtol=0, atol=2 * EPS)


def test_large_kappa_coefficients_match_complex_reference_and_do_not_jump():
    """κ = 1 … 1e3 on 241 values per η: coefficients equal those of the samples 1 − (cancellation-free complex
    1 − F) (atol 1e-12), and have no jumps in log κ (max |Δ²c| ≤ ¼ max |Δc|)."""
    kappa = np.geomspace(1.0, 1e3, 241)
    for eta in ETA_WITH_KAPPA:
        coefficients = coefficients_from_nk(eta, kappa)
        samples = 1.0 - one_minus_fresnel_complex(FIT_MU[None, :], eta, kappa[:, None])
        np.testing.assert_allclose(coefficients, coefficients_from_samples(samples), rtol=0, atol=1e-12)
        assert_no_jumps(coefficients)


def test_large_kappa_reconstruction_error_shrinks_with_the_curve():
    """κ = 10 … 1e6: max |Σ c b − F| over 2001 angles ≤ (1 + Λ) · ½ (1 − min F) (Lebesgue bound; reference F from
    the cancellation-free complex form), so it vanishes as F → 1; at κ = 1e6 it is below 1e-5."""
    kappa = np.geomspace(10.0, 1e6, 21)
    for eta in ETA_WITH_KAPPA:
        coefficients = coefficients_from_nk(eta, kappa)
        exact = 1.0 - one_minus_fresnel_complex(MU[None, :], eta, kappa[:, None])
        max_abs, _ = reconstruction_error(coefficients, THETA, exact)
        assert np.all(max_abs <= lebesgue_bound(exact) + 1e-12)
        assert max_abs[-1] < 1e-5


def test_normalisation_with_vanishing_span():
    """The SVD's normalisation (F − F0)/(F90 − F0) for η = 1, κ = 10 … 1e6 (span 4e-2 … 4e-12): curves with
    span ≤ MIN_SPAN (1e-9) are skipped, not divided; every kept one is finite, exactly 0 at θ = 0 and 1 at π/2,
    and within 4ε (2 + |F̂|) / span of the cancellation-free reference 1 − (1 − F)/(1 − F0)."""
    basis = default_basis()
    mu = cos_theta(basis.theta)
    for kappa in [10.0, 1e2, 1e3, 1e4, 3e4, 1e5, 1e6]:
        accumulator = GramAccumulator(basis.theta)
        accumulator.add(fresnel_conductor(mu, 1.0, kappa)[None, :])
        one_minus = one_minus_fresnel_complex(mu, 1.0, kappa)
        span = one_minus[0]
        if span <= MIN_SPAN:
            assert (accumulator.count, accumulator.skipped) == (0, 1)
            assert np.all(accumulator.gram == 0.0)
            continue
        assert accumulator.count == 1 and np.all(np.isfinite(accumulator.gram))
        weights = accumulator.sqrt_weights
        normalised = accumulator.total / np.where(weights > 0.0, weights, 1.0)
        assert normalised[0] == 0.0 and normalised[-1] == 1.0
        reference = 1.0 - one_minus / span
        assert np.all(np.abs(normalised - reference) <= 4.0 * EPS * (2.0 + np.abs(reference)) / span)


# ============================================================================= η → 1, κ = 0
DELTAS = np.geomspace(1e-2, 1e-12, 11)
#: Coefficients of the limit curve (F = 0 for θ < π/2, F(π/2) = 1): the grazing spike the curve collapses to.
SPIKE = coefficients_from_samples(np.array([0.0, 1.0, 0.0, 0.0]))


@pytest.mark.parametrize("side", [1.0, -1.0])
def test_index_matched_limit_coefficients(side):
    """η = 1 ± δ, δ = 1e-2 … 1e-12, κ = 0: coefficients equal those of the 60-digit Decimal samples (atol 1e-15);
    c0 = ((η−1)/(η+1))² (atol 2^-52); as δ → 0 they converge to the spike's c* = B⁻¹(0, 1, 0, 0):
    |c − c*| ≤ 2.7e4 δ² for δ ≤ 1e-4 (F(θ_i) ≈ (δ/2μ_i²)², ‖B⁻¹‖∞ = 2.69), and monotonically (to 2^-52)."""
    eta = 1.0 + side * DELTAS
    coefficients = coefficients_from_nk(eta, 0.0)
    decimal = np.array([[fresnel_decimal(mu, e, 0.0) for mu in FIT_MU] for e in eta])
    np.testing.assert_allclose(coefficients, coefficients_from_samples(decimal), rtol=0, atol=1e-15)
    np.testing.assert_allclose(coefficients[:, 0], ((eta - 1.0) / (eta + 1.0)) ** 2, rtol=0, atol=EPS)
    distance = np.max(np.abs(coefficients - SPIKE), axis=1)
    assert np.all(np.diff(distance) <= EPS)  # monotone down to rounding (the last steps are ~1e-16)
    small = DELTAS <= 1e-4
    assert np.all(distance[small] <= 2.7e4 * DELTAS[small] ** 2 + 1e-15)


def test_index_matched_interface_itself():
    """η = 1, κ = 0 exactly is no interface: F ≡ 0 and c = 0 (exact); the limit η → 1 is c* ≠ 0: the one physical
    discontinuity of the coefficients (a spike of zero width at θ = π/2)."""
    np.testing.assert_array_equal(coefficients_from_nk(1.0, 0.0), np.zeros(4))
    assert np.max(np.abs(SPIKE)) > 0.2


@pytest.mark.parametrize("kappa", [1e-100, 1e-150, 1e-160])
def test_index_matched_with_vanishing_kappa(kappa):
    """η = 1 with a trace of absorption κ down to 1e-160 is an interface: F(μ = 0) = 1 exactly and c1 = 1 (atol
    1e-15), however narrow the grazing spike."""
    assert fresnel_conductor(0.0, 1.0, kappa) == 1.0
    np.testing.assert_allclose(coefficients_from_nk(1.0, kappa)[1], 1.0, rtol=0, atol=1e-15)


@pytest.mark.parametrize("kappa", [1e-162, 1e-200, 5e-324])
def test_index_matched_with_underflowing_kappa(kappa):
    """η = 1, κ > 0 below √(smallest double): F(μ = 0) = 1 and c1 = 1, as for κ = 1e-160."""
    assert fresnel_conductor(0.0, 1.0, kappa) == 1.0
    np.testing.assert_allclose(coefficients_from_nk(1.0, kappa)[1], 1.0, rtol=0, atol=1e-15)


def test_index_matched_reconstruction_error_is_bounded():
    """η = 1 ± δ: the error of Σ c b against the exact curve (complex form, 2001 angles) stays within the Lebesgue
    bound (1 + Λ)/2 ≈ 1.24 and tends to max_θ<π/2 |Σ c*_k b_k(θ)| (atol 1e-6 at δ = 1e-9): four smooth terms cannot
    follow the spike (see README, Known limits)."""
    for side in (1.0, -1.0):
        eta = 1.0 + side * DELTAS
        exact = fresnel_complex(MU[None, :], eta[:, None], 0.0)
        max_abs, _ = reconstruction_error(coefficients_from_nk(eta, 0.0), THETA, exact)
        assert np.all(max_abs <= lebesgue_bound(exact) + 1e-12)
        spike_error = np.max(np.abs(reconstruct(SPIKE, MU[:-1])))
        np.testing.assert_allclose(max_abs[np.isclose(DELTAS, 1e-9, rtol=1e-9, atol=0)], spike_error, rtol=0, atol=1e-6)


# ============================================================================= η < 1 (internal reflection)
def test_internal_reflection_coefficients_match_reference():
    """κ = 0, η = 0.05 … 0.999 (60 values): coefficients equal those of complex-form samples (atol 1e-12); fit
    angles past the critical angle sample exactly F = 1; c0 = ((1−η)/(1+η))² (atol 2^-52); the reconstruction
    error is within the Lebesgue bound (reported by reconstruction_error)."""
    eta = np.linspace(0.05, 0.999, 60)
    coefficients = coefficients_from_nk(eta, 0.0)
    samples = fresnel_complex(FIT_MU[None, :], eta[:, None], 0.0)
    np.testing.assert_allclose(coefficients, coefficients_from_samples(samples), rtol=0, atol=1e-12)
    np.testing.assert_allclose(coefficients[:, 0], ((1.0 - eta) / (1.0 + eta)) ** 2, rtol=0, atol=EPS)
    past_critical = np.sin(default_basis().fit_angles)[None, :] > eta[:, None]
    assert np.all(fresnel_conductor(FIT_MU[None, :], eta[:, None], 0.0)[past_critical] == 1.0)
    exact = fresnel_complex(MU[None, :], eta[:, None], 0.0)
    max_abs, _ = reconstruction_error(coefficients, THETA, exact)
    assert np.all(max_abs <= lebesgue_bound(exact) + 1e-12)


@pytest.mark.parametrize("fit_angle", [1.5, 1.26])
def test_internal_reflection_critical_angle_crossing_is_continuous(fit_angle):
    """As the critical angle crosses a fit angle (η = sin θ_i), F(θ_i) has a square-root corner, so the
    coefficients move by ≤ 60 √h for η = sin θ_i ± h, h = 1e-4 … 1e-12 (measured 51 √h and 18 √h): no jump."""
    critical = np.sin(fit_angle)
    at = coefficients_from_nk(critical, 0.0)
    for h in np.geomspace(1e-4, 1e-12, 9):
        for side in (-1.0, 1.0):
            assert np.max(np.abs(coefficients_from_nk(critical + side * h, 0.0) - at)) <= 60.0 * np.sqrt(h)


# ============================================================================= Gulbrandsen r → 1
R_G1 = 1.0 - np.geomspace(1e-1, 2e-8, 101)  # η = (1 − r)/(1 + r) ≥ 1e-8: inside the accepted η range
R_G0 = 1.0 - np.geomspace(1e-1, 4.01e-6, 101)  # η = (1 + √r)/(1 − √r) ≤ 1e6: inside the accepted η range


def test_gulbrandsen_full_edge_tint_to_one():
    """g = 1, r → 1 − 2e-8: η = (1 − r)/(1 + r) (rtol 2ε) and κ = 2√r/(1 + r) (closed form of eq. 8–9 at
    n = n_min; rtol 4ε/(1 − r): the library's k² = (r(n+1)² − (n−1)²)/(1 − r) cancels); F0 = r (atol 2^-52),
    c0 = r and c1 = 1 − r (atol 2 ulp(1): a 4-term dot product with B⁻¹); no jumps in log(1 − r)."""
    eta, kappa = gulbrandsen_to_nk(R_G1, 1.0)
    np.testing.assert_allclose(eta, (1.0 - R_G1) / (1.0 + R_G1), rtol=2 * EPS, atol=0)
    closed = 2.0 * np.sqrt(R_G1) / (1.0 + R_G1)
    assert np.all(np.abs(kappa / closed - 1.0) <= 4.0 * EPS / (1.0 - R_G1))
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), R_G1, rtol=0, atol=EPS)
    coefficients = coefficients_from_gulbrandsen(R_G1, 1.0)
    assert np.all(np.isfinite(coefficients))
    np.testing.assert_allclose(coefficients[:, 0], R_G1, rtol=0, atol=2 * EPS)
    np.testing.assert_allclose(coefficients[:, 1], 1.0 - R_G1, rtol=0, atol=2 * EPS)
    assert_no_jumps(coefficients)


def test_gulbrandsen_zero_edge_tint_to_one():
    """g = 0 (a dielectric), r → 1 − 4.01e-6 (η → 1e6, the top of its range): η = (1 + √r)/(1 − √r) (rtol
    4ε/(1 − √r)); κ, which is 0 in exact arithmetic, is only the rounding of eq. 9's cancelling numerator,
    κ ≤ 2√ε (η + 1)/√(1 − r) (measured up to 5.5 at η = 1e6), and leaves F practically untouched: F(μ; η, κ) =
    F(μ; η, 0) on 2001 angles within 1e-12 (measured 1.2e-13, near grazing) and F0 = r (atol 2 ulp(1)).
    Coefficients finite, equal to those of complex-form samples    (atol 1e-12), no jumps in log(1 − r)."""
    eta, kappa = gulbrandsen_to_nk(R_G0, 0.0)
    root = np.sqrt(R_G0)
    assert np.all(np.abs(eta / ((1.0 + root) / (1.0 - root)) - 1.0) <= 4.0 * EPS / (1.0 - root))
    assert np.all(kappa <= 2.0 * np.sqrt(EPS) * (eta + 1.0) / np.sqrt(1.0 - R_G0))
    np.testing.assert_allclose(
        fresnel_conductor(MU[None, :], eta[:, None], kappa[:, None]),
        fresnel_conductor(MU[None, :], eta[:, None], 0.0),
        rtol=0,
        atol=1e-12,
    )
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), R_G0, rtol=0, atol=2 * EPS)
    coefficients = coefficients_from_gulbrandsen(R_G0, 0.0)
    samples = fresnel_complex(FIT_MU[None, :], eta[:, None], 0.0)
    np.testing.assert_allclose(coefficients, coefficients_from_samples(samples), rtol=0, atol=1e-12)
    assert_no_jumps(coefficients)


@pytest.mark.parametrize(
    "reflectivity, edge_tint",
    [
        (1.0 - 1e-7, 0.0),
        (1.0 - 1e-9, 0.0),
        (1.0 - 1e-9, 1.0),
        (1.0 - 1e-12, 1.0),
        (float(np.nextafter(1.0, 0.0)), 0.0),
        (float(np.nextafter(1.0, 0.0)), 1.0),
    ],
)
def test_gulbrandsen_reflectivity_next_to_one(reflectivity, edge_tint):
    """r in its documented range [0, 1) next to 1: either finite coefficients with c0 = r (atol 1e-12), or a
    ParameterError that names reflectivity (the argument given) — never an error about η."""
    try:
        coefficients = coefficients_from_gulbrandsen(reflectivity, edge_tint)
    except ParameterError as error:
        assert str(error).startswith("reflectivity"), str(error)
    else:
        assert np.all(np.isfinite(coefficients))
        np.testing.assert_allclose(coefficients[0], reflectivity, rtol=0, atol=1e-12)
