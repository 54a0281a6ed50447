"""The coefficient table of Gulbrandsen's (r, g) (basis/coefficient_table.py, issue 38), against exact Fresnel (the
Fresnel equations of Gulbrandsen's (η, κ), eq. 7–9) and against the four-point solve it replaces.

The shipped table (luts/fresnel_coefficients_rgb.exr) is read as a GPU reads it; the criterion is max over θ of
|F − F_exact| (it bounds the split sum's error too, tests/preintegrate checks that bound's premise: F̄ is a positive
average of F with weights summing to E ≤ 1).
"""

import numpy as np
import pytest

from basis import coefficients_from_gulbrandsen, default_basis, fresnel_conductor, gulbrandsen_to_nk
from basis.angles import cos_theta
from basis.coefficient_table import (
    COEFFICIENT_TABLE_SIZE,
    REFLECTIVITY_MAX,
    coefficient_table,
    coefficient_table_axes,
    coefficient_table_model,
    coefficient_table_weights,
    coefficients_from_coefficient_table,
    unwarp_edge_tint,
    unwarp_reflectivity,
    warp_edge_tint,
    warp_reflectivity,
)
from basis.storage import shipped_path
from basis.validation import ParameterError
from handoff.exr import read_lut
from handoff.shipped import COEFFICIENT_LUT

TABLE = read_lut(shipped_path(COEFFICIENT_LUT))[0]
BASIS = default_basis()
THETA = np.linspace(0.0, 0.5 * np.pi, 1025)
CURVES = BASIS.evaluate(THETA)  # (T, K)


def _curve_errors(coefficients, reflectivity, edge_tint):
    """(N,) max over θ of |Σ c_k b_k − F_exact| of Gulbrandsen's (r, g)."""
    exact = fresnel_conductor(cos_theta(THETA)[:, None], *gulbrandsen_to_nk(reflectivity, edge_tint))
    return np.max(np.abs(CURVES @ np.asarray(coefficients).T - exact), axis=0)


def test_warps_invert_and_span_the_axes():
    r = np.linspace(0.0, REFLECTIVITY_MAX, 1001)
    np.testing.assert_allclose(unwarp_reflectivity(warp_reflectivity(r)), r, rtol=0, atol=1e-14)
    g = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(unwarp_edge_tint(warp_edge_tint(g)), g, rtol=0, atol=1e-14)
    assert warp_reflectivity(0.0) == -0.5 and np.all(np.diff(warp_reflectivity(r)) > 0)


def _texel_axes():
    """(r (W,), g (H,)) of the shipped table's texel centres, from its axes as the module states them."""
    width, height = COEFFICIENT_TABLE_SIZE
    first, step = coefficient_table_axes(width, height)
    r = unwarp_reflectivity(first + step * np.arange(width))
    r[-1] = REFLECTIVITY_MAX
    return r, unwarp_edge_tint(np.linspace(0.0, 1.0, height))


def test_the_axes_put_r_zero_a_quarter_texel_before_column_zero_and_the_last_centre_on_the_largest_r():
    first, step = coefficient_table_axes(*COEFFICIENT_TABLE_SIZE)
    assert first - warp_reflectivity(0.0) == pytest.approx(0.25 * step, rel=1e-12)
    assert first + step * (COEFFICIENT_TABLE_SIZE[0] - 1) == pytest.approx(
        warp_reflectivity(REFLECTIVITY_MAX), rel=1e-12
    )


def test_the_shipped_table_is_the_weighted_fit_of_the_shipped_basis_at_its_texels():
    """Every 8th row, every column but the first (r = 0 there: all 0): the float32 values of the library's weighted
    fit of Gulbrandsen's (η, κ) at the texels' (r, g), and f90 = 1 (0 in column 0)."""
    r, g = _texel_axes()
    expected = coefficient_table_model(*np.meshgrid(r[1:], g[::8]))[..., 2:]
    np.testing.assert_allclose(TABLE[::8, 1:, :-1], expected, rtol=0, atol=1e-6)
    assert np.all(TABLE[:, 1:, -1] == 1.0) and np.all(TABLE[:, 0] == 0.0)


def test_the_weights_are_a_fixed_positive_weighting_of_the_basis_grid():
    """One weight per basis angle (sum 1, none negative), and the table's model at a texel is that weighted least
    squares: the normal equations of the residual against b2 … hold to round-off."""
    weights = coefficient_table_weights()
    assert weights.shape == BASIS.theta.shape and np.all(weights >= 0.0) and weights.sum() == pytest.approx(1.0)
    r, g = 0.6, 0.3
    c = coefficient_table_model(r, g)
    exact = fresnel_conductor(cos_theta(BASIS.theta), *gulbrandsen_to_nk(r, g))
    residual = exact - c @ BASIS.curves
    normal = BASIS.curves[2:] @ (weights * residual)
    assert np.max(np.abs(normal)) <= 1e-12 * np.max(np.abs(exact)), normal


