"""Coefficient solver (basis.coefficients) against the shipped basis (luts/basis.json).

References: the exact Fresnel curve (basis.fresnel, itself tested against the complex-amplitude form in
test_fresnel.py), the four-point scheme's exactness at theta = 0 and pi/2 (Belcour et al. 2020), and the
different entry points of the solver against each other.
"""

import numpy as np
import pytest

from basis import (
    coefficients_from_curve,
    coefficients_from_gulbrandsen,
    coefficients_from_nk,
    coefficients_from_samples,
    coefficients_from_table,
    default_basis,
    fit_condition_number,
    fresnel_conductor,
    gulbrandsen_to_nk,
    reconstruct,
)
from basis.coefficients import fit_matrix
from basis.validation import ParameterError

THETA = np.linspace(0.0, 0.5 * np.pi, 2001)


def cosines(theta):
    """cos(theta) with cos(pi/2) set to exactly 0."""
    mu = np.cos(theta)
    mu[np.asarray(theta) == 0.5 * np.pi] = 0.0
    return mu


def random_materials(count, seed=1):
    """(eta, kappa) across the broad domain: eta log-uniform 0.05..50, kappa 0 (30 %) or uniform 0..100."""
    rng = np.random.default_rng(seed)
    eta = np.exp(rng.uniform(np.log(0.05), np.log(50.0), count))
    kappa = np.where(rng.random(count) < 0.3, 0.0, rng.uniform(0.0, 100.0, count))
    return eta, kappa


def max_curve_error(eta, kappa, chunk=256):
    """max over a 2001-point theta grid of |reconstruct - exact Fresnel| per material (in chunks of materials)."""
    mu = cosines(THETA)
    errors = []
    for start in range(0, len(eta), chunk):
        part = slice(start, start + chunk)
        coefficients = coefficients_from_nk(eta[part], kappa[part])
        approximation = reconstruct(coefficients[:, None, :], mu[None, :])
        exact = fresnel_conductor(mu[None, :], eta[part, None], kappa[part, None])
        errors.append(np.max(np.abs(approximation - exact), axis=1))
    return np.concatenate(errors)


# ----------------------------------------------------------------------------- exactness at the ends
def test_c0_is_normal_incidence_reflectance():
    """c0 == F(theta = 0) for 2000 random (eta, kappa) across the domain (atol 1e-12)."""
    eta, kappa = random_materials(2000)
    coefficients = coefficients_from_nk(eta, kappa)
    np.testing.assert_allclose(coefficients[:, 0], fresnel_conductor(1.0, eta, kappa), rtol=0, atol=1e-12)


def test_c1_is_grazing_minus_normal_for_real_materials():
    """c1 == F(pi/2) - F(0) for dielectrics eta 1.2..2.9 and metals eta 0.1..4, kappa 1..8 (atol 1e-12)."""
    rng = np.random.default_rng(2)
    eta = np.concatenate([rng.uniform(1.2, 2.9, 1000), np.exp(rng.uniform(np.log(0.1), np.log(4.0), 1000))])
    kappa = np.concatenate([np.zeros(1000), rng.uniform(1.0, 8.0, 1000)])
    coefficients = coefficients_from_nk(eta, kappa)
    expected = fresnel_conductor(0.0, eta, kappa) - fresnel_conductor(1.0, eta, kappa)
    np.testing.assert_allclose(coefficients[:, 1], expected, rtol=0, atol=1e-12)


def test_c1_is_grazing_minus_normal_across_domain():
    """c1 == F(pi/2) - F(0) exactly (documented) for 2000 random (eta, kappa) across the domain (atol 1e-12)."""
    eta, kappa = random_materials(2000)
    coefficients = coefficients_from_nk(eta, kappa)
    expected = fresnel_conductor(0.0, eta, kappa) - fresnel_conductor(1.0, eta, kappa)
    np.testing.assert_allclose(coefficients[:, 1], expected, rtol=0, atol=1e-12)


