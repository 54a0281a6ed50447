"""GGX distribution, Smith masking and visible-normal sampling (preintegrate.ggx).

References are independent: scipy quadrature of the defining integrals (Walter 2007 eq. 33, Heitz 2014
eq. 2/7 and 72, 99, Heitz 2018 eq. 1) and the formulas re-typed in tests/references/integration.py.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import cubature, quad

from preintegrate import ggx
from tests.references.integration import ggx_d, smith_lambda_tan

ALPHAS = [0.001, 0.01, 0.05, 0.3, 0.7, 1.0]


def _theta_cuts(alpha, low=0.0, high=0.5 * np.pi, extra=()):
    """Break points in θ_h that bracket GGX's peak (width ≈ α) so adaptive rules resolve it."""
    cuts = {low, high, *extra}
    for multiple in (0.25, 1.0, 4.0, 16.0, 64.0):
        value = float(np.arctan(multiple * alpha))
        if low < value < high:
            cuts.add(value)
    return sorted(cuts)


def _visible_integral(g, mu_o, alpha, theta_low=0.0):
    """∫_{θ_h ≥ theta_low} g(h) max(0, ω_o·h) D(h) dω_h by adaptive 2-D Gauss–Kronrod cubature.

    ω_o = (sin θo, 0, μo); g maps h (N, 3) → (N, K). The domain ω_o·h > 0 is cos φ > −μo cosθ /(sinθo sinθ):
    φ ∈ [−φmax(θ), φmax(θ)], mapped onto s ∈ [−1, 1] (φ = s φmax, Jacobian φmax). φmax stops being π at
    θ_k = π/2 − θo and behaves like π − C √(θ − θ_k) just above it, so θ is split there and, above θ_k,
    written θ = θ_k + u² (Jacobian 2u), which makes every piece smooth.
    """
    sin_o = np.sqrt(1.0 - mu_o * mu_o)
    omega_o = np.array([sin_o, 0.0, mu_o])
    kink = 0.5 * np.pi - float(np.arccos(mu_o))

    def phi_max(theta):
        with np.errstate(divide="ignore", invalid="ignore"):
            c = -mu_o * np.cos(theta) / (sin_o * np.sin(theta))
        return np.arccos(np.clip(np.nan_to_num(c, nan=-1.0, neginf=-1.0, posinf=1.0), -1.0, 1.0))

    def integrand(points, above):
        v, s = points[:, 0], points[:, 1]
        theta, jacobian = (kink + v * v, 2.0 * v) if above else (v, 1.0)
        width = phi_max(theta)
        phi = s * width
        h = np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)], axis=-1)
        weight = np.maximum(h @ omega_o, 0.0) * ggx_d(h[:, 2], alpha) * np.sin(theta) * width * jacobian
        return np.asarray(g(h)) * weight[:, None]

    cuts = _theta_cuts(alpha, theta_low, 0.5 * np.pi, extra=[kink] if theta_low < kink < 0.5 * np.pi else [])
    total = 0.0
    for low, high in zip(cuts[:-1], cuts[1:]):
        above = low >= kink and sin_o > 0.0
        if above:
            low, high = np.sqrt(low - kink), np.sqrt(high - kink)
        result = cubature(integrand, [low, -1.0], [high, 1.0], rule="gk21", rtol=1e-10, atol=1e-12, args=(above,))
        assert result.status == "converged" or np.max(result.error) < 1e-10
        total = total + result.estimate
    return np.atleast_1d(total)


# ----------------------------------------------------------------------------- D
@pytest.mark.parametrize("alpha", ALPHAS)
def test_ndf_is_normalised(alpha):
    """∫ D(h) μh dω_h = 1 (Walter 2007 eq. 4) by scipy.integrate.quad over θ_h with break points at the peak; tol 1e-8."""

    def integrand(theta):
        return 2.0 * np.pi * float(ggx.ndf(np.cos(theta), alpha)) * np.cos(theta) * np.sin(theta)

    cuts = _theta_cuts(alpha)
    total = sum(quad(integrand, a, b, epsabs=1e-13, epsrel=1e-12, limit=200)[0] for a, b in zip(cuts[:-1], cuts[1:]))
    np.testing.assert_allclose(total, 1.0, rtol=0, atol=1e-8)


