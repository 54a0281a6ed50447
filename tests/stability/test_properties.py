"""Property-based tests (hypothesis) over the whole documented parameter domain.

Domains (the documented ones, boundaries included): Fresnel μ ∈ [0, 1], η ∈ [1e-8, 1e6], κ ∈ [0, 1e6];
Gulbrandsen r ∈ [0, 1), g ∈ [0, 1]; the split sum μo, α ∈ [0, 1]. What is asserted is what the maths
guarantees: finiteness; 0 ≤ F ≤ 1 (energy conservation); F(0°) in closed form; F non-increasing in μ from
grazing down to Brewster's angle for every dielectric (both polarisations grow with θ there); the four-point
fit within the Lebesgue bound (1 + Λ) · ½ range(F) of any curve; E ≤ 1 for the no-Fresnel albedo; and
|F̄[b_k]| ≤ max|b_k| · F̄[1] because the quadrature weights and the BRDF kernel are non-negative.

Runs derandomised (fixed examples, reproducible in CI) with deadline=None. Where a documented region is a known
failure, it gets its own strict-xfail property pinned by an @example, so the union still covers the domain. One more
known failure was found by a randomised run of these properties (6000 examples each): F(μ = 0; η = 1, κ ≤ 1e-162) = 0
instead of 1 (κ² underflows); it is pinned in test_stability_extremes.py::test_index_matched_with_underflowing_kappa.
"""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

from basis import (
    coefficients_from_gulbrandsen,
    coefficients_from_nk,
    default_basis,
    fresnel_conductor,
    fresnel_dielectric,
    gulbrandsen_to_nk,
)
from basis.angles import cos_theta
from basis.coefficients import fit_matrix, reconstruct, reconstruction_error
from preintegrate.channels import basis_channels
from preintegrate.quadrature import directional_albedo

PROPERTY = settings(max_examples=400, deadline=None, derandomize=True)
QUADRATURE_PROPERTY = settings(max_examples=150, deadline=None, derandomize=True)


def unit_floats(low=0.0, high=1.0, **kwargs):
    return st.floats(min_value=low, max_value=high, allow_nan=False, allow_infinity=False, **kwargs)


MU = unit_floats()
ETA = unit_floats(1e-8, 1e6)
KAPPA = unit_floats(0.0, 1e6)
REFLECTIVITY = unit_floats(0.0, 1.0, exclude_max=True)
EDGE_TINT = unit_floats()
THETA = np.linspace(0.0, 0.5 * np.pi, 257)
MU_GRID = cos_theta(THETA)
LEBESGUE = float(np.max(np.sum(np.abs(default_basis().evaluate(THETA) @ np.linalg.inv(fit_matrix())), axis=1)))
FLOAT32_HALF_ULP = 2.0**-24
_BASIS = basis_channels().functions
#: sup over x ∈ [0, 1] of |b_k(arccos x)| on 100001 points, with 1e-6 of room for the spline between them.
BASIS_MAX = np.max(np.abs(_BASIS(np.linspace(0.0, 1.0, 100001))), axis=0) * (1.0 + 1e-6)


def one(x):
    return np.ones(np.shape(x) + (1,))


def closed_form_f0(eta, kappa):
    """F(θ = 0) = ((η − 1)² + κ²)/((η + 1)² + κ²)."""
    return ((eta - 1.0) ** 2 + kappa**2) / ((eta + 1.0) ** 2 + kappa**2)


# ----------------------------------------------------------------------------- Fresnel
@PROPERTY
@given(mu=MU, eta=ETA, kappa=KAPPA)
@example(mu=0.0, eta=1e-8, kappa=0.0)
@example(mu=1.0, eta=1e6, kappa=1e6)
@example(mu=5e-324, eta=1.0, kappa=0.0)
def test_fresnel_whole_domain_finite_bounded_closed_forms(mu, eta, kappa):
    """Whole domain: F finite, 0 ≤ F ≤ 1; F(μ = 1) = closed form (atol 1e-12); F(μ = 0) = 1 unless η = 1, κ = 0."""
    value = float(fresnel_conductor(mu, eta, kappa))
    assert np.isfinite(value) and 0.0 <= value <= 1.0
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), closed_form_f0(eta, kappa), rtol=0, atol=1e-12)
    if eta != 1.0 or kappa > 0.0:
        assert fresnel_conductor(0.0, eta, kappa) == 1.0


@PROPERTY
@given(eta=ETA.filter(lambda eta: eta != 1.0))
@example(eta=1e-8)
@example(eta=1e6)
@example(eta=1.0 + 1e-12)
def test_dielectric_non_increasing_between_grazing_and_brewster(eta):
    """κ = 0, every η ≠ 1 in [1e-8, 1e6]: F non-increasing in μ on [0, μ_B], μ_B = 1/√(1 + η²) (R_s grows with θ
    everywhere, R_p from Brewster's angle on; internal reflection included); 257 points, tolerance 1e-13."""
    mu = np.linspace(0.0, 1.0 / np.sqrt(1.0 + eta * eta), 257)
    assert np.all(np.diff(fresnel_dielectric(mu, eta)) <= 1e-13)


# ----------------------------------------------------------------------------- Gulbrandsen
@PROPERTY
@given(reflectivity=REFLECTIVITY, edge_tint=EDGE_TINT)
@example(reflectivity=float(np.nextafter(1.0, 0.0)), edge_tint=0.0)
@example(reflectivity=float(np.nextafter(1.0, 0.0)), edge_tint=1.0)
@example(reflectivity=0.0, edge_tint=0.5)
def test_gulbrandsen_whole_domain(reflectivity, edge_tint):
    """Whole domain r ∈ [0, 1), g ∈ [0, 1]: η, κ finite, η > 0, κ ≥ 0, and the closed-form F0 of (η, κ) is r
    (atol 1e-12): eq. 7–9 define a material with the requested reflectivity even where η leaves [1e-8, 1e6]."""
    eta, kappa = gulbrandsen_to_nk(reflectivity, edge_tint)
    assert np.isfinite(eta) and np.isfinite(kappa) and eta > 0.0 and kappa >= 0.0
    np.testing.assert_allclose(closed_form_f0(eta, kappa), reflectivity, rtol=0, atol=1e-12)


