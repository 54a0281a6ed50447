"""Exact Fresnel reflectance (basis.fresnel) against independent references.

The reference is the textbook complex-amplitude form: n = eta + i kappa,
cos_t = sqrt(1 - sin^2(theta)/n^2) (complex), r_s = (mu - n cos_t)/(mu + n cos_t),
r_p = (n mu - cos_t)/(n mu + cos_t), F = (|r_s|^2 + |r_p|^2)/2. The library uses the
real a^2/b^2 form of Hoffman 2020, so agreement is a genuine cross-check.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from basis.fresnel import fresnel_conductor, fresnel_dielectric
from basis.validation import ParameterError
from tests.references.fresnel import (
    complex_amplitudes,
    fresnel_complex,
    fresnel_decimal,
    normal_incidence,
    one_minus_fresnel_complex,
)

ETA_GRID = np.geomspace(0.05, 50.0, 73)
KAPPA_GRID = np.concatenate([[0.0], np.geomspace(1e-3, 1e3, 61)])
MU_GRID = np.concatenate([np.linspace(0.0, 1.0, 101), [1e-6, 1e-3, 0.999, 1.0 - 1e-9]])


def test_conductor_matches_complex_form_on_broad_grid():
    """fresnel_conductor == complex-amplitude form over eta 0.05..50, kappa 0..1e3, mu 0..1 (atol 1e-12)."""
    eta, kappa, mu = np.meshgrid(ETA_GRID, KAPPA_GRID, MU_GRID, indexing="ij")
    np.testing.assert_allclose(fresnel_conductor(mu, eta, kappa), fresnel_complex(mu, eta, kappa), rtol=0, atol=1e-12)


def test_dielectric_matches_complex_form_on_broad_grid():
    """fresnel_dielectric == complex form with kappa = 0, eta 0.05..50 including internal reflection (atol 1e-12)."""
    eta, mu = np.meshgrid(ETA_GRID, MU_GRID, indexing="ij")
    np.testing.assert_allclose(fresnel_dielectric(mu, eta), fresnel_complex(mu, eta, 0.0), rtol=0, atol=1e-12)


def test_conductor_with_zero_kappa_is_the_dielectric():
    """fresnel_conductor(mu, eta, 0) == fresnel_dielectric(mu, eta) (same values, atol 0)."""
    eta, mu = np.meshgrid(ETA_GRID, MU_GRID, indexing="ij")
    np.testing.assert_allclose(fresnel_conductor(mu, eta, 0.0), fresnel_dielectric(mu, eta), rtol=0, atol=0)


# ----------------------------------------------------------------------------- closed forms
def test_normal_incidence_closed_form():
    """F(mu = 1) == ((eta-1)^2 + kappa^2)/((eta+1)^2 + kappa^2) on the broad grid (rtol 1e-13, atol 1e-15)."""
    eta, kappa = np.meshgrid(ETA_GRID, KAPPA_GRID, indexing="ij")
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), normal_incidence(eta, kappa), rtol=1e-13, atol=1e-15)


def test_glass_at_normal_incidence_is_four_percent():
    """eta = 1.5 at normal incidence: F = (0.5/2.5)^2 = 0.04 (atol 1e-15)."""
    np.testing.assert_allclose(fresnel_dielectric(1.0, 1.5), 0.04, rtol=0, atol=1e-15)
    np.testing.assert_allclose(fresnel_conductor(1.0, 1.5, 0.0), 0.04, rtol=0, atol=1e-15)


@pytest.mark.parametrize("eta", [1.1, 1.33, 1.5, 2.0, 2.42, 4.0, 10.0])
def test_brewster_angle_kills_p_polarisation(eta):
    """At tan(theta_B) = eta, |r_p|^2 = 0 and F = |r_s|^2/2 = ((eta^2-1)/(eta^2+1))^2/2 (complex form, atol 1e-12)."""
    mu_b = 1.0 / np.sqrt(1.0 + eta * eta)
    r_s, r_p, _, _ = complex_amplitudes(mu_b, eta, 0.0)
    assert abs(r_p) ** 2 < 1e-24  # the reference itself is at Brewster's angle
    closed_form = 0.5 * ((eta * eta - 1.0) / (eta * eta + 1.0)) ** 2
    np.testing.assert_allclose(0.5 * abs(r_s) ** 2, closed_form, rtol=0, atol=1e-14)
    np.testing.assert_allclose(fresnel_dielectric(mu_b, eta), 0.5 * abs(r_s) ** 2, rtol=0, atol=1e-12)


@pytest.mark.parametrize("eta", [0.05, 0.3, 1.0 / 1.5, 0.9, 0.99])
def test_total_internal_reflection_past_critical_angle(eta):
    """eta < 1: F == 1 for sin(theta) > eta, i.e. mu < sqrt(1 - eta^2) (atol 1e-15; closed form)."""
    mu_critical = np.sqrt(1.0 - eta * eta)
    mu = np.linspace(0.0, mu_critical, 200)[:-1]
    np.testing.assert_allclose(fresnel_dielectric(mu, eta), 1.0, rtol=0, atol=1e-15)


@pytest.mark.parametrize("eta", [0.05, 0.5, 0.999, 1.001, 1.5, 50.0, 1e6])
@pytest.mark.parametrize("kappa", [0.0, 1e-3, 1.0, 1e3])
def test_grazing_incidence_is_exactly_one(eta, kappa):
    """F(mu = 0) == 1 exactly (r_s = r_p = -1 in the complex form) for every interface with eta != 1."""
    assert fresnel_conductor(0.0, eta, kappa) == 1.0


def test_index_matched_interface_reflects_nothing():
    """eta = 1, kappa = 0 is no interface: F == 0 for every mu including mu = 0 (atol 1e-15)."""
    mu = np.linspace(0.0, 1.0, 1001)
    np.testing.assert_allclose(fresnel_dielectric(mu, 1.0), 0.0, rtol=0, atol=1e-15)
    assert fresnel_conductor(0.0, 1.0, 0.0) == 0.0


@pytest.mark.parametrize("eta", [0.05, 0.1, 1.0, 3.0, 10.0, 50.0])
def test_large_kappa_has_no_cancellation(eta):
    """kappa = 1e3: 1 - F matches the cancellation-free complex form 4 Re(a conj b)/|a+b|^2 (rtol 1e-9)."""
    mu = np.concatenate([np.linspace(0.0, 1.0, 51), [1e-6, 1e-3]])
    value = fresnel_conductor(mu, eta, 1e3)
    assert np.all(np.isfinite(value)) and np.all(value <= 1.0)
    np.testing.assert_allclose(1.0 - value, one_minus_fresnel_complex(mu, eta, 1e3), rtol=1e-9, atol=1e-300)
    np.testing.assert_allclose(value, fresnel_complex(mu, eta, 1e3), rtol=0, atol=1e-12)


@pytest.mark.parametrize("eta", [0.05, 1.0, 50.0, 1e6])
def test_huge_kappa_is_a_perfect_mirror(eta):
    """kappa = 1e6 (domain edge): F finite, <= 1, >= 0.9999 and equal to 1 - (cancellation-free complex 1 - F) (atol 1e-11)."""
    mu = np.linspace(0.0, 1.0, 51)
    value = fresnel_conductor(mu, eta, 1e6)
    assert np.all(np.isfinite(value))
    assert np.all(value <= 1.0)
    bound = 1.0 - one_minus_fresnel_complex(mu, eta, 1e6)
    np.testing.assert_allclose(value, bound, rtol=0, atol=1e-11)
    assert np.all(value >= 0.9999)


def test_near_index_matched_grazing_corner_matches_high_precision():
    """eta ~ 1, kappa <= 1e-6, mu <= 1e-3 against a 60-digit Decimal evaluation of the complex form (atol 1e-12)."""
    cases = [(1e-6, 1.0, 1e-12), (1e-4, 1.0 + 1e-6, 0.0), (1e-3, 1.0 - 1e-6, 1e-6), (1e-4, 1.0, 1e-6)]
    got = [float(fresnel_conductor(mu, eta, kappa)) for mu, eta, kappa in cases]
    expected = [fresnel_decimal(mu, eta, kappa) for mu, eta, kappa in cases]
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12)


def test_decimal_reference_agrees_with_complex_form_where_well_conditioned():
    """Sanity check of the 60-digit reference: equals the complex128 form away from eta ~ 1 (atol 1e-13)."""
    for mu, eta, kappa in [(0.3, 1.5, 0.0), (0.7, 0.27, 3.61), (0.05, 0.5, 0.0), (1.0, 2.0, 1e3), (0.0, 3.0, 1.0)]:
        np.testing.assert_allclose(fresnel_decimal(mu, eta, kappa), fresnel_complex(mu, eta, kappa), rtol=0, atol=1e-13)


@pytest.mark.parametrize("eta, kappa", [(1e-8, 0.0), (1e-8, 1e-8), (1e-8, 1e6)])
def test_smallest_eta_at_normal_incidence(eta, kappa):
    """F(mu = 1) at the domain's smallest eta equals the closed form ((eta-1)^2+kappa^2)/((eta+1)^2+kappa^2) (atol 1e-12)."""
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), normal_incidence(eta, kappa), rtol=0, atol=1e-12)