def test_ndf_matches_definition_and_is_zero_below_horizon():
    """ndf equals α²/(π(μ²(α²−1)+1)²) re-typed from Walter 2007 eq. 33 (rtol 1e-14), and 0 for μh ≤ 0."""
    mu = np.linspace(-1.0, 1.0, 401)
    for alpha in ALPHAS:
        expected = np.where(mu > 0, alpha**2 / (np.pi * (mu**2 * (alpha**2 - 1) + 1) ** 2), 0.0)
        np.testing.assert_allclose(ggx.ndf(mu, alpha), expected, rtol=1e-14, atol=0)
    assert float(ggx.ndf(0.0, 0.5)) == 0.0


def test_roughness_to_alpha_is_square():
    """α = r² (Burley 2012) compared with numpy's square; exact."""
    r = np.linspace(0.0, 1.0, 11)
    np.testing.assert_array_equal(ggx.roughness_to_alpha(r), r * r)


@pytest.mark.parametrize("mu_o", [0.05, 0.4, 0.8, 1.0])
@pytest.mark.parametrize("alpha", [0.01, 0.2, 0.6, 1.0])
def test_projected_area_identity(mu_o, alpha):
    """∫ G1(ω_o) max(0, ω_o·h) D(h) dω_h = μo (Heitz 2014 eq. 2/7), h-integral by 2-D cubature; tol 1e-6."""
    area = _visible_integral(lambda h: np.ones((h.shape[0], 1)), mu_o, alpha)[0]
    np.testing.assert_allclose(float(ggx.g1(mu_o, alpha)) * area, mu_o, rtol=0, atol=1e-6)


# ----------------------------------------------------------------------------- Λ, G1, G2
MU = np.concatenate([np.geomspace(1e-6, 1e-2, 9), np.linspace(0.02, 1.0, 50)])


@pytest.mark.parametrize("alpha", ALPHAS)
def test_smith_lambda_matches_tan_form(alpha):
    """smith_lambda equals (−1 + √(1 + α² tan²θ))/2 (Heitz 2014 eq. 72) re-typed independently; rtol 1e-9."""
    np.testing.assert_allclose(ggx.smith_lambda(MU, alpha), smith_lambda_tan(MU, alpha), rtol=1e-9, atol=1e-15)
    assert float(ggx.smith_lambda(1.0, alpha)) == 0.0


@pytest.mark.parametrize("alpha", ALPHAS)
def test_g1_is_one_over_one_plus_lambda(alpha):
    """g1 = 1/(1 + Λ) with Λ in tan form (Heitz 2014 eq. 43); rtol 1e-12; G1(μ=1) = 1 exactly, G1(0) = G1(<0) = 0."""
    np.testing.assert_allclose(ggx.g1(MU, alpha), 1.0 / (1.0 + smith_lambda_tan(MU, alpha)), rtol=1e-12)
    np.testing.assert_allclose(ggx.g1(MU, alpha), 1.0 / (1.0 + ggx.smith_lambda(MU, alpha)), rtol=1e-12)
    assert float(ggx.g1(1.0, alpha)) == 1.0
    assert float(ggx.g1(0.0, alpha)) == 0.0
    assert float(ggx.g1(-0.3, alpha)) == 0.0
    values = ggx.g1(MU, alpha)
    assert np.all((values > 0) & (values <= 1)) and np.all(np.diff(values) >= -1e-15)


