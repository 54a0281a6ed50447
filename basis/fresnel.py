"""Exact Fresnel reflectance of a planar interface, unpolarised, for a complex IOR η + iκ.

Public objects: ``fresnel_conductor``, ``fresnel_dielectric``, ``cos_theta``, ``ETA_RANGE``, ``KAPPA_RANGE``.

The incident medium has index 1 (divide η and κ by an external medium's index to change it).
Dielectrics are κ = 0; η < 1 is internal reflection and gives F = 1 past the critical angle.

References
----------
:cite:`Hoffman2020` N. Hoffman, "Fresnel Equations Considered Harmful" / "Thoughts on Fresnel",
    SIGGRAPH 2020 Physically Based Shading course, slide "1823: Fresnel's Equations" (F = (Fs + Fp)/2,
    Fs, Fp and the a², b² auxiliaries).
"""

from __future__ import annotations

import numpy as np

from .validation import check_range

__all__ = ["ETA_RANGE", "KAPPA_RANGE", "cos_theta", "fresnel_conductor", "fresnel_dielectric"]

#: Accepted η: [1e-8, 1e6] keeps every square and product of squares normal in float64 (below
#: ~1e-81 they underflow and the formula degenerates); no material has η ≤ 0.
ETA_RANGE = (1e-8, 1e6)
#: Accepted κ.
KAPPA_RANGE = (0.0, 1e6)


def cos_theta(theta) -> np.ndarray:
    """μ = cos θ with cos(π/2) exactly 0 (floating point gives 6e-17, which is not grazing)."""
    mu = np.cos(np.asarray(theta, dtype=np.float64))
    return np.where(np.asarray(theta) == 0.5 * np.pi, 0.0, mu)


def _fresnel(mu: np.ndarray, eta: np.ndarray, kappa: np.ndarray) -> np.ndarray:
    """Unchecked kernel of :func:`fresnel_conductor` (inputs already validated and broadcastable)."""
    mu2 = mu * mu
    sin2 = 1.0 - mu2
    # η² − κ² − sin²θ without avoidable cancellation: near η = 1 as (η − 1)(η + 1) + μ² − κ² (else
    # grazing angles lose digits), elsewhere as η² − κ² − (1 − μ)(1 + μ) (else small η at μ ≈ 1 does).
    t = np.where(
        np.abs(eta - 1.0) < 0.5,
        (eta - 1.0) * (eta + 1.0) + mu2 - kappa * kappa,
        eta * eta - kappa * kappa - (1.0 - mu) * (1.0 + mu),
    )
    four_eta2_kappa2 = 4.0 * (eta * kappa) ** 2
    s = np.sqrt(t * t + four_eta2_kappa2)  # a² + b²
    # 2a² = s + t loses every digit when t ≪ 0 (large κ); use (s + t)(s − t) = 4η²κ² there.
    with np.errstate(divide="ignore", invalid="ignore"):
        two_a2 = np.where(t >= 0.0, s + t, four_eta2_kappa2 / (s - t))
    two_a2 = np.where(np.isfinite(two_a2), two_a2, 0.0)
    a = np.sqrt(0.5 * two_a2)
    # Fs, and Fp / Fs with numerator and denominator multiplied by μ² so θ = π/2 needs no tan.
    fs_num = s - 2.0 * a * mu + mu2
    fs_den = s + 2.0 * a * mu + mu2
    ratio_num = s * mu2 - 2.0 * a * sin2 * mu + sin2 * sin2
    ratio_den = s * mu2 + 2.0 * a * sin2 * mu + sin2 * sin2
    # Both denominators vanish only for η = 1, κ = 0 at μ = 0: no interface, so no reflection.
    degenerate = (fs_den <= 0.0) | (ratio_den <= 0.0)
    with np.errstate(divide="ignore", invalid="ignore"):
        fs = np.where(degenerate, 0.0, fs_num / np.where(degenerate, 1.0, fs_den))
        ratio = np.where(degenerate, 0.0, ratio_num / np.where(degenerate, 1.0, ratio_den))
    return np.clip(0.5 * fs * (1.0 + ratio), 0.0, 1.0)


def fresnel_conductor(mu, eta, kappa) -> np.ndarray:
    """Unpolarised Fresnel reflectance F(μ) for the complex IOR η + iκ.

    Parameters
    ----------
    mu : array_like
        Cosine of the angle of incidence, in [0, 1].
    eta : array_like
        Real part of the relative IOR, in [1e-8, 1e6].
    kappa : array_like
        Extinction coefficient, in [0, 1e6].

    Returns
    -------
    numpy.ndarray
        Reflectance in [0, 1], float64, with the broadcast shape of the inputs.

    Notes
    -----
    Hoffman 2020, slide "1823: Fresnel's Equations":
    Fs = (a² + b² − 2a cos θ + cos²θ) / (a² + b² + 2a cos θ + cos²θ),
    Fp = Fs (a² + b² − 2a sin θ tan θ + sin²θ tan²θ) / (a² + b² + 2a sin θ tan θ + sin²θ tan²θ),
    2a² = √((η² − κ² − sin²θ)² + 4η²κ²) + (η² − κ² − sin²θ), a² + b² = √(…).
    Fp is evaluated multiplied through by cos²θ so that θ = π/2 is exact, and 2a² through
    4η²κ² / (a² + b² − (η² − κ² − sin²θ)) when that difference would cancel (κ ≫ η).

    Examples
    --------
    >>> float(fresnel_conductor(1.0, 1.5, 0.0))  # doctest: +ELLIPSIS
    0.04000...
    """
    mu = check_range("mu", mu, 0.0, 1.0)
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    return _fresnel(mu, eta, kappa)


def fresnel_dielectric(mu, eta) -> np.ndarray:
    """Unpolarised Fresnel reflectance of a dielectric (κ = 0); η < 1 gives total internal reflection.

    Parameters
    ----------
    mu : array_like
        Cosine of the angle of incidence, in [0, 1].
    eta : array_like
        Relative IOR (transmitted over incident medium), in [1e-8, 1e6].

    Examples
    --------
    >>> float(fresnel_dielectric(0.1, 1.0 / 1.5))  # past the critical angle
    1.0
    """
    return fresnel_conductor(mu, eta, 0.0)
