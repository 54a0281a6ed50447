"""The formulas of the approximate Fresnel models, each written once; μ = cos θ throughout.

Public objects: ``schlick_weight``, ``schlick_curve``, ``fresnel_Schlick1994``, ``lazanyi_dip``,
``lazanyi_curve``, ``F82_MU``, ``f82_dip_weight``, ``hoffman2019_curve``, ``fresnel_Hoffman2019``,
``adobe_dip_weight``, ``schlick_external_f0``, ``metal_external_f0``, ``ETA_E_RANGE``.

The lower-case kernels (``schlick_curve``, ``hoffman2019_curve``, …) trust their inputs (an RGB F0 out
of gamut may pass 1, as the references allow); the ``fresnel_AuthorYear`` functions validate them.

References
----------
:cite:`Schlick1994` C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer
    Graphics Forum 13(3), 1994, eq. 15.
:cite:`Lazanyi2005` I. Lazányi, L. Szirmay-Kalos, "Fresnel term approximations for metals", WSCG 2005.
:cite:`Hoffman2020` SIGGRAPH 2020 course notes: "2019: Reparameterized Lazányi", "External Media
    Adjustment".
:cite:`Hoffman2023` N. Hoffman, "Generalization of Adobe's Fresnel Model", 2023, eq. 1–6.
"""

from __future__ import annotations

import numpy as np

from ..validation import check_range

__all__ = [
    "ETA_E_RANGE",
    "F82_MU",
    "adobe_dip_weight",
    "f82_dip_weight",
    "fresnel_Hoffman2019",
    "fresnel_Schlick1994",
    "hoffman2019_curve",
    "lazanyi_curve",
    "lazanyi_dip",
    "metal_external_f0",
    "schlick_curve",
    "schlick_external_f0",
    "schlick_weight",
]

#: θ of Hoffman's F82 parameter and of the Lazányi term's extremum with β = 6: "approximately 82
#: degrees: to be precise, arccos(1/7)" (Hoffman 2020; Hoffman 2023, note 1).
F82_MU = 1.0 / 7.0
#: Accepted index of an external medium.
ETA_E_RANGE = (1.0, 10.0)


def schlick_weight(mu, exponent=5.0):
    """(1 − μ)^p, the weight of F90 in Schlick's approximation (Schlick 1994, eq. 15; p = 5)."""
    return (1.0 - mu) ** exponent


def schlick_curve(mu, f0, f90=1.0, exponent=5.0):
    """F0 + (F90 − F0)(1 − μ)^p: Schlick 1994, eq. 15 (F90 = 1, p = 5) and Hoffman 2023, eq. 4."""
    return f0 + (f90 - f0) * schlick_weight(mu, exponent)


def lazanyi_dip(mu, exponent=6.0):
    """μ (1 − μ)^α, the dip term of Lazányi and Szirmay-Kalos 2005 (Hoffman 2023, eq. 2; α = 6)."""
    return mu * (1.0 - mu) ** exponent


def lazanyi_curve(mu, f0, a, exponent=6.0):
    """F0 + (1 − F0)(1 − μ)^5 − a μ (1 − μ)^α (Hoffman 2023, eq. 2), unclamped."""
    return schlick_curve(mu, f0) - a * lazanyi_dip(mu, exponent)


def f82_dip_weight(f0, f82):
    """a = 823543/46656 (F0 − F82) + 49/6 (1 − F0), so that the Lazányi curve with α = 6 passes through
    F82 at arccos(1/7) (Hoffman 2020, "2019: Reparameterized Lazányi")."""
    return 823543.0 / 46656.0 * (f0 - f82) + 49.0 / 6.0 * (1.0 - f0)


def hoffman2019_curve(mu, f0, f82):
    """Hoffman's F82 model, unclamped and unchecked (RGB values out of gamut may pass 1)."""
    return lazanyi_curve(mu, f0, f82_dip_weight(f0, f82))


def adobe_dip_weight(r0, tint, r90=1.0, exponent=5.0):
    """a of the Adobe model from the tint t at arccos(1/7): a = S(θ_max)(1 − t) / (μ (1 − μ)^6)|θ_max, with
    S the (generalized) Schlick curve (Hoffman 2023, eq. 3; eq. 6 with r90 and p)."""
    return schlick_curve(F82_MU, r0, r90, exponent) * (1.0 - tint) / lazanyi_dip(F82_MU)


def fresnel_Schlick1994(mu, f0) -> np.ndarray:
    """Schlick's approximation F = F0 + (1 − F0)(1 − μ)^5 (Schlick 1994, eq. 15).

    Parameters
    ----------
    mu : array_like
        Cosine of the angle of incidence, in [0, 1].
    f0 : array_like
        Reflectance at normal incidence, in [0, 1]; broadcast against ``mu``.

    Examples
    --------
    >>> float(fresnel_Schlick1994(0.0, 0.04))
    1.0
    """
    return schlick_curve(check_range("mu", mu, 0.0, 1.0), check_range("f0", f0, 0.0, 1.0))


def fresnel_Hoffman2019(mu, f0, f82) -> np.ndarray:
    """Hoffman's reparameterised Lazányi model with F82, clamped to [0, 1] (Hoffman 2020, "2019:
    Reparameterized Lazányi").

    F = F0 + (1 − F0)(1 − μ)^5 − a μ (1 − μ)^6,  a = 823543/46656 (F0 − F82) + 49/6 (1 − F0),

    so that F(arccos 1/7) = F82. Extreme (F0, F82) pairs leave [0, 1]; the result is clamped there, as
    Hoffman warns (a C1 kink).

    Parameters
    ----------
    mu : array_like
        Cosine of the angle of incidence, in [0, 1].
    f0, f82 : array_like
        Reflectance at normal incidence and at arccos(1/7) ≈ 81.8°, in [0, 1]; broadcast.

    Examples
    --------
    >>> round(float(fresnel_Hoffman2019(1.0 / 7.0, 0.9, 0.8)), 12)
    0.8
    """
    mu = check_range("mu", mu, 0.0, 1.0)
    f0 = check_range("f0", f0, 0.0, 1.0)
    f82 = check_range("f82", f82, 0.0, 1.0)
    return np.clip(hoffman2019_curve(mu, f0, f82), 0.0, 1.0)


def _external_root(eta_external) -> np.ndarray:
    eta_external = check_range("eta_e", eta_external, *ETA_E_RANGE)
    return (eta_external - 1.0) / (eta_external + 1.0)


def schlick_external_f0(f0, eta_external) -> np.ndarray:
    """F0 seen from an external medium of index η_E (Hoffman 2020, "External Media Adjustment"):

    F0′ = ((√F0 − √F0E) / (1 − √F0 √F0E))²,  √F0E = (η_E − 1)/(η_E + 1). Exact for dielectrics.
    """
    f0 = check_range("f0", f0, 0.0, 1.0)
    root_e = _external_root(eta_external)
    root = np.sqrt(f0)
    return ((root - root_e) / (1.0 - root * root_e)) ** 2


def metal_external_f0(f0, eta_external) -> np.ndarray:
    """Hoffman 2020's asymmetric variant for metals in high-index media:

    F0′ = (√F0 − √F0E)² if F0 < F0E, else ((√F0 − √F0E) / (1 − √F0E))².
    """
    f0 = check_range("f0", f0, 0.0, 1.0)
    root_e = _external_root(eta_external)
    root = np.sqrt(f0)
    return np.where(root < root_e, (root - root_e) ** 2, ((root - root_e) / (1.0 - root_e)) ** 2)
