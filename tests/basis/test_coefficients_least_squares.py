"""Least-squares coefficients (basis.coefficients) and the report's registry of material representations.

References: curves built in the span of the shipped basis (known coefficients), the exact Fresnel curve
(basis.fresnel), the four-point scheme (the L2 fit must not be worse in its own norm), the exact discrete
minimax fit computed independently as a linear programme (scipy.optimize.linprog), and Schlick 1994
eq. 15 evaluated by hand.
"""

import numpy as np
import pytest
from scipy.optimize import linprog

from basis import coefficients_from_nk, default_basis, fresnel_conductor
from basis.angles import trapezoid_weights
from basis.coefficients import (
    LEAST_SQUARES_NORMS,
    coefficients_least_squares,
    coefficients_least_squares_from_table,
)
from basis.models import fresnel_Schlick1994
from basis.training import holdout_materials
from basis.validation import ParameterError
from fresnel_lut.report.model_error import REPRESENTATIONS, representation

BASIS = default_basis()
WEIGHTS = sorted(LEAST_SQUARES_NORMS)


def grid_cosines():
    """cos of the basis grid with cos(pi/2) set to exactly 0."""
    mu = np.cos(BASIS.theta)
    mu[-1] = 0.0
    return mu


def exact_on_grid(eta, kappa):
    return fresnel_conductor(grid_cosines()[None, :], np.asarray(eta)[:, None], np.asarray(kappa)[:, None])


# ----------------------------------------------------------------------------- least squares
@pytest.mark.parametrize("weight", WEIGHTS)
def test_least_squares_recovers_curve_in_span(weight):
    """F = sum_k c_k b_k on the basis grid with known c (5 random sets) gives back c (atol 1e-10)."""
    rng = np.random.default_rng(3)
    known = np.column_stack([rng.uniform(0.0, 0.5, 5), rng.uniform(0.2, 1.0, 5), rng.normal(0.0, 0.05, (5, 2))])
    values = known @ BASIS.curves
    recovered = coefficients_least_squares_from_table(BASIS.theta, values, fit=weight)
    np.testing.assert_allclose(recovered, known, rtol=0, atol=1e-10)


@pytest.mark.parametrize("weight", WEIGHTS)
def test_least_squares_keeps_f0_and_f90_exact(weight):
    """c0 = F(0) and c1 = F(pi/2) - F(0) for the held-out metals and dielectrics (atol 1e-12)."""
    groups = holdout_materials()
    eta = np.concatenate([groups["metals"][0], groups["dielectrics"][0]])
    kappa = np.concatenate([groups["metals"][1], groups["dielectrics"][1]])
    coefficients = coefficients_least_squares(eta, kappa, fit=weight)
    f0 = fresnel_conductor(1.0, eta, kappa)
    np.testing.assert_allclose(coefficients[:, 0], f0, rtol=0, atol=1e-12)
    np.testing.assert_allclose(coefficients[:, 1], fresnel_conductor(0.0, eta, kappa) - f0, rtol=0, atol=1e-12)


def test_uniform_least_squares_beats_four_point_in_l2_on_metals():
    """On the 400 held-out metals, the L2 error over theta (trapezoid rule on the basis grid, the norm the
    fit minimises) of the least-squares fit is <= that of the four-point fit, material by material."""
    eta, kappa = holdout_materials()["metals"]
    exact = exact_on_grid(eta, kappa)
    weights = trapezoid_weights(BASIS.theta)

    def l2(coefficients):
        return np.sqrt(((coefficients @ BASIS.curves - exact) ** 2) @ weights)

    least_squares, four_point = l2(coefficients_least_squares(eta, kappa)), l2(coefficients_from_nk(eta, kappa))
    assert np.all(least_squares <= four_point * (1.0 + 1e-12))
    assert np.mean(least_squares) < np.mean(four_point)


def minimax_by_linear_programme(values):
    """min over c2, c3 of max_j |F - c0 - c1 b1 - c2 b2 - c3 b3| on the basis grid (independent LP)."""
    residual = values - values[0] - (values[-1] - values[0]) * BASIS.curves[1]
    design = BASIS.curves[2:].T
    ones = np.ones((design.shape[0], 1))
    constraints = np.block([[-design, -ones], [design, -ones]])
    bounds = np.concatenate([-residual, residual])
    solution = linprog(np.r_[0.0, 0.0, 1.0], A_ub=constraints, b_ub=bounds, bounds=[(None, None)] * 2 + [(0, None)])
    assert solution.success
    return solution.fun


def test_minimax_weighting_is_within_one_percent_of_the_linear_programme():
    """Lawson's reweighting (default iterations) reaches the exact discrete minimax error within 1 % on 6 metals."""
    eta, kappa = (array[:6] for array in holdout_materials()["metals"])
    exact = exact_on_grid(eta, kappa)
    coefficients = coefficients_least_squares(eta, kappa, fit="minimax")
    lawson = np.max(np.abs(coefficients @ BASIS.curves - exact), axis=1)
    optimum = np.array([minimax_by_linear_programme(curve) for curve in exact])
    assert np.all(lawson >= optimum * (1.0 - 1e-9))
    assert np.all(lawson <= optimum * 1.01)