def test_at_texels_never_worse_than_the_four_point_solve_and_better_at_the_median():
    """Max over θ of the curve error at every 4th texel in r ∈ [0.01, 0.98] (every g): the table's fit against the
    four-point solve; no texel worse (within 1e-6 relative: the training checks the basis' grid, this a finer one),
    the median 1.25 × lower (measured 0.75 ×)."""
    r_axis, g_axis = _texel_axes()
    columns = np.flatnonzero((r_axis >= 0.01) & (r_axis <= 0.98))[::4]
    r, g = (values.ravel() for values in np.meshgrid(r_axis[columns], g_axis[::4]))
    table = coefficients_from_coefficient_table(TABLE, r, g)
    four_point = coefficients_from_gulbrandsen(r, g)
    table_error, four_point_error = _curve_errors(table, r, g), _curve_errors(four_point, r, g)
    assert np.all(table_error <= four_point_error * (1 + 1e-6) + 1e-7), float(np.max(table_error / four_point_error))
    assert np.median(table_error / four_point_error) <= 0.8


def test_between_texels_within_issue_38s_1e4_of_its_float64_model_and_closer_to_exact_fresnel():
    """20,000 random (r, g), r ∈ [0.01, 0.98]: the bilinear read against the float64 fit at the point itself, with
    exact and with 8-bit filter weights, all within issue 38's 1e-4 (measured 5.2e-5 and 5.8e-5); against exact
    Fresnel beside the four-point solve, the median 0.75 × (at most 0.8 ×) and nowhere more than 1e-5 worse (measured:
    at most 1.018 × it, 8e-6 in absolute terms, between texels where the four-point solve's own error dips)."""
    rng = np.random.default_rng(1)
    r, g = rng.uniform(0.01, 0.98, 20_000), rng.uniform(0.0, 1.0, 20_000)
    model = coefficient_table_model(r, g)
    for bits in (8, None):  # the exact weights' read last, for the comparison with exact Fresnel
        table = coefficients_from_coefficient_table(TABLE, r, g, bits)
        from_model = np.max(np.abs(CURVES @ (table - model).T), axis=0)
        assert np.max(from_model) <= 1e-4, (bits, np.max(from_model))
    table_error, four_point_error = _curve_errors(table, r, g), _curve_errors(coefficients_from_gulbrandsen(r, g), r, g)
    assert np.median(table_error / four_point_error) <= 0.8, np.median(table_error / four_point_error)
    assert np.max(table_error - four_point_error) <= 1e-5, np.max(table_error - four_point_error)


def test_at_every_cell_centre_within_1e4_of_its_float64_model():
    """Bilinear reading strays furthest from a smooth model midway between texels: at the centre of every cell whose
    r lies in [0.01, 0.98] (48,006 cells), the table within issue 38's 1e-4 of its float64 fit (measured 6.1e-5)."""
    r_axis, g_axis = _texel_axes()
    r_middle = unwarp_reflectivity(0.5 * (warp_reflectivity(r_axis[:-1]) + warp_reflectivity(r_axis[1:])))
    g_middle = unwarp_edge_tint(0.5 * (warp_edge_tint(g_axis[:-1]) + warp_edge_tint(g_axis[1:])))
    r, g = (values.ravel() for values in np.meshgrid(r_middle[(r_middle >= 0.01) & (r_middle <= 0.98)], g_middle))
    from_model = np.max(
        np.abs(CURVES @ (coefficients_from_coefficient_table(TABLE, r, g) - coefficient_table_model(r, g)).T), axis=0
    )
    assert r.size > 48_000 and np.max(from_model) <= 1e-4, np.max(from_model)


def test_zero_reflectivity_reflects_nothing_and_bad_input_is_refused():
    """r = 0 reads column 0 alone (a quarter texel before its centre), every g: all coefficients 0."""
    assert np.all(coefficients_from_coefficient_table(TABLE, 0.0, [0.0, 0.5, 1.0]) == 0.0)
    assert np.all(coefficients_from_coefficient_table(TABLE, 0.0, [0.0, 0.5, 1.0], weight_bits=8) == 0.0)
    for r, g in ((-0.1, 0.5), (1.0, 0.5), (0.5, 1.5), (np.nan, 0.5)):
        with pytest.raises(ParameterError):
            coefficients_from_coefficient_table(TABLE, r, g)
    with pytest.raises(ParameterError, match="fit must be one of"):
        coefficient_table(fit="least-squares")
    with pytest.raises(ParameterError, match="fit must be one of"):
        coefficient_table_model(0.5, 0.5, fit="least-squares")


def test_the_curve_table_holds_the_basis_curves_between_its_texels():
    """luts/fresnel_curves_rgb.exr read linearly (``direct_fresnel_table``) against the basis' own spline at 200,001
    V·H: within 3e-5 (measured 2.5e-5, b3 near grazing; the include's polynomial: 2.2e-5)."""
    from handoff.shaders import direct_fresnel_table
    from handoff.shipped import CURVE_LUT

    curves = read_lut(shipped_path(CURVE_LUT))[0]
    mu = np.linspace(0.0, 1.0, 200_001)
    identity = np.eye(4)[:, None, :]  # each b_k alone
    error = np.abs(direct_fresnel_table(curves, identity, mu[None, :]) - BASIS.evaluate_mu(mu).T)
    assert float(np.max(error)) <= 3e-5, float(np.max(error))
