"""Directional albedo of pbrt's FresnelBlend with GGX (preintegrate/fresnel_blend.py).

References: the closed form 23/56 of the diffuse integral (module docstring), the mirror limit α → 0
(E_s → F(μo)), and a Monte-Carlo estimate of ∫ f μi dωi with ωi uniform on the hemisphere that
evaluates pbrt's f directly (no half-vector change of variables), 4σ.
"""

import numpy as np
import pytest
from scipy.integrate import quad

from basis.validation import ParameterError
from preintegrate.fresnel_blend import (
    fresnel_blend_albedo,
    fresnel_blend_brdf,
    fresnel_blend_diffuse_albedo,
    fresnel_blend_specular_albedo,
)


def test_diffuse_integral_is_23_over_56():
    value, _ = quad(lambda mu: mu * (1.0 - (1.0 - 0.5 * mu) ** 5), 0.0, 1.0)
    assert value == pytest.approx(23.0 / 56.0, abs=1e-14)
    # E_d = 28/(23π) Rd (1 − Rs)(1 − (1 − μo/2)^5) · 2π · 23/56
    np.testing.assert_allclose(fresnel_blend_diffuse_albedo(0.6, 0.5, 0.04), 0.5 * 0.96 * (1.0 - 0.7**5), atol=1e-15)


@pytest.mark.parametrize("mu_o", [0.95, 0.5, 0.1])
def test_mirror_limit(mu_o):
    rs = 0.04
    np.testing.assert_allclose(
        fresnel_blend_specular_albedo(mu_o, 1e-5, rs), rs + (1.0 - rs) * (1.0 - mu_o) ** 5, atol=2e-4
    )


@pytest.mark.parametrize("mu_o, alpha", [(0.8, 0.5), (0.3, 0.3), (0.1, 0.8)])
def test_albedo_against_monte_carlo(mu_o, alpha):
    rng = np.random.default_rng(7)
    samples = 2_000_000
    mu_i = rng.uniform(0.0, 1.0, samples)
    phi = rng.uniform(0.0, 2.0 * np.pi, samples)
    sin_i = np.sqrt(1.0 - mu_i**2)
    w_i = np.stack([sin_i * np.cos(phi), sin_i * np.sin(phi), mu_i], axis=-1)
    w_o = np.array([np.sqrt(1.0 - mu_o**2), 0.0, mu_o])
    h = w_i + w_o
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    values = 2.0 * np.pi * mu_i * fresnel_blend_brdf(mu_i, mu_o, h[:, 2], np.sum(w_i * h, axis=-1), alpha, 0.5, 0.04)
    mean, error = values.mean(), values.std() / np.sqrt(samples)
    assert abs(fresnel_blend_albedo(mu_o, alpha, 0.5, 0.04) - mean) < 4.0 * error


def test_converged_and_broadcast():
    mu_o = np.array([0.2, 0.7])[:, None]
    alpha = np.array([0.1, 0.4, 0.9])
    coarse = fresnel_blend_albedo(mu_o, alpha, 0.3, [0.04, 0.5, 0.9])
    fine = fresnel_blend_albedo(mu_o, alpha, 0.3, [0.04, 0.5, 0.9], nodes_u=1024, nodes_phi=1024)
    assert coarse.shape == (2, 3)
    np.testing.assert_allclose(coarse, fine, atol=2e-5)


def test_errors():
    with pytest.raises(ParameterError, match=r"rd must be in \[0, 1\]"):
        fresnel_blend_diffuse_albedo(0.5, 1.5, 0.04)
    with pytest.raises(ParameterError, match="alpha"):
        fresnel_blend_specular_albedo(0.5, 0.0, 0.04)
    with pytest.raises(ParameterError, match="mu_o"):
        fresnel_blend_albedo(np.nan, 0.5, 0.5, 0.04)