def test_least_squares_from_a_finer_table_matches_the_nk_entry_point():
    """A 2001-point table of the exact curve, splined onto the basis grid, gives the (eta, kappa) coefficients
    to 1e-6 (spline interpolation error only)."""
    eta, kappa = np.array([0.2, 1.5, 1.1]), np.array([3.5, 0.0, 6.0])
    theta = np.linspace(0.0, 0.5 * np.pi, 2001)
    mu = np.cos(theta)
    mu[-1] = 0.0
    table = fresnel_conductor(mu[None, :], eta[:, None], kappa[:, None])
    for weight in WEIGHTS:
        np.testing.assert_allclose(
            coefficients_least_squares_from_table(theta, table, fit=weight),
            coefficients_least_squares(eta, kappa, fit=weight),
            rtol=0,
            atol=1e-6,
        )


def test_least_squares_n_dimensional():
    """Scalar, (6,), (2, 3) and (2, 3, 1) materials give coefficients of shape (..., 4) with equal values."""
    rng = np.random.default_rng(8)
    eta, kappa = rng.uniform(0.2, 3.0, 6), rng.uniform(0.0, 6.0, 6)
    flat = coefficients_least_squares(eta, kappa, fit="minimax")
    assert flat.shape == (6, 4)
    np.testing.assert_allclose(coefficients_least_squares(eta[0], kappa[0], fit="minimax"), flat[0], atol=1e-15)
    shaped = coefficients_least_squares(eta.reshape(2, 3), kappa.reshape(2, 3), fit="minimax")
    np.testing.assert_allclose(shaped.reshape(6, 4), flat, atol=1e-15)
    assert coefficients_least_squares(eta.reshape(2, 3, 1), kappa.reshape(2, 3, 1)).shape == (2, 3, 1, 4)


def test_least_squares_of_a_flat_curve_is_finite():
    """eta = 1, kappa = 0 (no interface, F = 0 everywhere) gives zero coefficients, not NaN, with both weights."""
    for weight in WEIGHTS:
        np.testing.assert_array_equal(coefficients_least_squares(1.0, 0.0, fit=weight), np.zeros(4))


def test_raise_exception_least_squares():
    with pytest.raises(ParameterError, match=r"fit must be one of \['least-squares', 'minimax'\], got 'L1'"):
        coefficients_least_squares(1.5, 0.0, fit="L1")
    with pytest.raises(ParameterError, match="iterations"):
        coefficients_least_squares(1.5, 0.0, fit="minimax", iterations=0)
    with pytest.raises(ParameterError, match="eta"):
        coefficients_least_squares(np.nan, 0.0)
    with pytest.raises(ParameterError, match="kappa"):
        coefficients_least_squares(1.5, -1.0)
    with pytest.raises(ParameterError, match="theta must cover"):
        coefficients_least_squares_from_table(np.linspace(0.1, 1.5, 10), np.zeros(10))
    with pytest.raises(ParameterError, match="trailing axis"):
        coefficients_least_squares_from_table(BASIS.theta, np.zeros(7))


# ----------------------------------------------------------------------------- model registry
def test_registry_names_and_shader_terms():
    assert list(REPRESENTATIONS) == ["exact", "schlick", "basis-4point", "basis-lsq", "basis-minimax"]
    assert representation("exact").shader_terms() is None
    assert representation("schlick").shader_terms() == 2
    assert all(
        representation(name).shader_terms() == BASIS.n_terms for name in REPRESENTATIONS if name.startswith("basis")
    )


def test_raise_exception_unknown_model_lists_the_names():
    with pytest.raises(ParameterError) as error:
        representation("cook-torrance")
    message = str(error.value)
    assert "'cook-torrance'" in message
    assert all(name in message for name in REPRESENTATIONS)
    with pytest.raises(ParameterError, match="material must be a pair"):
        representation("exact").evaluate(0.5, 1.5)
    with pytest.raises(ParameterError, match="mu"):
        representation("schlick").evaluate(1.5, (1.5, 0.0))


def test_schlick_values():
    """Schlick 1994 eq. 15 by hand: F0 + (1 - F0)(1 - mu)^5."""
    np.testing.assert_allclose(fresnel_Schlick1994([1.0, 0.5, 0.0], 0.04), [0.04, 0.04 + 0.96 / 32.0, 1.0], atol=1e-15)
    # the model takes F0 from the exact curve: eta = 1.5 gives F0 = 0.04 (Hecht, normal incidence)
    np.testing.assert_allclose(representation("schlick").evaluate(0.5, (1.5, 0.0)), 0.04 + 0.96 / 32.0, atol=1e-12)


@pytest.mark.parametrize("name", list(REPRESENTATIONS))
def test_models_are_exact_at_normal_and_grazing_incidence(name):
    """F0 and F90 of every model equal the exact curve's (atol 1e-12) for metals and dielectrics."""
    eta, kappa = np.array([0.2, 1.5, 1.1, 2.4]), np.array([3.5, 0.0, 6.0, 0.0])
    for mu in (1.0, 0.0):
        np.testing.assert_allclose(
            representation(name).evaluate(mu, (eta, kappa)), fresnel_conductor(mu, eta, kappa), rtol=0, atol=1e-12
        )


@pytest.mark.parametrize("name", list(REPRESENTATIONS))
def test_models_n_dimensional(name):
    """mu (5,) against materials (3, 1) gives (3, 5), equal to evaluating each material alone."""
    mu = np.linspace(0.0, 1.0, 5)
    eta, kappa = np.array([[0.2], [1.5], [1.1]]), np.array([[3.5], [0.0], [6.0]])
    model = representation(name)
    grid = model.evaluate(mu, (eta, kappa))
    assert grid.shape == (3, 5)
    for row in range(3):
        np.testing.assert_allclose(grid[row], model.evaluate(mu, (eta[row, 0], kappa[row, 0])), atol=1e-15)
    assert np.all((grid >= -0.05) & (grid <= 1.05))