def test_reconstruction_interpolates_at_fit_angles():
    """reconstruct(c, cos(fit angles)) == F at the four fit angles for 2000 random materials (atol 1e-10)."""
    eta, kappa = random_materials(2000, seed=3)
    mu = cosines(default_basis().fit_angles)
    coefficients = coefficients_from_nk(eta, kappa)
    np.testing.assert_allclose(
        reconstruct(coefficients[:, None, :], mu[None, :]),
        fresnel_conductor(mu[None, :], eta[:, None], kappa[:, None]),
        rtol=0,
        atol=1e-10,
    )


# ----------------------------------------------------------------------------- approximation quality
# Measured with the shipped basis (training["holdout_max_abs_error"]["chosen"]): dielectrics 0.0033,
# metals 0.0120 on the held-out set. The tolerances (0.01 for dielectrics, 0.02 for metals) leave a
# margin of ~3x and ~1.7x.
DIELECTRIC_TOLERANCE = 0.01
METAL_TOLERANCE = 0.02


def test_stored_holdout_errors_are_within_tolerances():
    """The build's own held-out max |dF| (luts/basis.json) is below the tolerances used here."""
    chosen = default_basis().training["holdout_max_abs_error"]["chosen"]
    assert chosen["dielectrics"] <= DIELECTRIC_TOLERANCE
    assert chosen["metals"] <= METAL_TOLERANCE


def test_reproduces_dielectric_curves():
    """max |reconstruct - exact Fresnel| over 2001 theta samples <= 0.01 for dielectrics eta 1.2..2.9."""
    eta = np.linspace(1.2, 2.9, 171)
    assert max_curve_error(eta, np.zeros_like(eta)).max() <= DIELECTRIC_TOLERANCE


def test_reproduces_metal_curves():
    """max |reconstruct - exact Fresnel| over 2001 theta samples <= 0.02 for metals eta 0.1..4, kappa 1..8 (grid + random)."""
    eta, kappa = np.meshgrid(np.geomspace(0.1, 4.0, 40), np.linspace(1.0, 8.0, 40))
    rng = np.random.default_rng(4)
    eta = np.concatenate([eta.ravel(), np.exp(rng.uniform(np.log(0.1), np.log(4.0), 400))])
    kappa = np.concatenate([kappa.ravel(), rng.uniform(1.0, 8.0, 400)])
    assert max_curve_error(eta, kappa).max() <= METAL_TOLERANCE


# ----------------------------------------------------------------------------- shapes
@pytest.mark.parametrize(
    "eta, kappa, shape",
    [
        (1.5, 0.0, (4,)),
        ([0.27, 0.68, 1.32], [3.61, 2.64, 1.81], (3, 4)),
        (np.full((5, 3), 0.5), np.full((5, 3), 2.0), (5, 3, 4)),
        (np.full((5, 3), 0.5), 2.0, (5, 3, 4)),
    ],
)
def test_output_shapes(eta, kappa, shape):
    """Target shape (...) -> coefficients (..., 4); values equal the per-element scalar call (atol 0)."""
    coefficients = coefficients_from_nk(eta, kappa)
    assert coefficients.shape == shape
    eta_b, kappa_b = np.broadcast_arrays(np.asarray(eta, float), np.asarray(kappa, float))
    first = coefficients_from_nk(eta_b.flat[0], kappa_b.flat[0])
    np.testing.assert_allclose(coefficients.reshape(-1, 4)[0], first, rtol=0, atol=1e-15)


def test_reconstruct_shapes():
    """reconstruct: (3,4) coefficients with scalar mu -> (3,); (5,3,4) with (5,3) mu -> (5,3); (4,) with (7,) -> (7,)."""
    c = coefficients_from_nk([0.27, 0.68, 1.32], [3.61, 2.64, 1.81])
    assert reconstruct(c, 0.5).shape == (3,)
    c5 = np.broadcast_to(c, (5, 3, 4))
    assert reconstruct(c5, np.full((5, 3), 0.5)).shape == (5, 3)
    single = coefficients_from_nk(1.5, 0.0)
    mu = np.linspace(0.0, 1.0, 7)
    assert reconstruct(single, mu).shape == (7,)
    np.testing.assert_allclose(reconstruct(single, 1.0), 0.04, rtol=0, atol=1e-12)


