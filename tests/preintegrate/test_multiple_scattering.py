"""Multiple-scattering compensation from the LUTs (preintegrate/multiple_scattering.py).

References: the hemispherical average 2∫F μ dμ of the exact Fresnel curve by adaptive quadrature
(scipy.integrate.quad), bounded by how well four terms fit the curve; the white furnace (F = 1), where
compensated GGX must reflect everything (Kulla and Conty 2017); and the mirror limit, where GGX loses
nothing and there is nothing to add back; E_avg against VNDF Monte Carlo (4σ).
"""

import numpy as np
import pytest
from scipy.integrate import quad

from basis.coefficients import coefficients_from_nk, reconstruct
from basis.eigenbasis import default_basis
from basis.fresnel import fresnel_conductor, fresnel_dielectric
from basis.presets import material_coefficients
from basis.validation import ParameterError
from handoff.exr import read_lut
from handoff.shipped import shipped_lut, shipped_tables
from preintegrate.estimators import monte_carlo_albedo
from preintegrate.ggx import roughness_to_alpha
from preintegrate.lut import LutGrid
from preintegrate.multiple_scattering import average_albedo, basis_albedo, compensated_albedo


@pytest.fixture(scope="module")
def tables():
    return shipped_tables()


def _average(curve):
    value, _ = quad(lambda mu: 2.0 * curve(mu) * mu, 0.0, 1.0, epsabs=1e-13, limit=200)
    return value


def test_constant_term_averages_to_one():
    np.testing.assert_allclose(default_basis().hemispherical_averages[0], 1.0, atol=1e-12)


@pytest.mark.parametrize("eta, kappa", [(0.18, 3.4), (1.5, 0.0), (2.9, 3.1), (1.02, 0.0)])
def test_average_fresnel_matches_the_exact_curve(eta, kappa):
    """Σ c_k avg(b_k) is the exact average of the reconstructed curve (quad of it, 1e-9) and within the
    fit's own error of the true curve's (1e-2 absolute; the four-point fit misses by at most ~1e-2)."""
    basis = default_basis()
    coefficients = coefficients_from_nk(eta, kappa)
    predicted = float(coefficients @ basis.hemispherical_averages)
    assert predicted == pytest.approx(_average(lambda mu: float(reconstruct(coefficients, mu))), abs=1e-9)
    exact = _average(lambda mu: float(fresnel_conductor(mu, eta, kappa)))
    assert predicted == pytest.approx(exact, abs=1e-2)


def test_white_furnace_is_exact(tables):
    """F = 1 (c = (1, 0, 0, 0) per channel): single scattering loses up to ~half at r = 1; compensated,
    every texel centre and every point between them reflects 1 to float32 precision."""
    white = np.zeros((3, default_basis().n_terms))
    white[:, 0] = 1.0
    mu, roughness = np.meshgrid(np.linspace(0.0, 1.0, 97), np.linspace(0.0, 1.0, 97), indexing="ij")
    single = basis_albedo(white, mu, roughness, multiple_scattering=False, tables=tables)
    assert single.min() < 0.6
    compensated = basis_albedo(white, mu, roughness, tables=tables)
    assert np.isfinite(compensated).all()
    np.testing.assert_allclose(compensated, 1.0, atol=1e-6)


def test_gold_gains_energy_with_roughness_and_stays_physical(tables):
    gold = material_coefficients("Gold")
    mu = np.full(6, 0.5)
    roughness = np.linspace(0.0, 1.0, 6)
    single = basis_albedo(gold, mu, roughness, multiple_scattering=False, tables=tables)
    compensated = basis_albedo(gold, mu, roughness, tables=tables)
    gain = compensated - single
    assert (gain >= 0.0).all() and (compensated <= 1.0).all()
    assert np.all(np.diff(gain, axis=0) > 0.0)  # rougher loses more to multiple bounces
    assert gain[0].max() < 1e-3  # mirror: nothing lost
    # a coloured metal saturates under multiple bounces (Kulla and Conty 2017): the brightest channel
    # gains relatively most, so red over blue grows
    assert compensated[-1, 0] / compensated[-1, 2] > single[-1, 0] / single[-1, 2]


