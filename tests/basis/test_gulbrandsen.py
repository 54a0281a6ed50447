"""Gulbrandsen (2014) artist parameters (r, g) <-> complex IOR (eta, kappa).

The defining property (Gulbrandsen 2014, eq. 7-9) is that the exact Fresnel reflectance at normal
incidence of the returned (eta, kappa) is r, for every g; it is checked with the library's Fresnel
and with the closed form ((eta-1)^2 + kappa^2)/((eta+1)^2 + kappa^2).
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from basis.fresnel import fresnel_conductor, fresnel_dielectric
from basis.gulbrandsen import gulbrandsen_to_nk, nk_to_gulbrandsen
from basis.validation import ParameterError

R_GRID = np.linspace(0.0, 0.99, 100)
G_GRID = np.linspace(0.0, 1.0, 51)


def grid():
    """(r, g) lattice over r in [0, 0.99], g in [0, 1]."""
    return np.meshgrid(R_GRID, G_GRID, indexing="ij")


def test_round_trip_on_grid():
    """nk_to_gulbrandsen(gulbrandsen_to_nk(r, g)) == (r, g) for r in (0, 0.99], g in [0, 1] (atol 1e-9)."""
    r, g = grid()
    r_back, g_back = nk_to_gulbrandsen(*gulbrandsen_to_nk(r, g))
    np.testing.assert_allclose(r_back, r, rtol=0, atol=1e-9)
    nonzero = r > 0.0
    np.testing.assert_allclose(g_back[nonzero], g[nonzero], rtol=0, atol=1e-9)


def test_zero_reflectivity_returns_zero_edge_tint():
    """r = 0 is eta = 1, kappa = 0 for every g (documented): the inverse returns r = 0 and g = 0 exactly."""
    eta, kappa = gulbrandsen_to_nk(0.0, G_GRID)
    np.testing.assert_allclose(eta, 1.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(kappa, 0.0, rtol=0, atol=1e-15)
    r_back, g_back = nk_to_gulbrandsen(1.0, 0.0)
    assert r_back == 0.0 and g_back == 0.0


def test_normal_incidence_fresnel_equals_reflectivity():
    """Defining property: fresnel_conductor(1, eta(r,g), kappa(r,g)) == r for every (r, g) (atol 1e-12)."""
    r, g = grid()
    eta, kappa = gulbrandsen_to_nk(r, g)
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), r, rtol=0, atol=1e-12)
    closed_form = ((eta - 1.0) ** 2 + kappa**2) / ((eta + 1.0) ** 2 + kappa**2)
    np.testing.assert_allclose(closed_form, r, rtol=0, atol=1e-12)


def test_zero_edge_tint_is_the_dielectric():
    """g = 0: eta = (1 + sqrt r)/(1 - sqrt r) (closed form), kappa ~ 0 (<= 1e-7 eta, rounding), curve == dielectric (atol 1e-12)."""
    eta, kappa = gulbrandsen_to_nk(R_GRID, 0.0)
    root = np.sqrt(R_GRID)
    np.testing.assert_allclose(eta, (1.0 + root) / (1.0 - root), rtol=1e-14, atol=0)
    assert np.all(kappa <= 1e-7 * eta)
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), R_GRID, rtol=0, atol=1e-12)
    np.testing.assert_allclose(fresnel_dielectric(1.0, eta), R_GRID, rtol=0, atol=1e-12)
    mu = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(
        fresnel_conductor(mu[None, :], eta[:, None], kappa[:, None]),
        fresnel_dielectric(mu[None, :], eta[:, None]),
        rtol=0,
        atol=1e-12,
    )


def test_full_edge_tint_is_the_lowest_eta():
    """g = 1: eta = n_min = (1 - r)/(1 + r) (Gulbrandsen eq. 7, closed form; rtol 1e-14)."""
    eta, _ = gulbrandsen_to_nk(R_GRID, 1.0)
    np.testing.assert_allclose(eta, (1.0 - R_GRID) / (1.0 + R_GRID), rtol=1e-14, atol=0)


@pytest.mark.parametrize("r", [0.99, 0.995, 0.999, 0.9999])
def test_reflectivity_close_to_one_is_finite(r):
    """r -> 1 (0.99 .. 0.9999): eta, kappa finite and positive, F(normal) == r (atol 1e-12), round trip (atol 1e-9)."""
    g = np.linspace(0.0, 1.0, 11)
    eta, kappa = gulbrandsen_to_nk(r, g)
    assert np.all(np.isfinite(eta)) and np.all(np.isfinite(kappa))
    assert np.all(eta > 0.0) and np.all(kappa >= 0.0)
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), r, rtol=0, atol=1e-12)
    r_back, g_back = nk_to_gulbrandsen(eta, kappa)
    np.testing.assert_allclose(r_back, r, rtol=0, atol=1e-9)
    np.testing.assert_allclose(g_back, g, rtol=0, atol=1e-9)


def test_docstring_example_glass():
    """r = 0.04, g = 0 -> eta = 1.5, kappa = 0 (closed form (1 + 0.2)/(1 - 0.2); atol 1e-12)."""
    eta, kappa = gulbrandsen_to_nk(0.04, 0.0)
    np.testing.assert_allclose(eta, 1.5, rtol=0, atol=1e-12)
    np.testing.assert_allclose(kappa, 0.0, rtol=0, atol=1e-7)


def test_shapes_broadcast():
    """(3,) r with scalar g -> (3,) outputs; (2,1) x (3,) -> (2,3); values equal elementwise calls (atol 0)."""
    eta, kappa = gulbrandsen_to_nk([0.1, 0.5, 0.9], 0.3)
    assert eta.shape == kappa.shape == (3,)
    eta, kappa = gulbrandsen_to_nk(np.array([[0.2], [0.7]]), np.array([0.0, 0.5, 1.0]))
    assert eta.shape == kappa.shape == (2, 3)
    single = gulbrandsen_to_nk(0.7, 0.5)
    np.testing.assert_allclose([eta[1, 1], kappa[1, 1]], [single[0], single[1]], rtol=0, atol=0)


@pytest.mark.parametrize(
    "r, g, name",
    [
        (1.0, 0.5, "reflectivity"),
        (1.5, 0.5, "reflectivity"),
        (-0.01, 0.5, "reflectivity"),
        (np.nan, 0.5, "reflectivity"),
        (np.inf, 0.5, "reflectivity"),
        ([0.5, 1.0], 0.5, "reflectivity"),
        ("0.5", 0.5, "reflectivity"),
        (True, 0.5, "reflectivity"),
        (0.5, -0.01, "edge_tint"),
        (0.5, 1.01, "edge_tint"),
        (0.5, np.nan, "edge_tint"),
        (0.5, 0.5j, "edge_tint"),
        (0.5, None, "edge_tint"),
    ],
)
def test_bad_input(r, g, name):
    """r outside [0, 1), g outside [0, 1], NaN, inf, str, bool, complex -> ParameterError naming the parameter."""
    with pytest.raises(ParameterError, match=rf"^{name}\b"):
        gulbrandsen_to_nk(r, g)


@pytest.mark.parametrize("eta, kappa, name", [(0.0, 1.0, "eta"), (np.nan, 1.0, "eta"), (1.0, -1.0, "kappa")])
def test_inverse_bad_input(eta, kappa, name):
    """nk_to_gulbrandsen validates eta in (0, 1e6], kappa in [0, 1e6]: ParameterError naming the parameter."""
    with pytest.raises(ParameterError, match=rf"^{name}\b"):
        nk_to_gulbrandsen(eta, kappa)


@settings(max_examples=200, deadline=None)
@given(
    r=st.floats(min_value=1e-12, max_value=0.99, allow_nan=False),
    g=st.floats(min_value=0.0, max_value=1.0, allow_nan=False),
)
def test_property_round_trip(r, g):
    """Round trip (r, g) -> (eta, kappa) -> (r, g) (atol 1e-9) and F(normal) == r (atol 1e-12).

    r >= 1e-12: near r = 0 the span n_max - n_min ~ 4 sqrt(r) shrinks to the float64 spacing of eta ~ 1,
    so g is not recoverable to 1e-9 below r ~ 1e-14 (a conditioning limit, not a defect).
    """
    eta, kappa = gulbrandsen_to_nk(r, g)
    r_back, g_back = nk_to_gulbrandsen(eta, kappa)
    np.testing.assert_allclose(r_back, r, rtol=0, atol=1e-9)
    np.testing.assert_allclose(g_back, g, rtol=0, atol=1e-9)
    np.testing.assert_allclose(fresnel_conductor(1.0, eta, kappa), r, rtol=0, atol=1e-12)