# ----------------------------------------------------------------------------- entry points agree
GOLD = (np.array([0.27, 0.68, 1.32]), np.array([3.61, 2.64, 1.81]))


def test_curve_in_theta_agrees_with_nk():
    """coefficients_from_curve(F(theta), 'theta') == coefficients_from_nk (atol 1e-12; cos(pi/2) = 6e-17 only)."""
    eta, kappa = GOLD
    from_curve = coefficients_from_curve(
        lambda theta: fresnel_conductor(np.cos(theta)[None, :], eta[:, None], kappa[:, None]), variable="theta"
    )
    np.testing.assert_allclose(from_curve, coefficients_from_nk(eta, kappa), rtol=0, atol=1e-12)


def test_curve_in_mu_agrees_with_nk():
    """coefficients_from_curve(F(mu), 'mu') == coefficients_from_nk (atol 1e-12)."""
    eta, kappa = GOLD
    from_curve = coefficients_from_curve(
        lambda mu: fresnel_conductor(mu[None, :], eta[:, None], kappa[:, None]), variable="mu"
    )
    np.testing.assert_allclose(from_curve, coefficients_from_nk(eta, kappa), rtol=0, atol=1e-12)
    scalar = coefficients_from_curve(lambda mu: fresnel_conductor(mu, 1.5, 0.0), variable="mu")
    np.testing.assert_allclose(scalar, coefficients_from_nk(1.5, 0.0), rtol=0, atol=1e-12)


@pytest.mark.parametrize("eta, kappa", [(1.5, 0.0), (2.9, 0.0), (0.27, 3.61), (0.1, 8.0), (4.0, 1.0), (1.0, 10.0)])
def test_table_agrees_with_nk(eta, kappa):
    """coefficients_from_table on a 2001-point theta table == coefficients_from_nk (spline error; atol 1e-8)."""
    values = fresnel_conductor(cosines(THETA), eta, kappa)
    np.testing.assert_allclose(
        coefficients_from_table(THETA, values), coefficients_from_nk(eta, kappa), rtol=0, atol=1e-8
    )


def test_table_with_material_axes():
    """A (3, M) table gives (3, 4) coefficients equal to coefficients_from_nk per channel (atol 1e-8)."""
    eta, kappa = GOLD
    values = fresnel_conductor(cosines(THETA)[None, :], eta[:, None], kappa[:, None])
    np.testing.assert_allclose(
        coefficients_from_table(THETA, values), coefficients_from_nk(eta, kappa), rtol=0, atol=1e-8
    )


def test_samples_agree_with_nk():
    """coefficients_from_samples(F at fit angles) == coefficients_from_nk (same solve; atol 1e-15)."""
    eta, kappa = GOLD
    mu = cosines(default_basis().fit_angles)
    samples = fresnel_conductor(mu[None, :], eta[:, None], kappa[:, None])
    np.testing.assert_allclose(coefficients_from_samples(samples), coefficients_from_nk(eta, kappa), rtol=0, atol=1e-15)


def test_gulbrandsen_equals_nk_of_converted():
    """coefficients_from_gulbrandsen(r, g) == coefficients_from_nk(*gulbrandsen_to_nk(r, g)) (atol 0)."""
    r, g = np.meshgrid(np.linspace(0.0, 0.95, 12), np.linspace(0.0, 1.0, 7))
    np.testing.assert_allclose(
        coefficients_from_gulbrandsen(r, g), coefficients_from_nk(*gulbrandsen_to_nk(r, g)), rtol=0, atol=0
    )


