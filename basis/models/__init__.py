"""Approximate Fresnel models: every model of the references in one registry, and their formulas.

Public objects: ``FRESNEL_MODELS``, ``fresnel_model``, ``FresnelModel``, ``Parameter``, ``LinearTerms``
(:mod:`basis.models.registry`); ``fresnel_Schlick1994``, ``fresnel_Hoffman2019``, ``F82_MU``,
``schlick_external_f0``, ``metal_external_f0`` and the unchecked kernels (:mod:`basis.models.formulas`).

==========================  ============================================================  ===========
name                        F(μ)                                                          channels
==========================  ============================================================  ===========
``schlick``                 F0 + (1 − F0)(1 − μ)^5 (Schlick 1994, eq. 15)                   2
``generalized-schlick``     r0 + (r90 − r0)(1 − μ)^p (Hoffman 2023, eq. 4; GLSL tutorial)   2 per p
``lazanyi``                 F0 + (1 − F0)(1 − μ)^5 − a μ (1 − μ)^α (Hoffman 2023, eq. 2)    3 per α
``f82``                     Lazányi with α = 6, a from F82 (Hoffman 2020, "2019: Reparam.") 3
``adobe``                   Lazányi with α = 6, a from the tint t (Hoffman 2023, eq. 3)     3
``generalized-adobe``       r0 + (r90 − r0)(1 − μ)^p − a μ (1 − μ)^6 (Hoffman 2023, 5–6)    3 per p
``cook-torrance``           F0 + (1 − F0) max(0, F′ − F′(1))/(1 − F′(1)) (Hoffman 2020)     2 per η′, κ′
``schlick-external``        Schlick with F0 adjusted for an external medium η_E            2
``schlick-external-metal``  Schlick with Hoffman's metal variant of the adjustment         2
``exact-external``          Fresnel equations of (η/η_E, κ/η_E) (Hoffman 2020)              –
``gulbrandsen``             Fresnel equations of Gulbrandsen's (r, g) (JCGT 2014)           –
``fresnel-blend``           pbrt's FresnelBlend specular Fresnel: Schlick with Rs           2
==========================  ============================================================  ===========

References
----------
:cite:`Schlick1994` Computer Graphics Forum 13(3), eq. 15.
:cite:`Lazanyi2005` I. Lazányi, L. Szirmay-Kalos, "Fresnel term approximations for metals", WSCG 2005.
:cite:`Hoffman2020` SIGGRAPH 2020 course notes: "2019: Reparameterized Lazányi", the corrected
    Cook–Torrance interpolation, "External Media Adjustment".
:cite:`Hoffman2023` N. Hoffman, "Generalization of Adobe's Fresnel Model", 2023, eq. 1–6.
:cite:`Kutz2021` P. Kutz, M. Hašan, P. Edmondson, "Novel aspects of the Adobe Standard Material", 2021.
:cite:`Pharr2016` pbrt 3rd ed., section 8.5 "Fresnel Incidence Effects" (FresnelBlend).
"""

from .formulas import (
    F82_MU,
    fresnel_Hoffman2019,
    fresnel_Schlick1994,
    metal_external_f0,
    schlick_external_f0,
)
from .registry import FRESNEL_MODELS, FresnelModel, LinearTerms, Parameter, fresnel_model

__all__ = [
    "F82_MU",
    "FRESNEL_MODELS",
    "FresnelModel",
    "LinearTerms",
    "Parameter",
    "fresnel_Hoffman2019",
    "fresnel_Schlick1994",
    "fresnel_model",
    "metal_external_f0",
    "schlick_external_f0",
]