def test_compensation_of_a_dielectric_is_small(tables):
    """Glass (F_avg ≈ 0.09) regains only F_avg² of the lost energy, well under 1 % absolute."""
    glass = np.repeat(coefficients_from_nk(1.5, 0.0)[None, :], 3, axis=0)
    single = basis_albedo(glass, 0.7, 1.0, multiple_scattering=False, tables=tables)
    compensated = basis_albedo(glass, 0.7, 1.0, tables=tables)
    assert np.all(compensated > single) and np.all(compensated - single < 1e-2)
    assert _average(lambda m: float(fresnel_dielectric(m, 1.5))) == pytest.approx(0.0918, abs=1e-3)


@pytest.mark.parametrize(
    "arguments, message",
    [
        ((np.ones(3), 1.2, np.ones(3)), "albedo"),
        ((np.ones(3), 0.5, np.full(3, np.nan)), "average_fresnel"),
        ((np.ones(3), -0.1, np.ones(3)), "albedo"),
        ((np.ones((2, 3)), np.full(4, 0.5), np.full(3, 0.5)), "must broadcast"),
    ],
)
def test_compensated_albedo_refuses_bad_input(arguments, message):
    with pytest.raises(ParameterError, match=message):
        compensated_albedo(*arguments)


def test_basis_albedo_refuses_wrong_shapes(tables):
    gold = material_coefficients("Gold")
    for wrong, message in [
        ("x", "tables must be"),
        ((np.zeros((2, 2)), tables[1]), "basis table"),
        ((tables[0], tables[0][..., :1]), "Schlick table"),
        ((np.full_like(tables[0], np.nan), tables[1]), "finite"),
    ]:
        with pytest.raises(ParameterError, match=message):
            basis_albedo(gold, 0.5, 0.5, tables=wrong)
    with pytest.raises(ParameterError, match="coefficients"):
        basis_albedo(np.ones((3, 2)), 0.5, 0.5, tables=tables)
    with pytest.raises(ParameterError, match="roughness"):
        basis_albedo(material_coefficients("Gold"), 0.5, 1.5, tables=tables)


def test_average_albedo_against_the_shipped_table_and_its_limits(tables):
    """E_avg(r) = 2 ∫ E μ dμ = 4 ∫ E x³ dx (x = √μo) against the trapezoid rule over the shipped table's 128
    columns of E (B channel, uniform in x; rule error ≤ 2e-4 here); 1 at the mirror; falling with roughness."""
    grid = LutGrid(128, 128)
    x, rows = np.sqrt(grid.mu_o), slice(None, None, 16)
    integrand = 4.0 * tables[1][rows, :, 2] * x**3
    trapezoid = np.sum(0.5 * (integrand[:, 1:] + integrand[:, :-1]) * np.diff(x), axis=1)
    averages = average_albedo(grid.roughness[rows])
    np.testing.assert_allclose(averages, trapezoid, atol=2e-4)
    assert average_albedo(0.0) == pytest.approx(1.0, abs=1e-12)
    assert np.all(np.diff(averages) < 0.0)


@pytest.mark.parametrize("roughness", [0.5, 1.0])
def test_average_albedo_against_monte_carlo(roughness):
    """2 ∫ E μ dμ with E from VNDF Monte Carlo at 16 Gauss–Legendre μ (independent of the quadrature
    integrator), 4σ."""
    nodes, weights = np.polynomial.legendre.leggauss(16)
    mu, weights = 0.5 * (nodes + 1.0), 0.5 * weights
    alpha = float(roughness_to_alpha(roughness))
    estimates = [
        monte_carlo_albedo(lambda x: np.ones_like(x), float(m), alpha, samples=100_000, seed=i)
        for i, m in enumerate(mu)
    ]
    values = np.array([np.ravel(mean)[0] for mean, _ in estimates])
    errors = np.array([np.ravel(error)[0] for _, error in estimates])
    reference, sigma = 2.0 * np.sum(weights * mu * values), 2.0 * np.sqrt(np.sum((weights * mu * errors) ** 2))
    assert abs(float(average_albedo(roughness)) - reference) < 4.0 * sigma + 1e-6


#: Gold-like RGB complex IOR (η, κ per channel): a strongly coloured conductor.
_GOLD_ETA, _GOLD_KAPPA = np.array([0.18, 0.42, 1.37]), np.array([3.42, 2.35, 1.77])


