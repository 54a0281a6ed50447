"""The shader include of a build: one self-contained file per language, every function written once.

Public objects: ``SHADER_INCLUDES``, ``INCLUDE_STEM``, ``ATLAS_INCLUDE_STEM``, ``PIXEL_TABLE_FUNCTIONS``, ``shader_source``,
``shader_includes``.

The include is assembled in the project's GLSL subset (:mod:`handoff.shaders.translate`) and printed in each
language: the header, the constants of :class:`~handoff.shaders.constants.ShaderConstants`, the few functions whose
statements depend on the basis (the fit angles' exact Fresnel, the solve, the curves' Horner steps, the terms
record of a basis of five to eight terms), then the bodies of ``source/*.glsl`` with their placeholders filled in:

* ``{{terms}}``: one channel's coefficients and terms: ``vec4`` for K ≤ 4, ``FresnelTerms8`` (``.lo`` terms 0-3,
  ``.hi`` 4-7) for K > 4;
* ``{{solve}}``, ``{{linear}}``, ``{{curves}}``, ``{{fetch}}``, ``{{averages}}``, ``{{albedo}}``, ``{{column}}``,
  ``{{table_terms}}``, ``{{curve_terms}}``, ``{{rect_punctual}}`` (and its comment, ``{{rect_punctual_note}}``:
  :attr:`preintegrate.lut.LutGrid.holds_mirror`):
  statements or expressions generated from the basis and the grid;
* a texture ``lut2`` (the second table of a basis of five to eight terms) and every argument passing it exist only
  where K > 4.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path

import numpy as np

from basis.coefficient_table import COEFFICIENT_TABLE_SIZE, coefficient_table_axes
from basis.eigenbasis import Basis
from basis.models.formulas import F82_MU, lazanyi_dip
from basis.validation import ParameterError, safe_line
from preintegrate.ltc import (
    LOBE_RATIO_MAX,
    LOBE_RATIO_PER_SIZE,
    LOBE_SHARE_RAISED,
    LOBE_SPREAD_POWER,
    LOBE_SPREAD_RATIO,
    LOBE_SPREAD_SHARE,
    LOBE_WEIGHT_POWER,
    PUNCTUAL_SPREAD,
    SPLIT_SUM_WEIGHT_LINEAR,
    SPLIT_SUM_WEIGHT_POWER,
    UPPER_SHARE_POWER,
    edge_factor_polynomial,
)
from preintegrate.lut import LutGrid
from preintegrate.multiple_scattering import schlick_table_averages

from ..atlas import ATLAS_ROLES
from ..shipped import COEFFICIENT_LUT_TERMS, CURVE_LUT_SIZE, CURVE_LUT_TERMS
from .constants import ShaderConstants, segment_map, shader_constants
from .translate import LANGUAGES, translate

__all__ = [
    "ATLAS_INCLUDE_STEM",
    "INCLUDE_STEM",
    "PIXEL_TABLE_FUNCTIONS",
    "SHADER_INCLUDES",
    "shader_includes",
    "shader_source",
]

#: The bodies, in the order the include holds them (each may call only what stands before it).
SOURCES = ("fresnel.glsl", "coefficients.glsl", "direct.glsl", "tables.glsl", "area.glsl")
SOURCE_FOLDER = Path(__file__).resolve().parent / "source"
#: The include's file name without its suffix (a scene's: ``fresnel_basis_scene``).
INCLUDE_STEM = "fresnel_basis"
_DESCRIPTIONS = {"glsl": "GLSL 3.30 / 4.50 / ES 3.00", "hlsl": "HLSL", "wgsl": "WGSL"}


def _number(value: float) -> str:
    """A constant as a float32 literal of every shading language; a value that none can hold (NaN, inf, beyond
    float32) is refused here, before any include is written, so that a generated include always compiles."""
    value = float(value)
    if not np.isfinite(value) or abs(value) > np.finfo(np.float32).max:
        raise ParameterError(f"a shader constant must be a finite float32 number, got {value!r}")
    text = f"{value:.9g}"
    return text if any(mark in text for mark in ".en") else text + ".0"


def _exponent(value: float, digits: int = 0) -> str:
    """1e-5, 3.1e-5: a tolerance as the comments write it."""
    return f"{value:.{digits}e}".replace("e-0", "e-").replace("e+0", "e")


def _vector_type(width: int) -> str:
    return "float" if width == 1 else f"vec{width}"


def _value(values) -> str:
    values = np.atleast_1d(np.asarray(values, dtype=np.float64))
    if len(values) == 1:
        return _number(values[0])
    return f"{_vector_type(len(values))}(" + ", ".join(_number(value) for value in values) + ")"


def _constant(name: str, values, comment: str = "") -> str:
    width = np.atleast_1d(values).size
    return f"const {_vector_type(width)} {name} = {_value(values)};" + (f"  // {comment}" if comment else "")


def _squarings_constant(name: str, power: float, comment: str) -> str:
    """``const int name = log2(power)``: the shaders raise to ``power`` by that many squarings (``fresnelLtcSquared``),
    so it must be a power of two, at least 2."""
    times = int(round(np.log2(power))) if power >= 2.0 else 0
    if times < 1 or 2.0**times != power:
        raise ParameterError(f"{name}: the shaders raise to {power:g} by squaring, which needs a power of two from 2")
    return f"const int {name} = {times};  // {comment}"


def _terms_constants(name: str, values, wide: bool, comment: str) -> list[str]:
    """``values`` (K,) as one vec4 ``name`` (zero-padded), and ``name_HI`` (terms 4-7) for K > 4."""
    padded = np.zeros(8 if wide else 4)
    padded[: len(values)] = values
    return [_constant(name, padded[:4], comment)] + ([_constant(f"{name}_HI", padded[4:], "terms 4-7")] if wide else [])


def _terms_value(expressions: list[str], wide: bool) -> str:
    """The terms record of up to eight scalar expressions (zero-padded)."""
    padded = list(expressions) + ["0.0"] * ((8 if wide else 4) - len(expressions))
    low = f"vec4({', '.join(padded[:4])})"
    return f"fresnelTerms8({low}, vec4({', '.join(padded[4:])}))" if wide else low


def _fit_chunks(n_angles: int) -> list[tuple[str, slice]]:
    """The fit angles θ_2 … θ_(K−1) in vectors of at most four: (constant suffix, angles); none for K = 2."""
    if n_angles == 0:
        return []
    if n_angles <= 4:
        return [("", slice(0, n_angles))]
    return [("", slice(0, 4)), ("_HI", slice(4, n_angles))]


def _fit_parts(c: ShaderConstants) -> tuple[list[str], str, str]:
    """(constants, functions, the solve's statements) of the K − 2 fit angles: exact Fresnel at each vector of at
    most four angles (Hoffman's Fs times (1 + Fp/Fs) / 2, the angle terms constant: one division), then
    c_(2+j) = Σ_i S⁻¹[j, i] (F(θ_i) − c0 − c1 b1(θ_i))."""
    chunks = _fit_chunks(len(c.fit_mu))
    constants, functions, rests = [], [], []
    for suffix, part in chunks:
        mu = c.fit_mu[part]
        width, kind = len(mu), _vector_type(len(mu))
        m, m2, s2 = (f"FRESNEL_FIT_MU_ROOT2{suffix}", f"FRESNEL_FIT_MU2{suffix}", f"FRESNEL_FIT_SIN2{suffix}")
        constants += [
            _constant(m, np.sqrt(2.0) * mu, "sqrt(2) cos(theta_i) of the fit angles"),
            _constant(m2, mu**2, "cos^2"),
            _constant(s2, (1.0 - mu) * (1.0 + mu), "sin^2"),
            _constant(f"FRESNEL_FIT_B1{suffix}", c.fit_b1[part], "b1 at the fit angles"),
        ]
        name = "fresnelAtFitAngles" + ("Hi" if suffix else "")
        if c.grazing_fit_angles:  # every angle beyond 45 degrees: eta^2 - kappa^2 - sin^2 as (eta - 1)(eta + 1) ...
            difference = [f"    {kind} t = (eta - 1.0) * (eta + 1.0) - kappa2 + {m2};  // eta^2 - kappa^2 - sin^2"]
        else:
            difference = [
                "    bool nearOne = abs(eta - 1.0) < 0.5;",
                "    float base = (nearOne ? (eta - 1.0) * (eta + 1.0) : eta * eta) - kappa2;",
                f"    {kind} t = base + (nearOne ? {m2} : -{s2});",
            ]
        components = "xyzw"[:width]
        two_a2 = (
            "fresnelTwoA2(t, u, e4)"
            if width == 1
            else f"{kind}(" + ", ".join(f"fresnelTwoA2(t.{axis}, u.{axis}, e4)" for axis in components) + ")"
        )
        body = [
            *difference,
            "    float e4 = 4.0 * eta * eta * kappa2;",
            f"    {kind} s = sqrt(t * t + e4);",
            f"    {kind} u = s + abs(t);",
            f"    {kind} twoAMu = {m} * sqrt({two_a2});  // 2 a mu",
            f"    {kind} r = s * {m2} + {s2} * {s2};",
        ]
        if width == 2:  # one division for both angles: den.x den.y < 1e31 over the documented (eta, kappa)
            body += [
                f"    {kind} den = (s + {m2} + twoAMu) * (r + twoAMu * {s2});",
                "    float inverse = 1.0 / (den.x * den.y);",
                f"    return (s + {m2} - twoAMu) * r * den.yx * inverse;",
            ]
        else:
            body.append(f"    return (s + {m2} - twoAMu) * r / ((s + {m2} + twoAMu) * (r + twoAMu * {s2}));")
        functions.append("\n".join([f"{kind} {name}(float eta, float kappa2)", "{", *body, "}", ""]))
        rest = "rest" + ("Hi" if suffix else "")
        rests.append(f"    {kind} {rest} = {name}(eta, kappa2) - f0 - (f90 - f0) * FRESNEL_FIT_B1{suffix};")
    solved = []
    for j, row in enumerate(c.inverse):
        terms = []
        for suffix, part in chunks:
            width = part.stop - part.start
            name = f"FRESNEL_FIT_INVERSE_{j}{suffix}"
            constants.append(_constant(name, row[part], f"row {j} of S^-1" if not suffix else ""))
            rest = "rest" + ("Hi" if suffix else "")
            terms.append(f"{name} * {rest}" if width == 1 else f"dot({name}, {rest})")
        solved.append(" + ".join(terms))
    wide = c.n_terms > 4
    statements = "\n".join([*rests, f"    return {_terms_value(['f0', 'f90 - f0', *solved], wide)};"])
    return constants, "\n".join(functions), statements


def _choose(conditions: list[str], values: list[str]) -> str:
    """The value of the first true condition, else the last value: nested conditionals (values[i] where
    conditions[i] is the first that holds), branch-free and with every index a literal."""
    if len(values) == 1:
        return values[0]
    return f"({conditions[0]} ? {values[0]} : {_choose(conditions[1:], values[1:])})"


def _edge_factor_parts() -> tuple[list[str], str]:
    """(constants, expression): the polynomial in u = 1 − cos θ ∈ [0, 1] that the area lights' edge integral takes
    θ / sin θ from (preintegrate.ltc.edge_factor_polynomial, degree 7: two vec4 of coefficients, constant term first;
    no array, which WGSL would hold as a private variable), and its Horner form in ``u``."""
    coefficients = edge_factor_polynomial()
    if len(coefficients) != 8:
        raise ValueError(f"the include holds a polynomial of degree 7, not {len(coefficients) - 1}")
    names = [f"FRESNEL_LTC_EDGE{suffix}.{axis}" for suffix in ("", "_HI") for axis in "xyzw"]
    expression = names[-1]
    for name in reversed(names[:-1]):
        expression = f"{name} + u * ({expression})"
    return [
        "// theta / sin(theta) = sum_p c_p u^p, u = 1 - cos(theta) in [0, 1], c_0 .. c_7 "
        "(preintegrate.ltc.edge_factor_polynomial).",
        _constant("FRESNEL_LTC_EDGE", coefficients[:4], "c_0 .. c_3"),
        _constant("FRESNEL_LTC_EDGE_HI", coefficients[4:], "c_4 .. c_7"),
    ], expression


def _curve_parts(c: ShaderConstants) -> tuple[list[str], str]:
    """(constants, statements) of the direct-light curves b_1 … b_(K−1) (b_0 = 1 is not evaluated): the warped
    cosine x, the segment of x, s on it, then the Horner steps of the polynomials, terms 1-3 in FRESNEL_CURVES and
    4-7 in FRESNEL_CURVES_HI. With segments, each power's coefficients are chosen by conditionals on literal
    indices: an index that varies per pixel into a constant array is an indirect load per lane (llvmpipe measured it
    at half the cost of Schlick's whole pass; divergent constant-memory reads on GPUs)."""
    edges, d, k = c.curve_segments, c.curve_degree, c.n_terms
    wide = k > 4
    polynomial = c.curve_polynomials.reshape(-1, k)  # (segments · (degree + 1), K)
    parts = [("", "b" if not wide else "bLo", polynomial[:, 1 : min(k, 4)])]
    if wide:
        parts.append(("_HI", "bHi", polynomial[:, 4:]))
    count = polynomial.shape[0]
    constants = []
    if c.curve_warp:
        constants.append(_constant("FRESNEL_CURVE_WARP", c.curve_warp, "w of x = mu (1 + w) / (1 + w mu)"))
    if len(edges) == 4:
        constants.append(_constant("FRESNEL_CURVE_EDGES", edges, "segment edges in x"))
        inner = [f"FRESNEL_CURVE_EDGES.{axis}" for axis in "yz"]
    elif len(edges) > 2:
        values = ", ".join(_number(edge) for edge in edges)
        constants.append(f"const float FRESNEL_CURVE_EDGES[{len(edges)}] = float[{len(edges)}]({values});")
        inner = [f"FRESNEL_CURVE_EDGES[{i}]" for i in range(1, len(edges) - 1)]
    else:
        inner = []
    constants.append(f"const int FRESNEL_CURVE_DEGREE = {d};")
    constants.append(
        f"// b_1 .. b_{k - 1} (b_0 = 1) on segment j of x: sum_p FRESNEL_CURVES[j * {d + 1} + p] * s^p, "
        "s = 2 (x - lo) / (hi - lo) - 1"
    )
    for suffix, _, rows in parts:
        kind = _vector_type(rows.shape[1])
        body = ",\n".join("    " + _value(row) for row in rows)
        constants.append(f"const {kind} FRESNEL_CURVES{suffix}[{count}] = {kind}[{count}](\n{body}\n);")
    x = "mu * (1.0 + FRESNEL_CURVE_WARP) / (1.0 + FRESNEL_CURVE_WARP * mu)" if c.curve_warp else "mu"
    statements = [f"    float x = {x};"]
    conditions = [f"below{i}" for i in range(1, len(edges) - 1)]
    statements += [f"    bool {name} = x < {edge};" for name, edge in zip(conditions, inner)]
    scale, offset = segment_map(edges)
    if conditions:
        s = (
            f"x * {_choose(conditions, [_number(value) for value in scale])} "
            f"+ {_choose(conditions, [_number(value) for value in offset])}"
        )
    else:
        s = f"x * {_number(scale[0])} {'-' if offset[0] < 0 else '+'} {_number(abs(offset[0]))}"
    statements.append(f"    float s = {s};")
    segments = len(edges) - 1

    def coefficient(suffix: str, power: int) -> str:
        return _choose(conditions, [f"FRESNEL_CURVES{suffix}[{j * (d + 1) + power}]" for j in range(segments)])

    for suffix, name, rows in parts:
        statements.append(f"    {_vector_type(rows.shape[1])} {name} = {coefficient(suffix, d)};")
    for power in range(d - 1, -1, -1):
        statements += [f"    {name} = {name} * s + {coefficient(suffix, power)};" for suffix, name, _ in parts]
    low = f"vec4(1.0, {parts[0][1]}{', 0.0' * (4 - min(k, 4))})"
    result = low if not wide else f"fresnelTerms8({low}, vec4(bHi{', 0.0' * (8 - k)}))"
    statements.append(f"    return {result};")
    return constants, "\n".join(statements)


def _atlas_map(c: ShaderConstants, role: str) -> tuple[float, float, float, float]:
    """(scale u, scale v, offset u, offset v) of a per-pixel table's coordinates into the include's atlas (the identity
    without one, or where the include reads no per-pixel table)."""
    if c.atlas is None or not c.pixel_tables:
        return 1.0, 1.0, 0.0, 0.0
    if role not in c.atlas:
        raise ParameterError(f"the atlas holds no {role} table, which this include reads")
    return tuple(float(value) for value in c.atlas[role])


def _coefficient_table_parts(c: ShaderConstants) -> tuple[str, str]:
    """(constant, return expression) of ``fresnelCoefficientsTableRead``: the affine maps of x = r^(1/4) − √(1 − r)/2
    and of s = (1 − g)^(1/4) (its row y = 1 − s folded into the map) onto the texel centres of a
    :data:`~basis.coefficient_table.COEFFICIENT_TABLE_SIZE` table (r = 0 a quarter texel before column 0, g's end
    points on the end rows), composed with the atlas' map where there is one (one multiply-add per coordinate either
    way), and c0 = r, c1 = f90 − r, c2 … from the fetch t (K − 1 ≤ 4 channels, f90 the last); a basis of more than five
    terms has no table (``fresnel-lut build --pixel-tables`` refuses it) and solves instead."""
    k = c.n_terms
    width, height = COEFFICIENT_TABLE_SIZE
    first, step = coefficient_table_axes(width, height)
    x_scale, x_offset = 1.0 / (width * step), (0.5 - first / step) / width
    s_scale, s_offset = -(height - 1) / height, (height - 0.5) / height
    tabled = k in COEFFICIENT_LUT_TERMS
    scale_u, scale_v, offset_u, offset_v = _atlas_map(c, "coefficients") if tabled else (1.0, 1.0, 0.0, 0.0)
    axes = [x_scale * scale_u, x_offset * scale_u + offset_u, s_scale * scale_v, s_offset * scale_v + offset_v]
    constant = _constant("FRESNEL_COEFFICIENT_AXES", axes, "x scale, x offset, s scale, s offset of the table's texels")
    if k == 2:  # c0 and c1 alone: nothing to read
        return constant, _terms_value(["r", "(r > 0.0 ? 1.0 : 0.0) - r"], False)
    if not tabled:
        return constant, "fresnelCoefficientsGulbrandsen(r, g)"
    channels = "xyzw"[: k - 1]
    return constant, _terms_value(["r", f"t.{channels[-1]} - r", *(f"t.{axis}" for axis in channels[:-1])], k > 4)


def _curve_table_parts(c: ShaderConstants) -> tuple[str, str]:
    """(constant, terms expression) of ``fresnelBasisDirectTable``: the map of μ onto the texel centres of the
    :data:`~handoff.shipped.CURVE_LUT_SIZE` end points and the row's v, composed with the atlas' map where there is
    one, and b = (1, t.x, …) from the fetch t; more than five terms evaluate the polynomial instead."""
    k = c.n_terms
    tabled = k in CURVE_LUT_TERMS
    scale_u, scale_v, offset_u, offset_v = _atlas_map(c, "curves") if tabled else (1.0, 1.0, 0.0, 0.0)
    table = [
        (CURVE_LUT_SIZE - 1) / CURVE_LUT_SIZE * scale_u,
        0.5 / CURVE_LUT_SIZE * scale_u + offset_u,
        0.5 * scale_v + offset_v,
    ]
    constant = _constant("FRESNEL_CURVE_TABLE", table, "scale, offset of mu, v of the row")
    if not tabled:
        return constant, "fresnelBasisCurves(mu)"
    return constant, _terms_value(["1.0", *(f"t.{axis}" for axis in "xyzw"[: k - 1])], k > 4)


#: The functions that read the tables at (V·H*, r') down to r = 0, left out where the grid does not hold that row.
MIRROR_ROW_FUNCTIONS = ("fresnelMirrorLutUV", "fresnelBasisSmoothed", "fresnelLinearSmoothed")
#: The functions that read the per-pixel tables (or choose them), left out of an include whose basis has none.
PIXEL_TABLE_FUNCTIONS = (
    "fresnelCoefficientsTableRead",
    "fresnelCoefficientsGulbrandsenTable",
    "fresnelCoefficientsNKTable",
    "fresnelCoefficientsGulbrandsenSelected",
    "fresnelCoefficientsNKSelected",
    "fresnelCoefficientsGulbrandsenTable3",
    "fresnelBasisDirectTable",
    "fresnelBasisDirectSelected",
)


#: The atlas roles only the per-pixel tables' functions read (an include without them needs no such rectangle).
PIXEL_TABLE_ROLES = ("coefficients", "curves")


def _without_functions(text: str, names) -> str:
    """``text`` (the assembled GLSL) without the top-level functions ``names`` and the comment lines right above
    each."""
    lines, kept, index = text.split("\n"), [], 0
    pattern = re.compile(r"^\w+ (" + "|".join(map(re.escape, names)) + r")\(")
    while index < len(lines):
        if pattern.match(lines[index]):
            while kept and kept[-1].startswith("//"):
                kept.pop()
            index = lines.index("}", index) + 1
            if index < len(lines) and not lines[index].strip():
                index += 1
            continue
        kept.append(lines[index])
        index += 1
    return "\n".join(kept)


def _header(c: ShaderConstants, language: str, command: str) -> str:
    k, m = c.n_terms, c.n_terms - 2
    solve = (
        f"exact Fresnel at the {m} fit angle{'s' if m != 1 else ''} + a constant {m}x{m} inverse"
        if m
        else "F(0), 1 - F(0)"
    )
    kind = "one vec4 per channel" if k <= 4 else "a FresnelTerms8 per channel (.lo terms 0-3, .hi terms 4-7)"
    textures = "lut" if k <= 4 else "lut, lut2 (the build's two basis tables)"
    sampler = {"glsl": "", "hlsl": " (and one SamplerState linearClamp after them)", "wgsl": " (and one sampler)"}
    return "\n".join(
        [
            f"// fresnel-basis: Fresnel of basis {c.basis_hash} for real-time rendering ({_DESCRIPTIONS[language]}, "
            f"{k} terms). Generated by",
            f"// `{safe_line(command)}` from the basis and the tables' grid: do not edit, regenerate it. Self-contained:",
            f"// use it beside the tables whose header says fresnel:basis_hash = {c.basis_hash}.",
            "//",
            "// Per pixel, per colour channel, " + kind + ' (Belcour, Bati, Barla 2020, eq. 4-5 and "Coefficients"):',
            f"//   fresnelCoefficientsNK(eta, kappa)               {solve}",
            "//   fresnelCoefficientsGulbrandsen(r, g)            Gulbrandsen 2014 eq. 7-9, then the same",
            "//   fresnelCoefficientsSchlick(f0, f90)             Schlick 1994 (F90 = 1: the usual Schlick)",
            "//   fresnelCoefficientsF82(f0, f82)                 Hoffman 2019's absolute F82",
            "//   fresnelCoefficientsF82Tint(f0, tint)            Adobe / OpenPBR specular_color / MaterialX color82 (a tint)",
            "//   fresnelCoefficientsGeneralizedAdobe(r0, r90, t) Hoffman 2023 eq. 6, p = 5",
            "// then, with the same coefficients: image-based light fresnelBasisSplitSum (or",
            "// fresnelBasisMultipleScattering), punctual lights fresnelBasisDirect(VdotH, ...), rectangular lights",
            f"// fresnelBasisRectLight. Tables: {textures}{sampler[language]}, read at level 0 through",
            "// fresnelBasisLutUV (bilinear, clamp to edge, no mipmaps).",
            "// Linear models exactly, from the Schlick table (R, G, A: scale, bias, dip), one vec3 of weights per channel:",
            "//   fresnelLinearSchlick(f0, f90), fresnelLinearF82(f0, f82), fresnelLinearF82Tint(f0, tint),",
            "//   fresnelLinearGeneralizedAdobe(r0, r90, tint) (Hoffman 2023 eq. 5-6, p = 5), then fresnelLinearSplitSum,",
            "//   fresnelLinearMultipleScattering, fresnelLinearDirect, fresnelLinearRectLight (schlickLut for lut).",
            *(
                [
                    "// Per-pixel tables (fresnel-lut build --pixel-tables): fresnelCoefficientsGulbrandsenTable(coefficientLut,",
                    "//   r, g), fresnelCoefficientsNKTable, fresnelBasisDirectTable(curveLut, ...), or the ...Selected functions,",
                    "//   which FRESNEL_BASIS_SOLVE switches to the solve.",
                ]
                if c.pixel_tables
                else ["// No per-pixel tables: they exist for a build's basis, not for this one."]
            ),
            "// Inputs: NaN becomes a fallback, every other value is clamped (eta to [1e-4, 1e4], kappa to [0, 1e4], r to",
            "// [0, 0.9999], the rest to [0, 1]); the table functions send a NaN to an end of its range by its sign bit.",
            f"// Float32: coefficients within {_exponent(c.float32_tolerance)} of float64, the Fresnel curve they give "
            f"within {_exponent(c.float32_curve_tolerance)}; the",
            f"// direct-light curves within {_exponent(c.curve_error, 1)} of the basis' spline (float64; tests/luts/ "
            "measures all three",
            "// on the GPU).",
            "",
        ]
    )


def _atlas_parts(c: ShaderConstants) -> tuple[list[str], str]:
    """(constants, functions) of the tables' address functions ``fresnelAtlas<Role>(uv)``: the identity where every
    table is its own texture, the map into its rectangle of one atlas (FRESNEL_ATLAS_<ROLE>: scale, offset). The
    per-pixel tables have none: their axes' constants already include the atlas' map."""
    constants, functions = [], []
    for role in ATLAS_ROLES:  # fresnelAtlasBasis, fresnelAtlasBasis2, fresnelAtlasSchlick, …
        if (role == "basis2" and c.n_terms <= 4) or role in PIXEL_TABLE_ROLES:
            continue
        if c.atlas is None:
            body = "    return uv;"
        else:
            if role not in c.atlas:
                raise ParameterError(f"the atlas holds no {role} table, which this include reads")
            name = f"FRESNEL_ATLAS_{role.upper()}"
            constants.append(_constant(name, c.atlas[role], "scale u, scale v, offset u, offset v in the atlas"))
            body = f"    return uv * {name}.xy + {name}.zw;"
        functions.append("\n".join([f"vec2 fresnelAtlas{role.capitalize()}(vec2 uv)", "{", body, "}", ""]))
    what = (
        "each table's own coordinates into its rectangle of the atlas"
        if c.atlas is not None
        else "the identity: every table is its own texture (an atlas build maps them into one)"
    )
    return constants, "\n".join([f"// The tables' addresses: {what}.", *functions])


def _record(wide: bool) -> str:
    """The terms record and its dot product (one vec4 for K ≤ 4; FresnelTerms8 of two for K > 4)."""
    if not wide:
        return "\n".join(
            [
                "// One channel's coefficients times the terms: sum_k c_k x_k.",
                "float fresnelTermsDot(vec4 c, vec4 x)",
                "{",
                "    return dot(c, x);",
                "}",
                "",
            ]
        )
    return "\n".join(
        [
            "// A basis of five to eight terms: one channel's coefficients (or terms) as two vec4, terms 0-3 and 4-7.",
            "struct FresnelTerms8",
            "{",
            "    vec4 lo;  // terms 0-3",
            "    vec4 hi;  // terms 4-7",
            "};",
            "",
            "FresnelTerms8 fresnelTerms8(vec4 lo, vec4 hi)",
            "{",
            "    FresnelTerms8 terms;",
            "    terms.lo = lo;",
            "    terms.hi = hi;",
            "    return terms;",
            "}",
            "",
            "float fresnelTermsDot(FresnelTerms8 c, FresnelTerms8 x)",
            "{",
            "    return dot(c.lo, x.lo) + dot(c.hi, x.hi);",
            "}",
            "",
        ]
    )


def _rect_punctual_parts(grid: LutGrid, albedo: str) -> dict[str, str]:
    """``fresnelBasisRectLight``'s and ``fresnelLinearRectLight``'s F averaged over the light, times E (``albedo``):
    from their table at (V·H*, r') where the grid holds the mirror row (:attr:`preintegrate.lut.LutGrid.holds_mirror`),
    else F(V·H*) from the direct-light polynomial (r' left out: such a table has no rows near r = 0)."""
    if grid.holds_mirror:
        return {
            "rect_punctual": f"fresnelBasisSmoothed(lut, lut2, VdotH, spread, {albedo}, cR, cG, cB)",
            "rect_punctual_note": "the basis table at (V.H*, r'), over its albedo there (one fetch; at r' = 0 the\n"
            "// table's mirror row, the curve itself; bilinear between the table's columns: tests/luts/test_shaders_area.py\n"
            "// measures it).",
            "linear_rect_punctual": "fresnelLinearSmoothed(schlickLut, VdotH, spread, t.z, wR, wG, wB)",
            "linear_rect_punctual_note": "the Schlick table at (V.H*, r'), over its B there",
        }
    return {
        "rect_punctual": f"{albedo} * fresnelBasisDirect(VdotH, cR, cG, cB)",
        "rect_punctual_note": "F(V.H*) from the direct-light polynomial (this table's rows start above r = 0).",
        "linear_rect_punctual": "t.z * fresnelLinearDirect(VdotH, wR, wG, wB)",
        "linear_rect_punctual_note": "F(V.H*) itself: this table's rows start above r = 0",
    }


def shader_source(constants: ShaderConstants, command: str = "fresnel-lut build") -> str:
    """The include in the project's GLSL subset, every placeholder filled in (GLSL as it is written)."""
    c = constants
    wide = c.n_terms > 4
    fit_constants, fit_functions, solve = _fit_parts(c)
    curve_constants, curves = _curve_parts(c)
    projections = [
        line
        for name, row, what in zip(
            ("SCALE", "BIAS", "DIP"), c.projections, ("1 - (1 - mu)^5", "(1 - mu)^5", "mu (1 - mu)^6")
        )
        for line in _terms_constants(f"FRESNEL_PROJECTION_{name}", row, wide, f"coefficients of {what}")
    ]
    linear = [
        f"w.x * FRESNEL_PROJECTION_SCALE{s} + w.y * FRESNEL_PROJECTION_BIAS{s} + w.z * FRESNEL_PROJECTION_DIP{s}"
        for s in ([""] + (["_HI"] if wide else []))
    ]
    grid = c.grid
    column = (
        "sqrt(fresnelSanitize(NdotV, 1.0, 0.0, 1.0))"
        if grid.columns == "root-endpoints"
        else ("fresnelSanitize(NdotV, 1.0, 0.0, 1.0)")
    )
    fetch = "textureLod(lut, fresnelAtlasBasis(uv), 0.0)"
    axes_constant, table_terms = _coefficient_table_parts(c)
    curve_table_constant, curve_terms = _curve_table_parts(c)
    atlas_constants, atlas_functions = _atlas_parts(c)
    edge_constants, edge_factor = _edge_factor_parts()
    placeholders = {
        "edge_factor": edge_factor,
        "terms": "FresnelTerms8" if wide else "vec4",
        "table_terms": table_terms,
        "curve_terms": curve_terms,
        "solve": solve,
        "linear": f"    return {f'fresnelTerms8({linear[0]}, {linear[1]})' if wide else linear[0]};",
        "curves": curves,
        "column": column,
        "fetch": f"fresnelTerms8({fetch}, textureLod(lut2, fresnelAtlasBasis2(uv), 0.0))" if wide else fetch,
        "averages": "fresnelTerms8(FRESNEL_BASIS_AVERAGES, FRESNEL_BASIS_AVERAGES_HI)"
        if wide
        else "FRESNEL_BASIS_AVERAGES",
        "albedo": "b.lo.x" if wide else "b.x",
        "mirror_column": "sqrt(x)" if grid.columns == "root-endpoints" else "x",
        **_rect_punctual_parts(grid, "b.lo.x" if wide else "b.x"),
    }
    preamble = [
        f"const uint FRESNEL_BASIS_HASH = 0x{c.basis_hash[:8]}u;  // the first 8 hex digits of {c.basis_hash}",
        *fit_constants,
        *projections,
        *_terms_constants("FRESNEL_BASIS_AVERAGES", c.averages, wide, "2 * integral of b_k(mu) mu dmu"),
        *curve_constants,
        _constant("FRESNEL_F82_SCHLICK_WEIGHT", (1.0 - F82_MU) ** 5, "(1 - 1/7)^5"),
        _constant("FRESNEL_F82_DIP", lazanyi_dip(F82_MU), "(1/7) (1 - 1/7)^6"),
        _constant(
            "FRESNEL_LINEAR_AVERAGES",
            schlick_table_averages()[[0, 1, 3]],
            "2 * integral of t(mu) mu dmu, t = 1 - (1 - mu)^5, (1 - mu)^5, mu (1 - mu)^6",
        ),
        f"// The tables' grid ({grid.width} x {grid.height}, columns at {grid.columns}, rows at {grid.rows}): "
        "fresnelBasisLutUV's affine maps.",
        _constant("FRESNEL_LUT_COLUMNS", grid.column_mapping, "scale, offset"),
        _constant("FRESNEL_LUT_ROWS", grid.row_mapping, "lo, hi, scale, offset"),
        _constant("FRESNEL_LTC_SIZE", c.ltc_size, "the LTC table's texels a side"),
        "// How far the lobe over the LTC's density raises a rect light's integral I: at most max(R0, min(K sqrt(solid "
        "angle), S / I)) (preintegrate.ltc.lobe_ratio_bound).",
        _constant("FRESNEL_LTC_LOBE_RATIO_MAX", LOBE_RATIO_MAX, "R0, any light"),
        _constant(
            "FRESNEL_LTC_LOBE_RATIO_PER_SIZE",
            LOBE_RATIO_PER_SIZE * np.sqrt(np.pi),
            "K sqrt(pi): K per unit of sqrt(the light's solid angle), which the shader has over sqrt(pi)",
        ),
        _constant("FRESNEL_LTC_LOBE_SHARE_RAISED", LOBE_SHARE_RAISED, "S, the share of the lobe it may raise I to"),
        _constant(
            "FRESNEL_LTC_LOBE_WEIGHT_POWER",
            LOBE_WEIGHT_POWER,
            "p: I keeps the weight I^p against that ratio (preintegrate.ltc.toward_lobe_limit)",
        ),
        _squarings_constant(
            "FRESNEL_LTC_SPREAD_SQUARINGS",
            LOBE_SPREAD_POWER,
            "log2 k: w is at least (1 - s^k) min(1, I / c) min(1, ratio / rho), s the light's spread",
        ),
        _constant("FRESNEL_LTC_SPREAD_SHARE", LOBE_SPREAD_SHARE, "c (preintegrate.ltc.LOBE_SPREAD_POWER)"),
        _constant("FRESNEL_LTC_SPREAD_RATIO", LOBE_SPREAD_RATIO, "rho (preintegrate.ltc.LOBE_SPREAD_POWER)"),
        _constant(
            "FRESNEL_LTC_PUNCTUAL_SPREAD",
            PUNCTUAL_SPREAD * np.sqrt(np.pi),
            "k sqrt(pi): a rect light's Fresnel is that of a GGX lobe of roughness min(r, k sqrt(solid angle)), which "
            "the shader has as k sqrt(pi) size (preintegrate.ltc.PUNCTUAL_SPREAD)",
        ),
        _squarings_constant(
            "FRESNEL_LTC_UPPER_SHARE_SQUARINGS",
            UPPER_SHARE_POWER,
            "log2 m: the LTC's share below the horizon counts as min(I / H, 1)^m (preintegrate.ltc.toward_upper_share)",
        ),
        _constant(
            "FRESNEL_LTC_SPLIT_SUM_WEIGHT_LINEAR",
            SPLIT_SUM_WEIGHT_LINEAR,
            "a: the split sum's weight a I + (1 - a) I^n in a rect light's Fresnel (preintegrate.ltc.rect_light_fresnel)",
        ),
        _squarings_constant(
            "FRESNEL_LTC_SPLIT_SUM_WEIGHT_SQUARINGS",
            SPLIT_SUM_WEIGHT_POWER,
            "log2 n (FRESNEL_LTC_SPLIT_SUM_WEIGHT_LINEAR)",
        ),
        *edge_constants,
        axes_constant,
        curve_table_constant,
        *atlas_constants,
        "",
    ]
    bodies = [(SOURCE_FOLDER / name).read_text(encoding="utf-8") for name in SOURCES]
    bodies.insert(1, fit_functions)  # after the exact Fresnel helpers, before the solve that calls them
    text = "\n".join([_header(c, "glsl", command), *preamble, _record(wide), atlas_functions, *bodies])
    text = re.sub(r"\{\{(\w+)\}\}", lambda match: placeholders[match.group(1)], text)
    if not c.pixel_tables:
        text = _without_functions(text, PIXEL_TABLE_FUNCTIONS)
    if not grid.holds_mirror:  # no rows near r = 0: the rect lights take F(V·H*) from the polynomials
        text = _without_functions(text, MIRROR_ROW_FUNCTIONS)
    if not wide:  # the second table exists only for five to eight terms
        text = re.sub(r",\s*(?:sampler2D\s+)?lut2\b", "", text)
    return text


def _include(language: str) -> Callable[[ShaderConstants, str], str]:
    def generate(constants: ShaderConstants, command: str) -> str:
        source = shader_source(constants, command)
        header_end = source.index("\nconst uint FRESNEL_BASIS_HASH")
        return _header(constants, language, command) + translate(source[header_end:], language)

    return generate


#: Registry: language → (file name, generator(constants, command) → text) of the include.
SHADER_INCLUDES: dict[str, tuple[str, Callable[[ShaderConstants, str], str]]] = {
    language: (f"{INCLUDE_STEM}.{language}", _include(language)) for language in LANGUAGES
}


#: The stem of an include that reads every table from one atlas (``fresnel-lut build --atlas``).
ATLAS_INCLUDE_STEM = f"{INCLUDE_STEM}_atlas"


def shader_includes(
    basis: Basis | None = None,
    command: str = "fresnel-lut build",
    grid: LutGrid | None = None,
    ltc_size: int = 64,
    atlas: dict | None = None,
    pixel_tables: bool = True,
) -> list[tuple[str, str]]:
    """(file name, text) of the include in every language for ``basis`` (default: the shipped one), its tables' grid
    and the LTC table's size; with ``atlas`` (role → map, :meth:`handoff.atlas.AtlasLayout.uv_map`), the include that
    reads every table from that atlas, ``fresnel_basis_atlas.*`` (the same functions: pass the atlas for every
    table); ``pixel_tables`` False leaves the per-pixel tables' functions out (:data:`PIXEL_TABLE_FUNCTIONS`)."""
    constants = shader_constants(basis, grid, ltc_size, atlas, pixel_tables)
    includes = [(name, generate(constants, command)) for name, generate in SHADER_INCLUDES.values()]
    if atlas is not None:
        includes = [(name.replace(INCLUDE_STEM, ATLAS_INCLUDE_STEM, 1), text) for name, text in includes]
    return includes
