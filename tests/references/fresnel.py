"""Exact Fresnel reflectance, typed independently of basis.fresnel: the textbook complex-amplitude form
(n = η + iκ, cos_t = √(1 − sin²θ/n²), r_s = (μ − n cos_t)/(μ + n cos_t), r_p = (n μ − cos_t)/(n μ + cos_t),
F = (|r_s|² + |r_p|²)/2), in float64 complex arithmetic and in 60-digit decimal arithmetic. The library uses
the real a²/b² form of Hoffman 2020, so agreement is a genuine cross-check."""

from decimal import Decimal, localcontext

import numpy as np


def complex_amplitudes(mu, eta, kappa):
    """r_s, r_p and n cos_t, cos_t of the complex-amplitude form (independent of the library)."""
    mu, eta, kappa = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (mu, eta, kappa)))
    n = eta + 1j * kappa
    sin2 = 1.0 - mu * mu
    with np.errstate(divide="ignore", invalid="ignore"):
        cos_t = np.sqrt(1.0 - sin2 / (n * n) + 0j)
        r_s = (mu - n * cos_t) / (mu + n * cos_t)
        r_p = (n * mu - cos_t) / (n * mu + cos_t)
    return r_s, r_p, n * cos_t, cos_t


def fresnel_complex(mu, eta, kappa):
    """Unpolarised F = (|r_s|^2 + |r_p|^2) / 2 from complex arithmetic."""
    r_s, r_p, _, _ = complex_amplitudes(mu, eta, kappa)
    return 0.5 * (np.abs(r_s) ** 2 + np.abs(r_p) ** 2)


def one_minus_fresnel_complex(mu, eta, kappa):
    """1 - F without cancellation: 1 - |(a-b)/(a+b)|^2 = 4 Re(a conj b) / |a+b|^2, per polarisation."""
    mu, eta, kappa = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (mu, eta, kappa)))
    _, _, n_cos_t, cos_t = complex_amplitudes(mu, eta, kappa)
    n = eta + 1j * kappa
    t_s = 4.0 * np.real(mu * np.conj(n_cos_t)) / np.abs(mu + n_cos_t) ** 2
    t_p = 4.0 * np.real(n * mu * np.conj(cos_t)) / np.abs(n * mu + cos_t) ** 2
    return 0.5 * (t_s + t_p)


def fresnel_decimal(mu, eta, kappa, digits=60):
    """The complex-amplitude form evaluated in 60-digit decimal arithmetic (ground truth for ill-conditioned corners)."""
    with localcontext() as context:
        context.prec = digits
        mu, eta, kappa = (Decimal(float(x)) for x in (mu, eta, kappa))

        def csqrt(x, y):
            modulus = (x * x + y * y).sqrt()
            re, im = ((modulus + x) / 2).sqrt(), ((modulus - x) / 2).sqrt()
            return re, (im if y >= 0 else -im)

        def cdiv(a, b, c, d):
            den = c * c + d * d
            return (a * c + b * d) / den, (b * c - a * d) / den

        # n cos_t = sqrt(n^2 - sin^2), principal branch (decaying transmitted wave).
        nc = csqrt(eta * eta - kappa * kappa - (1 - mu * mu), 2 * eta * kappa)
        r_s = cdiv(mu - nc[0], -nc[1], mu + nc[0], nc[1])
        ct = cdiv(nc[0], nc[1], eta, kappa)
        r_p = cdiv(eta * mu - ct[0], kappa * mu - ct[1], eta * mu + ct[0], kappa * mu + ct[1])
        return float((r_s[0] ** 2 + r_s[1] ** 2 + r_p[0] ** 2 + r_p[1] ** 2) / 2)


def normal_incidence(eta, kappa):
    """Closed-form F(theta = 0) = ((eta - 1)^2 + kappa^2) / ((eta + 1)^2 + kappa^2)."""
    eta, kappa = np.asarray(eta, dtype=np.float64), np.asarray(kappa, dtype=np.float64)
    return ((eta - 1.0) ** 2 + kappa**2) / ((eta + 1.0) ** 2 + kappa**2)