@pytest.mark.parametrize(
    "mu_o, roughness, gap", [(0.5, 1.0, 0.04), (0.2, 0.8, 0.012), (0.9, 0.6, 0.006), (0.5, 0.3, 0.003)]
)
def test_against_a_random_walk_on_the_microsurface(mu_o, roughness, gap):
    """Heitz et al. 2016's random walk (tests/references/random_walk.py, 200 000 paths):

    - in the white furnace it returns 1 (every path leaves), and its one-bounce paths reproduce the
      single-scattering E of the shipped table within 4σ + 2e-4 (bilinear, float32);
    - for a gold-like conductor its one-bounce paths match the basis split sum within 4σ + 5e-3 (the
      four-term fit of the curve);
    - Kulla–Conty compensation is an approximation (it assumes the bounced energy leaves with the
      average Fresnel F_avg): it must bring the split sum closer to the walk, and within ``gap``, the
      measured bound (0.035 at r = 1, green; 0.009 at r = 0.8; 0.004 at r = 0.6; 0.002 at r = 0.3).
    """
    from tests.references.random_walk import random_walk_albedo

    alpha = float(roughness_to_alpha(roughness))
    white, white_single, white_error, white_single_error = random_walk_albedo(mu_o, alpha, [1e-3], [1e5], seed=1)
    assert white[0] == pytest.approx(1.0, abs=4.0 * white_error[0] + 1e-9)
    table = basis_albedo(
        np.array([[1.0, 0.0, 0.0, 0.0]] * 3), mu_o, roughness, tables=shipped_tables(), multiple_scattering=False
    )
    assert abs(white_single[0] - table[0]) < 4.0 * white_single_error[0] + 2e-4

    total, single, total_error, single_error = random_walk_albedo(mu_o, alpha, _GOLD_ETA, _GOLD_KAPPA, seed=3)
    coefficients = coefficients_from_nk(_GOLD_ETA, _GOLD_KAPPA)
    split_sum = basis_albedo(coefficients, mu_o, roughness, tables=shipped_tables(), multiple_scattering=False)
    compensated = basis_albedo(coefficients, mu_o, roughness, tables=shipped_tables())
    assert np.all(np.abs(split_sum - single) < 4.0 * single_error + 5e-3)
    assert np.all(np.abs(compensated - total) < np.abs(split_sum - total))
    assert np.all(np.abs(compensated - total) < gap + 4.0 * total_error)


def test_shipped_average_table_is_the_api_and_reads_with_its_header():
    """luts/ggx_albedo_average.exr: one column of E_avg at the rows' roughness (float32 of the API's
    values), a single Y channel, its own convention; the roughest row loses about 59 % (0.41 measured)."""
    from handoff.shipped import AVERAGE_LUT

    table, header = read_lut(shipped_lut(AVERAGE_LUT))
    assert table.shape == (128, 1, 1) and header["channels"] == "Y" and header["convention"].startswith("one column")
    roughness = LutGrid(128, 128).roughness
    np.testing.assert_array_equal(table[:, 0, 0], average_albedo(roughness).astype(np.float32))
    assert 0.38 < table[-1, 0, 0] < 0.45


def test_compensation_reads_e_as_the_shaders_do():
    """Issue 26 item 10: the shaders take E from the Schlick table's B channel; so does compensate_lookup (on a half
    table B and R + G differ by up to 4.9e-4). A texel whose B is changed changes the result as the shader's would."""
    from basis import default_basis
    from preintegrate.multiple_scattering import compensate_lookup

    texels = np.array([[0.30, 0.20, 0.5], [0.30, 0.20, 0.5004883]])  # B = R + G, and B one half-float step above
    single = np.full((2, 3), 0.4)
    coefficients = np.tile([0.9, 0.1, 0.0, 0.0], (3, 1))
    first, second = compensate_lookup(single, texels, coefficients, default_basis())
    assert not np.allclose(first, second, rtol=0, atol=1e-9)
    two_channel = compensate_lookup(single, texels[:1, :2], coefficients, default_basis())
    np.testing.assert_allclose(two_channel[0], first, rtol=0, atol=1e-15)