def test_talk_figure2_setting():
    """Talk Figure 2, r = 0.44, g = (0, 1, 0): c0 = 0.44 and c1 = 0.56 in every channel (atol 1e-12); G differs from R."""
    coefficients = coefficients_from_gulbrandsen(0.44, [0.0, 1.0, 0.0])
    assert coefficients.shape == (3, 4)
    np.testing.assert_allclose(coefficients[:, 0], 0.44, rtol=0, atol=1e-12)
    np.testing.assert_allclose(coefficients[:, 1], 0.56, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(coefficients[0], coefficients[2])
    assert np.max(np.abs(coefficients[1, 2:] - coefficients[0, 2:])) > 0.1


# ----------------------------------------------------------------------------- conditioning, corners
def test_fit_condition_number():
    """The 4x4 fit matrix of the shipped basis is well conditioned: finite and < 100 (measured 4.8)."""
    condition = fit_condition_number()
    assert np.isfinite(condition) and 1.0 <= condition < 100.0
    np.testing.assert_allclose(condition, np.linalg.cond(fit_matrix()), rtol=1e-12)


@pytest.mark.parametrize(
    "eta, kappa",
    [(1.0, 1e3), (0.05, 1e3), (50.0, 1e3), (1.0001, 0.0), (0.9999, 0.0), (1e3, 0.0), (0.05, 0.0), (1.0, 0.0)],
)
def test_stiff_corners_are_finite(eta, kappa):
    """kappa = 1e3, eta -> 1, eta = 1e3, eta = 0.05: coefficients finite, c0 == F(0) (atol 1e-12)."""
    coefficients = coefficients_from_nk(eta, kappa)
    assert np.all(np.isfinite(coefficients))
    np.testing.assert_allclose(coefficients[0], fresnel_conductor(1.0, eta, kappa), rtol=0, atol=1e-12)


def test_gulbrandsen_near_one_is_finite():
    """Gulbrandsen r = 0.999 for g in [0, 1]: coefficients finite, c0 == 0.999 (atol 1e-12)."""
    coefficients = coefficients_from_gulbrandsen(0.999, np.linspace(0.0, 1.0, 11))
    assert np.all(np.isfinite(coefficients))
    np.testing.assert_allclose(coefficients[:, 0], 0.999, rtol=0, atol=1e-12)


# ----------------------------------------------------------------------------- bad input
def test_bad_samples_shape():
    """samples with trailing axis 3 or 0-d -> ParameterError naming 'samples'."""
    with pytest.raises(ParameterError, match=r"^samples"):
        coefficients_from_samples(np.zeros((5, 3)))
    with pytest.raises(ParameterError, match=r"^samples"):
        coefficients_from_samples(0.5)
    with pytest.raises(ParameterError, match=r"^samples"):
        coefficients_from_samples([0.1, np.nan, 0.2, 0.3])


def test_bad_coefficients_shape():
    """reconstruct with coefficients of trailing length 3 or a scalar -> ParameterError naming 'coefficients'."""
    with pytest.raises(ParameterError, match=r"^coefficients"):
        reconstruct(np.zeros((2, 3)), 0.5)
    with pytest.raises(ParameterError, match=r"^coefficients"):
        reconstruct(1.0, 0.5)
    with pytest.raises(ParameterError, match=r"^mu"):
        reconstruct(np.zeros(4), 1.5)


def test_bad_curve():
    """A non-callable curve, or variable not in {'theta', 'mu'} -> ParameterError."""
    with pytest.raises(ParameterError, match=r"^curve must be callable"):
        coefficients_from_curve([0.1, 0.2, 0.3, 0.4])
    with pytest.raises(ParameterError, match=r"^variable must be 'theta' or 'mu'"):
        coefficients_from_curve(lambda x: x, variable="degrees")
    with pytest.raises(ParameterError, match=r"^curve must return one value per fit angle \(4\)"):
        coefficients_from_curve(lambda x: x[:3], variable="theta")  # the curve's fault, not the samples


def test_bad_table():
    """Tables not covering [0, pi/2], too short, unsorted, beyond pi/2 or mismatched in length -> ParameterError."""
    short = np.linspace(0.0, 1.5, 100)
    with pytest.raises(ParameterError, match=r"cover \[0, pi/2\]"):
        coefficients_from_table(short, np.zeros(100))
    late = np.linspace(0.1, 0.5 * np.pi, 100)
    with pytest.raises(ParameterError, match=r"cover \[0, pi/2\]"):
        coefficients_from_table(late, np.zeros(100))
    with pytest.raises(ParameterError, match=r"^theta must be in \[0, 1.5708\]"):
        coefficients_from_table(np.linspace(0.0, 2.0, 100), np.zeros(100))
    with pytest.raises(ParameterError, match=r"strictly increasing"):
        coefficients_from_table(THETA[::-1], np.zeros(THETA.size))
    with pytest.raises(ParameterError, match=r"at least 4"):
        coefficients_from_table([0.0, 0.5 * np.pi], [0.04, 1.0])
    with pytest.raises(ParameterError, match=r"^values"):
        coefficients_from_table(THETA, np.zeros(THETA.size - 1))


def test_bad_basis_argument():
    """basis= something that is not a Basis -> ParameterError naming 'basis'."""
    with pytest.raises(ParameterError, match=r"^basis must be"):
        coefficients_from_nk(1.5, 0.0, basis="luts/basis.json")


@pytest.mark.parametrize(
    "eta, kappa, name", [(0.0, 1.0, "eta"), (1.5, -1.0, "kappa"), (np.nan, 0.0, "eta"), ("1.5", 0.0, "eta")]
)
def test_bad_nk(eta, kappa, name):
    """coefficients_from_nk validates eta and kappa like fresnel_conductor: ParameterError naming the parameter."""
    with pytest.raises(ParameterError, match=rf"^{name}\b"):
        coefficients_from_nk(eta, kappa)


@pytest.mark.parametrize("r, g, name", [(1.0, 0.5, "reflectivity"), (0.5, 2.0, "edge_tint")])
def test_bad_gulbrandsen(r, g, name):
    """coefficients_from_gulbrandsen: r = 1 or g > 1 -> ParameterError naming the parameter."""
    with pytest.raises(ParameterError, match=rf"^{name}\b"):
        coefficients_from_gulbrandsen(r, g)


def test_api_errors_name_the_parameter():
    """Mismatched shapes, a foreign basis, a wrong-length curve and overflowing samples are ParameterErrors
    naming what is wrong (they used to be numpy's broadcast error, AttributeError and silent inf)."""
    from basis import coefficients_least_squares, fresnel_conductor, material_coefficients

    cases = [
        (lambda: coefficients_from_nk([1.5, 1.6], [0.0, 0.0, 0.0]), "eta and kappa must broadcast"),
        (lambda: coefficients_least_squares([1.5, 1.6], [0.0, 0.0, 0.0]), "eta and kappa must broadcast"),
        (lambda: fresnel_conductor([0.5, 0.4], [1.5, 1.6, 1.7], 0.0), "must broadcast"),
        (lambda: reconstruct(np.zeros((2, 4)), np.zeros(3)), "coefficients and mu must broadcast"),
        (lambda: material_coefficients("Gold", basis="x"), "basis must be"),
        (lambda: coefficients_from_nk(1.5, 0.0, basis="x"), "basis must be"),
        (lambda: coefficients_from_samples([1e308, -1e308, 1e308, 1e308]), "overflow"),
    ]
    for call, words in cases:
        with pytest.raises(ParameterError, match=words):
            call()


def test_least_squares_of_many_materials_runs_in_chunks():
    """10^4 materials at once (chunks of 4096) give the same coefficients as one at a time."""
    from basis import coefficients_least_squares

    rng = np.random.default_rng(5)
    eta, kappa = rng.uniform(0.2, 3.0, 10_000), rng.uniform(0.0, 5.0, 10_000)
    together = coefficients_least_squares(eta, kappa)
    alone = coefficients_least_squares(eta[[0, 4095, 4096, 9999]], kappa[[0, 4095, 4096, 9999]])
    np.testing.assert_allclose(together[[0, 4095, 4096, 9999]], alone, rtol=0, atol=1e-14)