@pytest.mark.parametrize("eta", [1e-81, 5e-324, 9.9e-9])
def test_eta_below_domain_is_refused(eta):
    """eta below 1e-8, where float64 squares underflow, is refused with the accepted range in the message."""
    with pytest.raises(ParameterError, match=r"eta must be in \[1e-08"):
        fresnel_conductor(1.0, eta, 0.0)


# ----------------------------------------------------------------------------- broadcasting
@pytest.mark.parametrize(
    "function, arguments",
    [
        (fresnel_conductor, (0.37, 0.27, 3.61)),
        (fresnel_dielectric, (0.37, 1.5)),
    ],
)
def test_n_dimensional_inputs(function, arguments):
    """Scalar, 1-D, (2,3) and (2,3,1) inputs give the scalar value tiled/reshaped (atol 0; colour-science style)."""
    expected = function(*arguments)
    assert np.shape(expected) == ()
    for shape in [(6,), (2, 3), (2, 3, 1)]:
        tiled = [np.full(shape, value) for value in arguments]
        result = function(*tiled)
        assert result.shape == shape
        np.testing.assert_allclose(result, np.full(shape, expected), rtol=0, atol=0)
    # Mixed: only the first argument is an array, the others stay scalar.
    result = function(np.full((2, 3, 1), arguments[0]), *arguments[1:])
    assert result.shape == (2, 3, 1)
    np.testing.assert_allclose(result, np.full((2, 3, 1), expected), rtol=0, atol=0)


