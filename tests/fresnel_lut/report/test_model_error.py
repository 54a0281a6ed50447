"""Studies 2 and 3 (fresnel_lut.report.model_error): texel weights and a quick run of both studies.

References: direct integration of the exact Fresnel curve with the one integrator
(preintegrate.quadrature.directional_albedo) and the engine's LUT channels (preintegrate.lut.build_table);
polynomials in theta, which the four-point Lagrange cardinal functions reproduce exactly.
"""

import math

import numpy as np
import pytest

from basis import default_basis, fresnel_conductor
from basis.validation import ParameterError
from fresnel_lut.report.model_error import model_error_markdown, model_error_study, plot_model_error
from preintegrate.channels import basis_channels
from preintegrate.lut import LutGrid, build_table
from preintegrate.quadrature import directional_albedo, lagrange_cardinals, texel_weights

BASIS = default_basis()
MU_O, ROUGHNESS = LutGrid.centred(8).mu_o, LutGrid.centred(8).roughness
ALPHA = ROUGHNESS**2


def grid_cosines(theta):
    mu = np.cos(theta)
    mu[theta == 0.5 * np.pi] = 0.0
    return mu


@pytest.fixture(scope="module")
def weights():
    """(8, 8, 512) texel weights on the basis grid, LUT texel centres."""
    return texel_weights(BASIS.theta, MU_O[None, :], ALPHA[:, None])


def test_cardinal_functions_reproduce_cubics_in_theta():
    """sum_j p(theta_j) L_j(theta) = p(theta) for a cubic p on a non-uniform grid (atol 1e-12)."""
    grid = np.sort(np.r_[0.0, np.random.default_rng(2).uniform(0.0, 0.5 * np.pi, 30), 0.5 * np.pi])

    def cubic(theta):
        return 0.3 - theta + 0.7 * theta**2 - 0.25 * theta**3

    x = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(lagrange_cardinals(grid)(x) @ cubic(grid), cubic(np.arccos(x)), rtol=0, atol=1e-12)


def test_weights_match_direct_integration_of_exact_fresnel(weights):
    """W @ F(theta grid) equals directional_albedo of the exact curve for 3 materials, 64 texels (atol 1e-6)."""
    eta, kappa = np.array([1.5, 0.2, 1.1]), np.array([0.0, 3.5, 6.0])
    direct = directional_albedo(lambda x: fresnel_conductor(x[..., None], eta, kappa), MU_O[None, :], ALPHA[:, None])
    via_weights = weights @ fresnel_conductor(grid_cosines(BASIS.theta)[:, None], eta, kappa)
    np.testing.assert_allclose(via_weights, direct, rtol=0, atol=1e-6)


def test_weights_match_the_basis_lut(weights):
    """W @ b_k(theta grid) equals the basis LUT channels of build_table (atol 1e-6)."""
    channels = basis_channels()
    np.testing.assert_allclose(
        weights @ channels.functions(grid_cosines(BASIS.theta)),
        build_table(channels, LutGrid.centred(8)),
        rtol=0,
        atol=1e-6,
    )


def test_weights_integrate_one_to_the_ggx_albedo(weights):
    """sum_j W_j is the albedo of f = 1; it lies in (0, 1] (energy conservation of GGX, Heitz 2014)."""
    albedo = weights.sum(axis=-1)
    assert np.all(albedo > 0.0) and np.all(albedo <= 1.0 + 1e-9)


def test_raise_exception_texel_weights():
    with pytest.raises(ParameterError, match="theta_grid must cover"):
        texel_weights(np.linspace(0.0, 1.0, 10), 0.5, 0.5)
    with pytest.raises(ParameterError, match="strictly increasing"):
        texel_weights(np.array([0.0, 0.2, 0.1, 0.5 * np.pi]), 0.5, 0.5)


def test_quick_study_is_finite(tmp_path):
    """The quick study (thinned groups, 32 x 32) returns finite numbers, tables and a PNG."""
    result = model_error_study(quick=True)
    curve, preintegrated = result["curve"], result["preintegrated"]
    assert set(curve["models"]) == {"exact", "schlick", "basis-4point", "basis-lsq", "basis-minimax"}
    assert set(preintegrated["models"]) == {"schlick", "basis-4point", "basis-lsq", "basis-minimax"}
    for entry in curve["models"].values():
        assert math.isfinite(entry["ns_per_evaluation"]) and entry["ns_per_evaluation"] > 0.0
        for group in entry["groups"].values():
            assert all(math.isfinite(group[key]) for key in ("max_worst", "max_mean", "rms_worst", "rms_mean"))
    for per_group in preintegrated["models"].values():
        for group in per_group.values():
            assert np.all(np.isfinite(group["max_per_material"])) and 0.0 <= group["max_worst"] <= 1.0
    assert curve["models"]["exact"]["groups"]["metals"]["max_worst"] == 0.0
    assert preintegrated["lut_check"]["max_abs_difference"] < 1e-5
    text = model_error_markdown(result)
    assert "basis-minimax" in text and "nan" not in text.lower()
    pytest.importorskip("matplotlib")
    path = plot_model_error(result, tmp_path / "study.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
