"""Exact split-sum channels of the linear models of the references (preintegrate/channels.py, build --model).

For each model linear in fixed functions t_n of cos θ, Σ_n w_n · t̄_n (the integrator's channels) must
equal the split sum of the model's own curve, estimated independently by VNDF Monte Carlo
(preintegrate/montecarlo.py) — within 4σ plus the integrator's 1e-6.
"""

import numpy as np
import pytest

from basis.models import FRESNEL_MODELS, fresnel_model
from basis.validation import ParameterError
from preintegrate.channels import CHANNEL_SETS, channel_set, schlick_channels
from preintegrate.estimators import monte_carlo_albedo
from preintegrate.quadrature import directional_albedo

# One material per linear model, away from the clamp (checked below), RGB where the model has colours.
CASES = {
    "schlick": {"f0": [0.9, 0.6, 0.3]},
    "generalized-schlick": {"r0": [0.04, 0.5, 0.9], "r90": [1.0, 0.8, 0.6], "exponent": 2.5},
    "lazanyi": {"f0": [0.9, 0.6, 0.3], "a": [0.5, 1.0, 1.5], "alpha": 4.0},
    "f82": {"f0": [0.9, 0.6, 0.3], "f82": [0.85, 0.55, 0.35]},
    "adobe": {"f0": [0.9, 0.6, 0.3], "tint": [0.9, 0.8, 1.0]},
    "generalized-adobe": {"r0": [0.9, 0.6, 0.3], "r90": [1.0, 0.9, 0.8], "exponent": 4.0, "tint": [0.9, 0.8, 1.0]},
    "cook-torrance": {"f0": [0.9, 0.6, 0.3], "eta_prime": 0.42, "kappa_prime": 2.35},
    "schlick-external": {"f0": [0.04, 0.5, 0.9], "eta_e": 1.33},
    "schlick-external-metal": {"f0": [0.04, 0.5, 0.9], "eta_e": 2.42},
    "fresnel-blend": {"rs": [0.04, 0.5, 0.9]},
}
TEXELS = [(0.9, 0.2), (0.35, 0.5), (0.08, 0.8)]  # (μo, α)


def test_every_linear_model_has_a_case_and_a_channel_set():
    linear = {name for name, model in FRESNEL_MODELS.items() if model.linear}
    assert set(CASES) == linear
    assert linear <= set(CHANNEL_SETS)


@pytest.mark.parametrize("name", sorted(CASES))
def test_weighted_channels_equal_monte_carlo_of_the_curve(name):
    model = fresnel_model(name)
    parameters = CASES[name]
    assert np.all(model.clamp_is_inactive(**parameters))
    channels = channel_set(name, **parameters)
    weights = model.channel_weights(**parameters)  # (3, n)
    for index, (mu_o, alpha) in enumerate(TEXELS):
        table = directional_albedo(channels.functions, mu_o, alpha)  # (n,)
        mean, error = monte_carlo_albedo(
            lambda x: model.evaluate(x[..., None], **parameters), mu_o, alpha, samples=400_000, seed=index
        )
        np.testing.assert_array_less(np.abs(weights @ table - mean), 4.0 * error + 1e-6)


def test_schlick_model_channels_are_the_shipped_schlick_channels():
    x = np.linspace(0.0, 1.0, 11)
    np.testing.assert_array_equal(channel_set("fresnel-blend").functions(x), channel_set("schlick").functions(x))


def test_the_schlick_channel_set_is_schlicks():
    """One registry: ``channel_set("schlick")`` is the set of the shipped Schlick table (Karis's scale and bias,
    his combination rule), and its functions are 1 - (1 - x)^5 and (1 - x)^5 (Schlick 1994, eq. 15)."""
    x = np.linspace(0.0, 1.0, 11)
    registered, shipped = channel_set("schlick"), schlick_channels()
    assert (registered.name, registered.channel_names, registered.combination) == (
        shipped.name,
        shipped.channel_names,
        shipped.combination,
    )
    assert shipped.combination == "Fbar = F0 * R + G (Karis 2013; R = scale, G = bias)"
    np.testing.assert_array_equal(registered.functions(x), np.stack([1.0 - (1.0 - x) ** 5, (1.0 - x) ** 5], axis=-1))


def test_shape_parameters_fix_the_channels():
    x = np.linspace(0.0, 1.0, 11)
    two = channel_set("generalized-schlick", exponent=2.0).functions(x)
    np.testing.assert_allclose(two[:, 1], (1.0 - x) ** 2, atol=1e-15)
    assert channel_set("f82").n_channels == 3 and channel_set("generalized-schlick").n_channels == 2
    with pytest.raises(ParameterError, match="not linear"):
        fresnel_model("gulbrandsen").channel_functions()
    with pytest.raises(ParameterError, match=r"exponent must be in \[0.1, 50\]"):
        channel_set("generalized-schlick", exponent=0.0)


# Every model (linear or not): the basis projection rendered with the basis channels, against VNDF
# Monte Carlo of the model's own curve. F̄ is ∫ F K with K ≥ 0 and ∫ K ≤ 1 (energy), so the split-sum
# error of the projection is at most its max |ΔF| over θ: the bound is that plus 4σ.
ALL_CASES = {
    **CASES,
    "exact-external": {"eta": [0.18, 0.42, 1.37], "kappa": [3.42, 2.35, 1.77], "eta_e": 1.33},
    "gulbrandsen": {"reflectivity": [0.9, 0.6, 0.3], "edge_tint": [0.2, 0.5, 0.9]},
}


@pytest.mark.parametrize("name", sorted(ALL_CASES))
def test_basis_projection_of_every_model_against_monte_carlo(name):
    from basis.angles import cos_theta
    from basis.coefficients import coefficients_from_samples
    from basis.eigenbasis import default_basis
    from preintegrate.channels import basis_channels

    assert set(ALL_CASES) == set(FRESNEL_MODELS)
    model, parameters, basis = fresnel_model(name), ALL_CASES[name], default_basis()
    coefficients = coefficients_from_samples(model.evaluate(cos_theta(basis.fit_angles)[:, None], **parameters).T)
    theta = np.linspace(0.0, 0.5 * np.pi, 4001)
    exact = model.evaluate(cos_theta(theta)[:, None], **parameters)
    projection_error = np.max(np.abs(exact - (coefficients @ basis.evaluate(theta).T).T), axis=0)
    for index, (mu_o, alpha) in enumerate(TEXELS[:2]):
        rendered = coefficients @ directional_albedo(basis_channels().functions, mu_o, alpha)
        mean, error = monte_carlo_albedo(
            lambda x: model.evaluate(x[..., None], **parameters), mu_o, alpha, samples=200_000, seed=10 + index
        )
        np.testing.assert_array_less(np.abs(rendered - mean), projection_error + 4.0 * error + 1e-6)