def test_broadcast_grid_equals_elementwise():
    """mu (5,) x eta (3,1) x kappa (3,1) broadcasts to (3,5), equal to scalar calls one by one (atol 0)."""
    mu = np.linspace(0.0, 1.0, 5)
    eta = np.array([[0.27], [1.5], [2.4]])
    kappa = np.array([[3.6], [0.0], [0.1]])
    result = fresnel_conductor(mu, eta, kappa)
    assert result.shape == (3, 5)
    expected = [[float(fresnel_conductor(m, e, k)) for m in mu] for e, k in zip(eta[:, 0], kappa[:, 0])]
    np.testing.assert_allclose(result, expected, rtol=0, atol=0)


# ----------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "mu, eta, kappa, name",
    [
        (np.nan, 1.5, 0.0, "mu"),
        (0.5, np.nan, 0.0, "eta"),
        (0.5, 1.5, np.nan, "kappa"),
        (np.inf, 1.5, 0.0, "mu"),
        (0.5, np.inf, 0.0, "eta"),
        (0.5, 1.5, np.inf, "kappa"),
        (0.5, 0.0, 0.0, "eta"),
        (0.5, -1.5, 0.0, "eta"),
        (0.5, 1.5, -0.1, "kappa"),
        (-0.01, 1.5, 0.0, "mu"),
        (1.01, 1.5, 0.0, "mu"),
        (0.5, 2e6, 0.0, "eta"),
        (0.5, 1.5, 2e6, "kappa"),
        ([0.5, np.nan], 1.5, 0.0, "mu"),
        (0.5, [1.5, -1.0], 0.0, "eta"),
        ("0.5", 1.5, 0.0, "mu"),
        (0.5, "1.5", 0.0, "eta"),
        (0.5, 1.5, "0", "kappa"),
        (True, 1.5, 0.0, "mu"),
        (0.5, True, 0.0, "eta"),
        (0.5, 1.5, False, "kappa"),
        (0.5, 1.5 + 0.1j, 0.0, "eta"),
        (0.5, 1.5, 3j, "kappa"),
        (0.5 + 0j, 1.5, 0.0, "mu"),
        (None, 1.5, 0.0, "mu"),
        (0.5, np.array([object()]), 0.0, "eta"),
    ],
)
def test_bad_input_raises_parameter_error_naming_the_parameter(mu, eta, kappa, name):
    """Invalid mu/eta/kappa -> ParameterError (a ValueError) whose message starts with the parameter name."""
    with pytest.raises(ParameterError, match=rf"^{name}\b"):
        fresnel_conductor(mu, eta, kappa)
    assert issubclass(ParameterError, ValueError)