def test_g1_closed_forms():
    """G1 at α = 1 is 2μ/(1+μ) and at α → 0 is 1 (closed forms of Heitz 2014 eq. 72); rtol 1e-13."""
    np.testing.assert_allclose(ggx.g1(MU, 1.0), 2 * MU / (1 + MU), rtol=1e-13)
    np.testing.assert_allclose(ggx.g1(MU[MU > 0.01], 0.0), 1.0, rtol=1e-13)


@pytest.mark.parametrize("alpha", ALPHAS)
def test_g2_height_correlated_properties(alpha):
    """G2 = 1/(1+Λo+Λi) (Heitz 2014 eq. 99, rtol 1e-12), symmetric (exact up to 1 ulp), G1o·G1i ≤ G2 ≤ min(G1o, G1i), 0 at the horizon."""
    mu_o, mu_i = np.meshgrid(MU, MU, indexing="ij")
    g2 = ggx.g2_height_correlated(mu_o, mu_i, alpha)
    expected = 1.0 / (1.0 + smith_lambda_tan(mu_o, alpha) + smith_lambda_tan(mu_i, alpha))
    np.testing.assert_allclose(g2, expected, rtol=1e-12)
    np.testing.assert_allclose(g2, g2.T, rtol=1e-15, atol=0)
    g1o, g1i = ggx.g1(mu_o, alpha), ggx.g1(mu_i, alpha)
    assert np.all(g2 <= np.minimum(g1o, g1i) * (1 + 1e-14))
    assert np.all(g2 >= g1o * g1i * (1 - 1e-14))
    for horizon in (0.0, -0.2):
        np.testing.assert_array_equal(ggx.g2_height_correlated(horizon, MU, alpha), 0.0)
        np.testing.assert_array_equal(ggx.g2_height_correlated(MU, horizon, alpha), 0.0)
    assert float(ggx.g2_height_correlated(1.0, 1.0, alpha)) == 1.0


def test_g2_is_finite_near_horizon():
    """G2 stays finite and tends to 0 as μi → 0 (limit of eq. 99: ≈ 2μi/α); compared with 2μoμi/(μi Ro + μo α), rtol 1e-6."""
    mu_i = np.array([1e-300, 1e-200, 1e-30, 1e-12])
    for alpha in (0.001, 0.5, 1.0):
        g2 = ggx.g2_height_correlated(0.5, mu_i, alpha)
        assert np.all(np.isfinite(g2))
        ro = np.sqrt(0.25 + alpha**2 * 0.75)
        np.testing.assert_allclose(g2, 2 * 0.5 * mu_i / (mu_i * ro + 0.5 * alpha), rtol=1e-6)


# ----------------------------------------------------------------------------- VNDF sampling
SAMPLES = 400_000
VNDF_CASES = [  # (μo, α, azimuth of ω_o)
    (0.5, 0.3, 0.0),
    (0.9, 1.0, 1.1),
    (0.15, 0.05, 2.0),
    (1.0, 0.5, 0.0),  # normal incidence: the degenerate-frame branch
    (0.02, 0.8, -0.7),
    (0.3, 0.001, 0.4),
]


def _samples(mu_o, alpha, azimuth, seed=7):
    sin_o = np.sqrt(1 - mu_o * mu_o)
    omega_o = np.array([sin_o * np.cos(azimuth), sin_o * np.sin(azimuth), mu_o])
    rng = np.random.default_rng(seed)
    h = ggx.sample_vndf(omega_o, alpha, rng.random(SAMPLES), rng.random(SAMPLES))
    # Rotate into ω_o's azimuthal frame (ω_o in the xz half-plane x ≥ 0).
    c, s = np.cos(azimuth), np.sin(azimuth)
    local = np.stack([c * h[:, 0] + s * h[:, 1], -s * h[:, 0] + c * h[:, 1], h[:, 2]], axis=-1)
    return omega_o, h, local


