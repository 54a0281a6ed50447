"""Published tables the project measures itself against, as data: Hoffman 2020's ΔE2000 columns.

Public objects: ``HOFFMAN_SCHLICK``, ``HOFFMAN_FITTED``, ``HOFFMAN_BLENDING``, ``HOFFMAN_GAMUT``.

References
----------
:cite:`Hoffman2020` N. Hoffman, "Fresnel Equations Considered Harmful" / "Thoughts on Fresnel", SIGGRAPH
    2020 Physically Based Shading course: the tables of RMS ΔE2000 over incidence angle (ACEScg),
    "Parameter Blending" and "Color Gamut Conversion".
"""

__all__ = ["HOFFMAN_BLENDING", "HOFFMAN_FITTED", "HOFFMAN_GAMUT", "HOFFMAN_SCHLICK"]

#: Hoffman 2020, Schlick RMS ΔE2000 (ACEScg) per material.
HOFFMAN_SCHLICK = {
    "Silver": 0.27,
    "Copper": 0.69,
    "Gold": 0.69,
    "Bronze": 0.78,
    "Brass": 1.04,
    "Aluminum": 1.12,
    "Palladium": 1.70,
    "Nickel": 1.82,
    "Titanium": 1.87,
    "Mercury": 1.89,
    "Platinum": 2.08,
    "Iron": 2.42,
    "Zinc": 2.44,
    "Chromium": 2.90,
    "Diamond": 1.18547,
    "Cubic Zirconia": 1.20586,
    "Moissanite": 1.40412,
    "Water": 1.46765,
    "Glass SF66": 1.49880,
    "Acrylic": 1.56734,
    "Glass BK7": 1.60457,
    "Glass SF11": 1.64151,
    "Quartz": 1.64646,
    "Ruby": 1.66026,
    "Glass F5": 1.67466,
    "Polycarbonate": 1.67845,
    "Tourmaline": 1.69488,
    "PET": 1.70027,
}
#: Hoffman 2020, "Fitted η, κ" column: exact Fresnel with numerically fitted RGB parameters.
HOFFMAN_FITTED = {
    "Silver": 0.02,
    "Copper": 0.03,
    "Gold": 0.05,
    "Bronze": 0.02,
    "Brass": 0.04,
    "Aluminum": 0.01,
    "Palladium": 0.02,
    "Nickel": 0.02,
    "Titanium": 0.01,
    "Mercury": 0.02,
    "Platinum": 0.02,
    "Iron": 0.01,
    "Zinc": 0.08,
    "Chromium": 0.02,
}
#: Hoffman 2020, "Parameter Blending": ΔE2000 of blending (F0, g) 50/50 instead of the curves.
HOFFMAN_BLENDING = {
    ("Gold", "Chromium"): 2.42,
    ("Gold", "Iron"): 2.15,
    ("Copper", "Chromium"): 2.02,
    ("Gold", "Zinc"): 1.96,
    ("Brass", "Chromium"): 1.95,
    ("Bronze", "Chromium"): 1.94,
    ("Copper", "Iron"): 1.94,
    ("Gold", "Titanium"): 1.83,
    ("Bronze", "Iron"): 1.78,
    ("Copper", "Titanium"): 1.77,
    ("Brass", "Iron"): 1.72,
    ("Zinc", "Copper"): 1.68,
    ("Zinc", "Bronze"): 1.66,
    ("Silver", "Gold"): 1.57,
    ("Silver", "Chromium"): 1.45,
    ("Aluminum", "Gold"): 1.47,
    ("Gold", "Platinum"): 1.47,
    ("Bronze", "Titanium"): 1.49,
    ("Copper", "Platinum"): 1.42,
    ("Zinc", "Chromium"): 1.40,
}
#: Hoffman 2020, "Color Gamut Conversion": ΔE2000 of converting (F0, g) ACEScg → Rec.709 / AP0.
HOFFMAN_GAMUT = {
    "Silver": (0.17, 0.02),
    "Copper": (0.59, 0.83),
    "Gold": (0.44, 1.46),
    "Bronze": (1.38, 0.79),
    "Brass": (1.89, 0.54),
    "Aluminum": (0.08, 0.04),
    "Palladium": (0.04, 0.02),
    "Nickel": (0.07, 0.03),
    "Titanium": (0.05, 0.02),
    "Mercury": (0.11, 0.05),
    "Platinum": (0.05, 0.03),
    "Iron": (0.06, 0.02),
    "Zinc": (0.74, 0.39),
    "Chromium": (0.06, 0.03),
}
