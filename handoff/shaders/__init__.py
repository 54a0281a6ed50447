"""Shader-side Fresnel generated from one basis: the include of a build (per-pixel coefficients, the split sums, the
direct-light curves, rectangular lights, the tables' coordinates), its constants and the Python mirrors of its
arithmetic.

Public objects: ``ShaderConstants``, ``shader_constants``, ``SHADER_INCLUDES``, ``INCLUDE_STEM``, ``ATLAS_INCLUDE_STEM``,
``shader_includes``,
``shader_source``, ``translate``, ``LANGUAGES``, ``sanitize_nk``, ``sanitize_gulbrandsen``, ``sanitize_unit``, ``bits_clamp``,
``coefficients_per_pixel_nk``, ``coefficients_per_pixel_gulbrandsen``, ``coefficients_per_pixel_gulbrandsen_table``,
``coefficients_per_pixel_nk_table``, ``coefficients_per_pixel_model``,
``direct_fresnel``, ``direct_fresnel_table``, ``lut_coordinates``, ``ltc_coordinates``, ``rect_light_specular``, ``rect_light_punctual``, ``linear_rect_light_specular``, ``linear_model_curve``,
``linear_weights``, ``linear_split_sum``, ``linear_direct``,
``warped_cosine``, ``unwarped_cosine``, ``PER_PIXEL_MODELS``, ``CURVE_WARPS``, ``CURVE_SEGMENTS``,
``FINE_CURVE_SEGMENTS``, ``CURVE_TOLERANCE``.

Everything a shader needs to turn a texel's material parameters into the K coefficients of the basis, and the
coefficients into F(V·H) for a punctual light, depends on the basis alone (:mod:`.constants`); how the tables are
addressed depends on their grid. :func:`shader_includes` writes both into one self-contained include per language
(GLSL 3.30/4.50/ES 3.00, HLSL, WGSL), which every build writes beside its tables, so coefficients and tables cannot
come from different bases (the include states the basis hash, and so does every table header). Every function is
written once, in the GLSL of ``source/`` and the statements :mod:`.include` generates, and printed in each language
by :mod:`.translate` (MaterialX's way: one GLSL body per function, the other targets a spelling of it; chosen over an
expression tree in Python, which would make the bodies Python code that shader writers do not read). :mod:`.mirrors`
computes the same numbers in float64.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4-5 and "Coefficients". :cite:`Hoffman2020` "Fresnel Equations
Considered Harmful". :cite:`Gulbrandsen2014` JCGT 3(4), eq. 7-9. :cite:`Hoffman2019` eq. 4.
:cite:`Hoffman2023` "Generalization of Adobe's Fresnel Model", eq. 3 and 6. :cite:`Heitz2016` "Real-Time
Polygonal-Light Shading with Linearly Transformed Cosines", eq. 11.
"""

from .constants import (
    CURVE_SEGMENTS,
    CURVE_TOLERANCE,
    CURVE_WARPS,
    FINE_CURVE_SEGMENTS,
    PER_PIXEL_MODELS,
    ShaderConstants,
    shader_constants,
    unwarped_cosine,
    warped_cosine,
)
from .include import ATLAS_INCLUDE_STEM, INCLUDE_STEM, SHADER_INCLUDES, shader_includes, shader_source
from .mirrors import (
    bits_clamp,
    coefficients_per_pixel_gulbrandsen,
    coefficients_per_pixel_gulbrandsen_table,
    coefficients_per_pixel_model,
    coefficients_per_pixel_nk,
    coefficients_per_pixel_nk_table,
    direct_fresnel,
    direct_fresnel_table,
    linear_direct,
    linear_model_curve,
    linear_rect_light_specular,
    linear_split_sum,
    linear_weights,
    ltc_coordinates,
    lut_coordinates,
    rect_light_punctual,
    rect_light_specular,
    sanitize_gulbrandsen,
    sanitize_nk,
    sanitize_unit,
)
from .translate import LANGUAGES, translate

__all__ = [
    "ATLAS_INCLUDE_STEM",
    "CURVE_SEGMENTS",
    "CURVE_TOLERANCE",
    "CURVE_WARPS",
    "FINE_CURVE_SEGMENTS",
    "INCLUDE_STEM",
    "LANGUAGES",
    "PER_PIXEL_MODELS",
    "SHADER_INCLUDES",
    "ShaderConstants",
    "bits_clamp",
    "coefficients_per_pixel_gulbrandsen",
    "coefficients_per_pixel_gulbrandsen_table",
    "coefficients_per_pixel_model",
    "coefficients_per_pixel_nk",
    "coefficients_per_pixel_nk_table",
    "direct_fresnel",
    "direct_fresnel_table",
    "linear_direct",
    "linear_model_curve",
    "linear_split_sum",
    "linear_weights",
    "ltc_coordinates",
    "lut_coordinates",
    "linear_rect_light_specular",
    "rect_light_punctual",
    "rect_light_specular",
    "sanitize_gulbrandsen",
    "sanitize_nk",
    "sanitize_unit",
    "shader_constants",
    "shader_includes",
    "shader_source",
    "translate",
    "unwarped_cosine",
    "warped_cosine",
]
