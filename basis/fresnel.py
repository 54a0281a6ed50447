"""Exact Fresnel reflectance of a planar interface, unpolarised, for a complex IOR η + iκ.

Public objects: ``fresnel_conductor``, ``fresnel_dielectric``, ``fresnel_kernel``, ``fresnel_normal_incidence``,
``ETA_RANGE``, ``KAPPA_RANGE``.

``fresnel_kernel`` is the same formula without validation, for callers whose inputs are already checked
(the training set, the integrators' nodes).

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

from .validation import check_broadcast, check_range

__all__ = [
    "ETA_RANGE",
    "KAPPA_RANGE",
    "fresnel_conductor",
    "fresnel_dielectric",
    "fresnel_kernel",
    "fresnel_normal_incidence",
]

#: Accepted η: [1e-8, 1e6] keeps every square and product of squares normal in float64 (below
#: ~1e-81 they underflow and the formula degenerates); no material has η ≤ 0.
ETA_RANGE = (1e-8, 1e6)
#: Accepted κ.
KAPPA_RANGE = (0.0, 1e6)


def fresnel_kernel(mu, eta, kappa) -> np.ndarray:
    """:func:`fresnel_conductor` without validation: μ in [0, 1], η, κ in range and broadcastable.

    Terms that depend on the material alone or on the angle alone are formed on their own (small)
    shapes; the full broadcast shape is touched by about thirty in-place passes, which is what a training
    set of 10^6 curves × 512 angles costs.
    """
    shape = np.broadcast_shapes(np.shape(mu), np.shape(eta), np.shape(kappa))
    mu, eta, kappa = np.atleast_1d(mu, eta, kappa)  # in-place passes need arrays, not 0-d scalars
    mu2 = mu * mu
    sin2 = (1.0 - mu) * (1.0 + mu)
    # η² − κ² − sin²θ without avoidable cancellation: near η = 1 as (η − 1)(η + 1) − κ² + μ² (else
    # grazing angles lose digits), elsewhere as η² − κ² − (1 − μ)(1 + μ) (else small η at μ ≈ 1 does).
    near_one = np.abs(eta - 1.0) < 0.5
    t = np.where(near_one, (eta - 1.0) * (eta + 1.0), eta * eta) - kappa * kappa
    t = t + np.where(near_one, mu2, -sin2)
    four_eta2_kappa2 = 4.0 * (eta * kappa) ** 2
    s = t * t
    s += four_eta2_kappa2
    np.sqrt(s, out=s)  # a² + b²
    # 2a² = s + t loses every digit when t ≪ 0 (large κ); there it is 4η²κ² / (s − t) = 4η²κ² / (s + |t|).
    u = np.abs(t)
    u += s
    with np.errstate(divide="ignore", invalid="ignore"):
        two_a = np.where(t >= 0.0, u, four_eta2_kappa2 / u)
    np.nan_to_num(two_a, copy=False, nan=0.0, posinf=0.0)
    two_a *= 0.5
    np.sqrt(two_a, out=two_a)
    two_a *= 2.0 * mu  # now 2aμ
    # Fs = (s − 2aμ + μ²)/(s + 2aμ + μ²); Fp/Fs = (sμ² − 2aμ sin²θ + sin⁴θ)/(sμ² + 2aμ sin²θ + sin⁴θ), i.e.
    # Hoffman's ratio multiplied through by μ² so that θ = π/2 needs no tan.
    q = s + mu2
    fs_den = q + two_a
    q -= two_a
    r = s * mu2
    r += sin2 * sin2
    two_a *= sin2
    ratio_den = r + two_a
    r -= two_a
    # fs_den vanishes only at μ = 0 when a² + b² is 0 or underflows (η = 1 with κ = 0 or κ < 1e-154):
    # every real interface reflects fully at grazing, the index-matched η = 1, κ = 0 not at all.
    grazing_value = np.where((eta == 1.0) & (kappa == 0.0), 0.0, 1.0)
    fs = np.divide(q, fs_den, out=np.broadcast_to(grazing_value, q.shape).copy(), where=fs_den > 0.0)
    ratio = np.divide(r, ratio_den, out=np.ones_like(r), where=ratio_den > 0.0)
    ratio += 1.0
    fs *= ratio
    fs *= 0.5
    return np.clip(fs, 0.0, 1.0, out=fs).reshape(shape)


def fresnel_normal_incidence(eta, kappa) -> np.ndarray:
    """F(θ = 0) = ((η − 1)² + κ²) / ((η + 1)² + κ²), the closed form at normal incidence; unchecked."""
    return ((eta - 1.0) ** 2 + kappa**2) / ((eta + 1.0) ** 2 + kappa**2)


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
    >>> round(float(fresnel_conductor(1.0, 1.5, 0.0)), 12)  # ((1.5 - 1) / (1.5 + 1))^2
    0.04
    """
    mu = check_range("mu", mu, 0.0, 1.0)
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    check_broadcast(mu=mu, eta=eta, kappa=kappa)
    return fresnel_kernel(mu, eta, kappa)


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
