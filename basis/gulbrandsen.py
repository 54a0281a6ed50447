"""Gulbrandsen's artist-friendly metallic Fresnel parameters: reflectivity r and edge tint g.

Public objects: ``gulbrandsen_to_nk``, ``nk_to_gulbrandsen``.

References
----------
:cite:`Gulbrandsen2014` O. Gulbrandsen, "Artist Friendly Metallic Fresnel", Journal of Computer
    Graphics Techniques 3(4), 2014, equations 7–9 (n_min, n_max, n(r, g), k(r, n)) and their inverse.
"""

from __future__ import annotations

import numpy as np

from .fresnel import ETA_RANGE, KAPPA_RANGE, fresnel_normal_incidence
from .validation import check_broadcast, check_range

__all__ = ["gulbrandsen_to_nk", "nk_to_gulbrandsen"]


def _n_bounds(reflectivity: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """n_min = (1 − r)/(1 + r) (g = 1) and n_max = (1 + √r)/(1 − √r) (g = 0, a dielectric)."""
    root = np.sqrt(reflectivity)
    return (1.0 - reflectivity) / (1.0 + reflectivity), (1.0 + root) / (1.0 - root)


def gulbrandsen_to_nk(reflectivity, edge_tint) -> tuple[np.ndarray, np.ndarray]:
    """Map Gulbrandsen's (r, g) to the complex IOR (η, κ) whose Fresnel curve has F(0) = r.

    Parameters
    ----------
    reflectivity : array_like
        Normal-incidence reflectance r, in [0, 1).
    edge_tint : array_like
        Edge tint g, in [0, 1]; 0 gives the dielectric with F0 = r, 1 the lowest η for that r.

    Returns
    -------
    (eta, kappa) : tuple of numpy.ndarray
        Broadcast shape of the inputs.

    Notes
    -----
    Gulbrandsen 2014, eq. 7–9: n = g n_min + (1 − g) n_max,
    k = √((r (n + 1)² − (n − 1)²) / (1 − r)). η grows without bound as r → 1 with g = 0
    (η ≈ 4/(1 − r)), so r is capped below 1.

    Examples
    --------
    >>> eta, kappa = gulbrandsen_to_nk(0.04, 0.0)
    >>> round(float(eta), 6), round(float(kappa), 6)  # κ² is 0 up to rounding: κ ~ 1e-8
    (1.5, 0.0)
    """
    reflectivity = check_range("reflectivity", reflectivity, 0.0, 1.0, high_open=True)
    edge_tint = check_range("edge_tint", edge_tint, 0.0, 1.0)
    check_broadcast(reflectivity=reflectivity, edge_tint=edge_tint)
    n_min, n_max = _n_bounds(reflectivity)
    eta = edge_tint * n_min + (1.0 - edge_tint) * n_max
    kappa2 = (reflectivity * (eta + 1.0) ** 2 - (eta - 1.0) ** 2) / (1.0 - reflectivity)
    kappa = np.sqrt(np.maximum(kappa2, 0.0))  # ≈ 0 at g = 0, where rounding can leave κ² < 0
    return eta, kappa


def nk_to_gulbrandsen(eta, kappa) -> tuple[np.ndarray, np.ndarray]:
    """Map a complex IOR (η, κ) to Gulbrandsen's (r, g); the inverse of :func:`gulbrandsen_to_nk`.

    Parameters
    ----------
    eta : array_like
        In [1e-8, 1e6].
    kappa : array_like
        In [0, 1e6].

    Returns
    -------
    (reflectivity, edge_tint) : tuple of numpy.ndarray
        r = ((η − 1)² + κ²)/((η + 1)² + κ²) and g = (n_max − η)/(n_max − n_min) (Gulbrandsen 2014,
        inverse of eq. 7–9). g lies in [0, 1] only inside Gulbrandsen's gamut; outside it
        (e.g. η < n_min) g > 1 is returned as is. For r = 0 (η = 1, κ = 0) every g is the same
        material and 0 is returned.
    """
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    check_broadcast(eta=eta, kappa=kappa)
    reflectivity = fresnel_normal_incidence(eta, kappa)
    reflectivity = np.minimum(reflectivity, np.nextafter(1.0, 0.0))
    n_min, n_max = _n_bounds(reflectivity)
    span = n_max - n_min
    with np.errstate(divide="ignore", invalid="ignore"):
        edge_tint = np.where(span > 0.0, (n_max - eta) / np.where(span > 0.0, span, 1.0), 0.0)
    return reflectivity, edge_tint