@pytest.mark.parametrize("mu, eta, name", [(0.5, -1.0, "eta"), (2.0, 1.5, "mu"), (0.5, True, "eta"), (0.5, "x", "eta")])
def test_dielectric_bad_input(mu, eta, name):
    """fresnel_dielectric validates like fresnel_conductor: ParameterError naming the parameter."""
    with pytest.raises(ParameterError, match=rf"^{name}\b"):
        fresnel_dielectric(mu, eta)


# ----------------------------------------------------------------------------- properties
ETA_DOMAIN = st.floats(min_value=1e-8, max_value=1e3, allow_nan=False, allow_infinity=False)
KAPPA_DOMAIN = st.floats(min_value=0.0, max_value=1e3, allow_nan=False, allow_infinity=False)
MU_DOMAIN = st.floats(min_value=0.0, max_value=1.0, allow_nan=False, allow_infinity=False)


@settings(max_examples=200, deadline=None)
@given(mu=MU_DOMAIN, eta=ETA_DOMAIN, kappa=KAPPA_DOMAIN)
def test_property_reflectance_is_finite_and_in_unit_interval(mu, eta, kappa):
    """Over the documented domain F is finite and 0 <= F <= 1 (energy conservation; no reference needed)."""
    value = fresnel_conductor(mu, eta, kappa)
    assert np.isfinite(value)
    assert 0.0 <= value <= 1.0


#: Above eta = 2 + sqrt(3) the unpolarised dielectric reflectance is NOT monotone: near normal incidence
#: R_p falls faster than R_s rises, so F dips below F(0) (to R_s/2 at Brewster's angle for large eta).
#: This is physics, checked against the complex form below, not a library defect.
MONOTONE_ETA_LIMIT = 2.0 + np.sqrt(3.0)


@settings(max_examples=200, deadline=None)
@given(eta=st.floats(min_value=1.0, max_value=3.7, exclude_min=True, allow_nan=False))
def test_property_dielectric_is_monotone_in_mu(eta):
    """kappa = 0, 1 < eta <= 3.7 (< 2 + sqrt 3): F non-increasing in mu on a sorted 257-point grid (tolerance 1e-12)."""
    mu = np.linspace(0.0, 1.0, 257)
    value = fresnel_dielectric(mu, eta)
    assert np.all(np.diff(value) <= 1e-12)


@pytest.mark.parametrize("eta", [4.0, 10.0, 100.0, 1e3])
def test_dielectric_above_two_plus_sqrt3_dips_below_normal_incidence(eta):
    """eta > 2 + sqrt(3): both the complex form and the library have min F < F(mu = 1); they agree (atol 1e-12)."""
    assert eta > MONOTONE_ETA_LIMIT
    mu = np.linspace(0.0, 1.0, 2001)
    reference = fresnel_complex(mu, eta, 0.0)
    value = fresnel_dielectric(mu, eta)
    assert reference.min() < reference[-1] - 1e-6
    np.testing.assert_allclose(value, reference, rtol=0, atol=1e-12)


@settings(max_examples=200, deadline=None)
@given(
    eta=st.floats(min_value=1e-3, max_value=1e3, allow_nan=False),
    kappa=KAPPA_DOMAIN,
)
def test_property_normal_incidence_closed_form(eta, kappa):
    """F(mu = 1) == ((eta-1)^2 + kappa^2)/((eta+1)^2 + kappa^2) for eta >= 1e-3 (rtol 1e-12, atol 1e-15).

    Tiny eta is covered by test_tiny_eta_at_normal_incidence (a known failure).
    """
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), normal_incidence(eta, kappa), rtol=1e-12, atol=1e-15)
