"""Independent reference for the split-sum directional albedo, shared by the test modules.

F̄_k(μo, α) = ∫_{H²} f_k(ω_o·h) ρ(ω_o, ω_i) μ_i dω_i, ρ = D(h) G2(ω_o, ω_i) / (4 μo μi),

integrated directly over the incident direction in plain spherical coordinates (θi, φi) with
scipy's adaptive Gauss–Kronrod cubature (``scipy.integrate.cubature``). Nothing here comes from the
library: GGX D, Smith Λ (tan form) and the height-correlated G2 are re-typed from the definitions, and
there is no half-vector change of variables, no stretched coordinates and no horizon cut splitting.

With ω_o = (sin θo, 0, μo) the integrand is even in φi, so F̄ = 2 ∫_0^{π/2} ∫_0^{π} … dφi dθi. The
specular peak sits at the mirror direction (θi = θo, φi = π); the θi range is split there so the
adaptive rule does not have to find it. This is accurate (≲1e-9) for α ≳ 0.05; for tiny α the peak
is too narrow for a grid in ω_i: :func:`reference_albedo_half_vector` integrates over the half vector
instead (only dω_i = 4 (ω_o·h) dω_h is used; no stretched coordinates, no analytic horizon cut).
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import cubature


def ggx_d(mu_h, alpha):
    """D(h) = α² / (π (μh² (α² − 1) + 1)²), 0 for μh ≤ 0."""
    a2 = alpha * alpha
    den = mu_h * mu_h * (a2 - 1.0) + 1.0
    return np.where(mu_h > 0.0, a2 / (np.pi * den * den), 0.0)


def smith_lambda_tan(mu, alpha):
    """Λ(μ) = (−1 + √(1 + α² tan²θ)) / 2 for 0 < μ ≤ 1 (inf at μ = 0)."""
    mu = np.asarray(mu, dtype=np.float64)
    with np.errstate(divide="ignore", invalid="ignore"):
        tan2 = (1.0 - mu * mu) / (mu * mu)
        return 0.5 * (-1.0 + np.sqrt(1.0 + alpha * alpha * tan2))


def g2_reference(mu_o, mu_i, alpha):
    """1 / (1 + Λ(μo) + Λ(μi)), 0 when either cosine is ≤ 0."""
    mu_i = np.asarray(mu_i, dtype=np.float64)
    ok = (mu_i > 0.0) & (np.asarray(mu_o) > 0.0)
    safe_i = np.where(ok, mu_i, 1.0)
    value = 1.0 / (1.0 + smith_lambda_tan(mu_o, alpha) + smith_lambda_tan(safe_i, alpha))
    return np.where(ok, value, 0.0)


def g2_separable_reference(mu_o, mu_i, alpha):
    """1 / ((1 + Λ(μo)) (1 + Λ(μi))): the separable form G1(o) G1(i), 0 when either cosine is ≤ 0."""
    mu_i = np.asarray(mu_i, dtype=np.float64)
    ok = (mu_i > 0.0) & (np.asarray(mu_o) > 0.0)
    safe_i = np.where(ok, mu_i, 1.0)
    value = 1.0 / ((1.0 + smith_lambda_tan(mu_o, alpha)) * (1.0 + smith_lambda_tan(safe_i, alpha)))
    return np.where(ok, value, 0.0)


G2_FORMS = {"height-correlated": g2_reference, "separable": g2_separable_reference}


def _integrand(points, functions, mu_o, alpha, g2=g2_reference):
    theta_i, phi_i = points[:, 0], points[:, 1]
    sin_o = np.sqrt(max(1.0 - mu_o * mu_o, 0.0))
    sin_i, mu_i = np.sin(theta_i), np.cos(theta_i)
    wi = np.stack([sin_i * np.cos(phi_i), sin_i * np.sin(phi_i), mu_i], axis=-1)
    h = wi + np.array([sin_o, 0.0, mu_o])
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    x = np.clip(h @ np.array([sin_o, 0.0, mu_o]), 0.0, 1.0)
    # ρ μi sinθi = D G2 / (4 μo) · sinθi; times 2 for the φ symmetry.
    weight = 2.0 * ggx_d(h[:, 2], alpha) * g2(mu_o, mu_i, alpha) * sin_i / (4.0 * mu_o)
    values = np.asarray(functions(x), dtype=np.float64)
    if values.ndim == 1:
        values = values[:, None]
    return values * weight[:, None]


def _cubature_over_cuts(integrand, cuts, functions, mu_o, alpha, rtol, atol, accepted_error, g2=g2_reference):
    """Σ over the polar intervals [cuts[k], cuts[k+1]] × φ ∈ [0, π] of adaptive Gauss–Kronrod cubature.

    Raises AssertionError for an interval that neither converges nor estimates its error below ``accepted_error``.
    """
    total = 0.0
    for low, high in zip(cuts[:-1], cuts[1:]):
        result = cubature(
            integrand,
            [low, 0.0],
            [high, np.pi],
            rule="gk21",
            rtol=rtol,
            atol=atol,
            args=(functions, mu_o, alpha, g2),
            max_subdivisions=20000,
        )
        assert result.status == "converged" or np.max(result.error) < accepted_error, (mu_o, alpha, result.error)
        total = total + result.estimate
    return np.atleast_1d(total)


def reference_albedo(
    functions, mu_o, alpha, rtol=1e-11, atol=1e-12, visibility="height-correlated", accepted_error=1e-10
):
    """(K,) F̄_k(μo, α) by adaptive cubature over (θi, φi); ``functions`` maps x (N,) → (N,) or (N, K);
    ``visibility`` picks the G2 form (:data:`G2_FORMS`).

    Raises AssertionError if the cubature neither converges nor estimates its error below ``accepted_error``.
    """
    mu_o, alpha = float(mu_o), float(alpha)
    assert 0.0 < mu_o <= 1.0 and 0.0 < alpha <= 1.0
    theta_o = float(np.arccos(mu_o))
    cuts = [0.0] + ([theta_o] if 1e-9 < theta_o < 0.5 * np.pi - 1e-9 else []) + [0.5 * np.pi]
    return _cubature_over_cuts(
        _integrand, cuts, functions, mu_o, alpha, rtol, atol, accepted_error=accepted_error, g2=G2_FORMS[visibility]
    )


def _half_vector_integrand(points, functions, mu_o, alpha, g2=g2_reference):
    theta_h, phi = points[:, 0], points[:, 1]
    sin_o = np.sqrt(max(1.0 - mu_o * mu_o, 0.0))
    sin_h, mu_h = np.sin(theta_h), np.cos(theta_h)
    x = np.clip(sin_o * sin_h * np.cos(phi) + mu_o * mu_h, 0.0, 1.0)
    mu_i = 2.0 * x * mu_h - mu_o
    # ρ μi dω_i = D G2 / (4 μo μi) μi · 4 x dω_h = D G2 x / μo dω_h; times 2 for the φ symmetry.
    weight = 2.0 * ggx_d(mu_h, alpha) * g2(mu_o, mu_i, alpha) * x / mu_o * sin_h
    values = np.asarray(functions(x), dtype=np.float64)
    if values.ndim == 1:
        values = values[:, None]
    return values * weight[:, None]


def reference_albedo_half_vector(functions, mu_o, alpha, rtol=1e-9, atol=1e-10):
    """(K,) F̄_k by adaptive cubature over the half vector (θh, φh), for any α > 0 including tiny ones.

    Uses dω_i = 4 (ω_o·h) dω_h only (no stretched coordinates, no analytic horizon cut: G2 = 0 below the
    horizon makes a kink that the adaptive rule refines). θh is split at atan(m α), m = 1/4 … 4⁸, so the
    GGX peak and its long tail are resolved; accurate to ~1e-9 for 1e-4 ≲ α ≤ 1 (for α ≲ 1e-5 the peak
    value 1/(πα²) defeats the error estimate). Slower than :func:`reference_albedo` at large α.
    """
    mu_o, alpha = float(mu_o), float(alpha)
    assert 0.0 < mu_o <= 1.0 and 0.0 < alpha <= 1.0
    cuts = sorted({0.0, 0.5 * np.pi, *(float(np.arctan(alpha * 4.0**k)) for k in range(-1, 9))})
    return _cubature_over_cuts(_half_vector_integrand, cuts, functions, mu_o, alpha, rtol, atol, accepted_error=1e-9)


def reference_albedo_adaptive(functions, mu_o, alpha):
    """(K,) F̄_k at one texel by whichever adaptive cubature holds it: over the half vector for α < 0.05, at μo = 0
    its limit (μo = 1e-9, looser tolerances), else over the incident direction."""
    if alpha < 0.05:
        return reference_albedo_half_vector(functions, mu_o, alpha)
    if mu_o == 0.0:
        return reference_albedo(functions, 1e-9, alpha, rtol=1e-8, atol=1e-9, accepted_error=1e-8)
    return reference_albedo(functions, mu_o, alpha, accepted_error=1e-9)


def _graded_nodes(low, high, scale, order):
    """Gauss–Legendre nodes and weights (…, order) on [low, high] graded geometrically from ``low``: d = x − low =
    s (e^{t ln(1 + L/s)} − 1), t ∈ [0, 1], L = high − low, s = ``scale``; a peak of width ≳ s at ``low`` and every
    scale up to L get points in proportion to the logarithm of their size."""
    t, w = np.polynomial.legendre.leggauss(order)
    t, w = 0.5 * (t + 1.0), 0.5 * w
    low, high, scale = (np.asarray(v, dtype=np.float64)[..., None] for v in (low, high, scale))
    span = np.maximum(high - low, 0.0)
    log_range = np.log1p(span / scale)
    grow = np.exp(t * log_range)
    return low + scale * (grow - 1.0), w * scale * log_range * grow


def reference_albedo_grid(functions, mu_o, alpha, order=96, chunk=32):
    """(N, K) F̄_k at N points (μo, α) at once, μo = 0 included (its limit), by fixed-order quadrature over the incident
    direction in spherical coordinates (θi, φi); for checking a whole table texel by texel.

    The integrand ρ μi = D(h) G2 / (4 μo) = D(h) μi / (2 (μi Ro + μo Ri)), R = √(μ² + α² (1 − μ²)) (G2 of
    :func:`g2_reference` with the μo in it cancelled, so μo = 0 is the limit D / (2α)). θi is split at the mirror
    direction θo; each side and φi ∈ [0, π] (even in φi) are graded from the peak (:func:`_graded_nodes`) with the
    scales min(α, μo) in θ and that over sin θ in φ, which resolve the lobe and, for μo ≪ α, the layer of width ~μo
    where G2 falls to 0 at the horizon. Unlike the library's quadrature: no half-vector change of variables, no
    inverse-CDF coordinates, no analytic horizon cut (the horizon is the domain's edge here). Converged to ≲1e-9
    against :func:`reference_albedo` where that converges (tests/preintegrate/test_linear_models.py).
    """
    mu_o, alpha = np.broadcast_arrays(np.asarray(mu_o, dtype=np.float64), np.asarray(alpha, dtype=np.float64))
    mu_o, alpha = mu_o.ravel(), alpha.ravel()
    assert np.all((mu_o >= 0.0) & (mu_o <= 1.0) & (alpha > 0.0) & (alpha <= 1.0))
    results = []
    for start in range(0, mu_o.size, chunk):
        m, a = mu_o[start : start + chunk], alpha[start : start + chunk]  # (n,)
        theta_o = np.arccos(m)
        scale = np.maximum(np.where(m > 0.0, np.minimum(a, m), a), 1e-12)
        m3, a3 = m[:, None, None], a[:, None, None]
        sin_o, r_o = np.sqrt(1.0 - m3 * m3), np.sqrt(m3 * m3 + a3 * a3 * (1.0 - m3 * m3))
        total = 0.0
        for sign, length in ((1.0, 0.5 * np.pi - theta_o), (-1.0, theta_o)):
            distance, w_theta = _graded_nodes(0.0, length, scale, order)  # (n, order)
            theta = (theta_o[:, None] + sign * distance)[..., None]  # (n, order, 1)
            sin_i, mu_i = np.sin(theta), np.cos(theta)
            # at grazing the lobe is narrower across the plane of incidence: ωi_y = 2 (ωo·h) h_y, ωo·h ~ max(μo, α)
            spread = (scale * np.maximum(m, a))[:, None]
            phi_scale = np.clip(spread / np.maximum(sin_i[..., 0], 1e-12), 1e-12, np.pi)
            phi, w_phi = _graded_nodes(0.0, np.pi, phi_scale, order)  # (n, order, order): φi = π − φ
            wi = (-sin_i * np.cos(phi), sin_i * np.sin(phi), mu_i)
            h = (wi[0] + sin_o, wi[1], wi[2] + m3)
            norm = np.sqrt(h[0] ** 2 + h[1] ** 2 + h[2] ** 2)
            mu_h, x = h[2] / norm, np.clip((h[0] * sin_o + h[2] * m3) / norm, 0.0, 1.0)
            r_i = np.sqrt(mu_i * mu_i + a3 * a3 * (1.0 - mu_i * mu_i))
            kernel = ggx_d(mu_h, a3) * mu_i / (2.0 * (mu_i * r_o + m3 * r_i))
            weight = 2.0 * kernel * sin_i * w_phi * w_theta[..., None]
            values = np.asarray(functions(x.reshape(-1)), dtype=np.float64).reshape(x.shape + (-1,))
            total = total + np.einsum("nij,nijk->nk", weight, values)
        results.append(total)
    return np.concatenate(results)