#: g = 0 maps r to η = (1 + √r)/(1 − √r) ≤ 1e6 only for r ≤ 1 − 4.000004e-6, g = 1 to η = (1 − r)/(1 + r) ≥ 1e-8 only
#: for r ≤ 1 − 2e-8; past that coefficients_from_gulbrandsen fails (test_stability_extremes.py,
#: test_gulbrandsen_reflectivity_next_to_one, strict xfail). This property takes the part of [0, 1) every g accepts.
REFLECTIVITY_ACCEPTED = unit_floats(0.0, 1.0 - 4.01e-6)


@PROPERTY
@given(reflectivity=REFLECTIVITY_ACCEPTED, edge_tint=EDGE_TINT)
@example(reflectivity=1.0 - 4.01e-6, edge_tint=0.0)
@example(reflectivity=1.0 - 4.01e-6, edge_tint=1.0)
def test_gulbrandsen_coefficients(reflectivity, edge_tint):
    """r ∈ [0, 1 − 4.01e-6], g ∈ [0, 1]: coefficients finite, c0 = r (atol 1e-12), c1 = 1 − r (atol 1e-12) — except
    r = 0, which is η = 1, κ = 0 for every g (no interface, F ≡ 0): c = 0 exactly."""
    coefficients = coefficients_from_gulbrandsen(reflectivity, edge_tint)
    assert np.all(np.isfinite(coefficients))
    if reflectivity == 0.0:
        np.testing.assert_array_equal(coefficients, np.zeros(4))
    else:
        np.testing.assert_allclose(coefficients[:2], [reflectivity, 1.0 - reflectivity], rtol=0, atol=1e-12)


# ----------------------------------------------------------------------------- coefficients
@PROPERTY
@given(eta=ETA, kappa=KAPPA)
@example(eta=1e-8, kappa=0.0)
@example(eta=1e6, kappa=1e6)
@example(eta=1.0, kappa=0.0)
@example(eta=1.0 + 1e-15, kappa=0.0)
def test_coefficients_whole_domain(eta, kappa):
    """Whole domain: coefficients finite; c0 = F0 (closed form, atol 1e-12); the reconstruction is finite and its
    max error over 257 angles is within (1 + Λ) · ½ range of {F on the grid, F at the fit angles} (+1e-12)."""
    coefficients = coefficients_from_nk(eta, kappa)
    assert coefficients.shape == (4,) and np.all(np.isfinite(coefficients))
    np.testing.assert_allclose(coefficients[0], closed_form_f0(eta, kappa), rtol=0, atol=1e-12)
    curve = fresnel_conductor(MU_GRID, eta, kappa)
    assert np.all(np.isfinite(reconstruct(coefficients, MU_GRID)))
    at_fit = fresnel_conductor(cos_theta(default_basis().fit_angles), eta, kappa)
    max_abs, _ = reconstruction_error(coefficients, THETA, curve)
    assert max_abs <= (1.0 + LEBESGUE) * 0.5 * np.ptp(np.concatenate([curve, at_fit])) + 1e-12


# ----------------------------------------------------------------------------- split sum
#: α below 1e-9 is split off: there the default schedule overshoots E = 1 (test_stability_extremes.py,
#: test_tiny_alpha_albedo_at_most_one) — the second property covers it as a strict xfail.
ALPHA_REGULAR = st.one_of(st.just(0.0), unit_floats(1e-9, 1.0))


def _check_albedo(mu_o, alpha):
    values = directional_albedo(lambda x: np.concatenate([one(x), _BASIS(x)], axis=-1), mu_o, alpha)
    assert values.shape == (5,) and np.all(np.isfinite(values))
    albedo = values[0]
    assert 0.0 <= albedo <= 1.0 + FLOAT32_HALF_ULP, albedo - 1.0
    # Non-negative weights × non-negative kernel: |Σ w K b_k| ≤ max|b_k| Σ w K.
    assert np.all(np.abs(values[1:]) <= BASIS_MAX * albedo * (1.0 + 1e-12) + 1e-300)


@QUADRATURE_PROPERTY
@given(mu_o=MU, alpha=ALPHA_REGULAR)
@example(mu_o=0.0, alpha=1e-9)
@example(mu_o=1.0, alpha=1e-9)
@example(mu_o=0.0, alpha=0.0)
@example(mu_o=1.0, alpha=1.0)
@example(mu_o=5e-324, alpha=1.0)
def test_split_sum_albedo_bounded(mu_o, alpha):
    """μo ∈ [0, 1], α ∈ {0} ∪ [1e-9, 1]: E = F̄[1] finite and in [0, 1 + 2^-24] (half a float32 ulp); the basis
    channels finite and |F̄[b_k]| ≤ max|b_k| · E (non-negative quadrature weights and kernel)."""
    _check_albedo(mu_o, alpha)


@QUADRATURE_PROPERTY
@given(mu_o=MU, alpha=unit_floats(0.0, 1e-9))
@example(mu_o=0.5, alpha=6.309573444801943e-12)
def test_split_sum_albedo_bounded_tiny_alpha(mu_o, alpha):
    """μo ∈ [0, 1], α ∈ [0, 1e-9] (the rest of the domain): the same bounds as test_split_sum_albedo_bounded."""
    _check_albedo(mu_o, alpha)