@pytest.mark.parametrize("mu_o, alpha, azimuth", VNDF_CASES)
def test_sample_vndf_outputs_visible_unit_vectors(mu_o, alpha, azimuth):
    """Samples are unit vectors (|h| = 1 to 1e-12) in the upper hemisphere with h·ω_o ≥ 0 (Heitz 2018: support of D_ωo), all finite."""
    omega_o, h, _ = _samples(mu_o, alpha, azimuth)
    assert h.shape == (SAMPLES, 3) and np.all(np.isfinite(h))
    np.testing.assert_allclose(np.linalg.norm(h, axis=-1), 1.0, rtol=0, atol=1e-12)
    assert np.all(h[:, 2] >= 0.0)
    assert np.all(h @ omega_o >= -1e-12)


def _test_functions(omega_o_local):
    def g(h):
        return np.stack(
            [h[:, 2], h[:, 2] ** 2, h @ omega_o_local, h[:, 0], h[:, 0] ** 2, h[:, 1], h[:, 1] ** 2], axis=-1
        )

    return g


@pytest.mark.parametrize("mu_o, alpha, azimuth", VNDF_CASES)
def test_sample_vndf_moments_match_vndf_density(mu_o, alpha, azimuth):
    """Sample means of μh, μh², ω_o·h, h_x, h_x², h_y, h_y² equal ∫ g D_ωo dω_h (D_ωo = G1 max(0,ω_o·h) D/μo, Heitz 2018 eq. 1) by 2-D cubature; within 5σ."""
    _, _, local = _samples(mu_o, alpha, azimuth)
    omega_local = np.array([np.sqrt(1 - mu_o * mu_o), 0.0, mu_o])
    g = _test_functions(omega_local)
    expected = float(ggx.g1(mu_o, alpha)) / mu_o * _visible_integral(g, mu_o, alpha)
    values = g(local)
    mean = values.mean(axis=0)
    sigma = values.std(axis=0, ddof=1) / np.sqrt(SAMPLES)
    assert np.all(np.abs(mean - expected) <= 5 * sigma + 1e-12), (mean, expected, sigma)


@pytest.mark.parametrize("mu_o, alpha, azimuth", VNDF_CASES)
def test_sample_vndf_mu_h_distribution(mu_o, alpha, azimuth):
    """Empirical CDF of μh at its deciles equals P(μh ≤ c) = ∫_{θh ≥ arccos c} D_ωo dω_h by 2-D cubature; within 5 binomial σ."""
    _, _, local = _samples(mu_o, alpha, azimuth)
    mu_h = local[:, 2]
    if np.ptp(mu_h) == 0.0:  # all samples at the normal (cannot happen for α > 0)
        pytest.fail("degenerate sample set")
    scale = float(ggx.g1(mu_o, alpha)) / mu_o
    one = lambda h: np.ones((h.shape[0], 1))  # noqa: E731
    for q in np.arange(1, 10) / 10:
        c = float(np.quantile(mu_h, q))
        empirical = float(np.mean(mu_h <= c))
        if c >= 1.0:
            continue
        cdf = scale * _visible_integral(one, mu_o, alpha, theta_low=float(np.arccos(c)))[0]
        sigma = np.sqrt(max(cdf * (1 - cdf), 1e-12) / SAMPLES)
        assert abs(empirical - cdf) <= 5 * sigma + 1e-9, (q, c, empirical, cdf, sigma)


def test_sample_vndf_broadcasts_alpha():
    """sample_vndf with an α array gives the same h as scalar calls element by element (exact)."""
    omega_o = np.array([0.6, 0.0, 0.8])
    rng = np.random.default_rng(3)
    u1, u2 = rng.random(5), rng.random(5)
    alpha = np.array([0.01, 0.1, 0.4, 0.8, 1.0])
    batch = ggx.sample_vndf(omega_o, alpha, u1, u2)
    for k in range(5):
        np.testing.assert_array_equal(batch[k], ggx.sample_vndf(omega_o, alpha[k], u1[k : k + 1], u2[k : k + 1])[0])
