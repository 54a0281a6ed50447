"""Shader-side Fresnel: error against shader cost, per parametrisation (issue 23).

Cost: one full-screen pass at 1280 × 720 on Mesa's llvmpipe (or the GPU the EGL context finds), a sphere's normals
per fragment seen from an eye and lit by a point light at finite distances (V, L and so V·H vary per pixel: with a
constant light direction and view the compiler folds the direct-light Fresnel into a constant, which hid its cost
until 2026-12), the image-based split sum and the point light (GGX, height-correlated G2), ten variants alternated
round by round in one run, the median frame time of each as a ratio to Schlick's (which reads its F0 from a texture,
as a textured material would):

* ``schlick``: F0 texture, Schlick's split-sum table, Schlick's F for the light, its fifth power as three
  multiplications as engines write it (Filament's ``pow5``, HDRP, Unreal; llvmpipe's ``pow`` is a software exp2 and
  log2 that made this baseline 8 % slower and every ratio below look better until 2026-12);
* ``basis uniform``: coefficients as uniforms, the basis table, the basis' direct-light curves;
* ``basis per pixel (eta, kappa)``, ``(r, g)``, ``(F0, F82 tint)``: the generated include's per-pixel solves from
  texture reads, then the same as above;
* ``basis per pixel (r, g), tables``: the per-pixel tables of ``build --pixel-tables`` instead of the solve and the
  polynomial (``fresnelCoefficientsGulbrandsenTable3``, one fetch per colour channel; ``fresnelBasisDirectTable``);
  ``basis per pixel (eta, kappa), tables``: (η, κ) through Gulbrandsen's (r, g) in closed form and the same tables;
  ``basis uniform, curve table``: the uniform coefficients with the curve table (issue 38); and
  :data:`IN_ATLAS`: the tables' pass reading all its tables from one atlas (``build --atlas``);
* ``schlick, two textures``: Schlick reading as many textures as the per-pixel variants (its F0 the product of
  two): what a second texture costs, apart from any Fresnel;
* ``exact x E``: exact conductor Fresnel per pixel times E (the Schlick table's B), and exact F for the light;
* :data:`DECOMPOSITION`: the (r, g) pass with its second texture read, Gulbrandsen's closed form or the exact
  Fresnel at the fit angles taken out, one at a time: what each part costs (diagnostics, not products);
* :data:`DIRECT_ALTERNATIVES`: the (r, g) pass with its direct-light curves read from a 1-D RGBA table over the
  same warped cosine (linear filtering, :data:`CURVE_TABLE_SIZE` texels), the other form issue 23 names: its cost
  and its curve error beside the include's polynomial: the measurement behind the include's choice of form; and
  with Schlick's F from the coefficients' c0 for the light, no curves at all: what the curves cost;
* :data:`SOLVED_OFFLINE`: the coefficients read from three textures (cR, cG, cB), as an engine that solves its
  material maps once at import (with the include's Python mirrors) would read them: what the per-pixel solve costs
  against three texture reads.

Every variant's cost is given twice: measured on llvmpipe, and as a GPU's own compiler estimates it (ACO, Mesa's
compiler for AMD GPUs, compiling the same fragment shader for RDNA 2 through RADV's device-less mode:
:mod:`benchmarks.gpu_compiler`): its instruction count and its inverse throughput (cycles per 64 pixels of the
busiest unit, texture latency hidden behind other waves) as a ratio to Schlick's. llvmpipe filters textures in
software, so a texture read weighs much more there than on a GPU, whose texture unit filters, and arithmetic is
diluted (the decomposition shows both: a second texture read against Gulbrandsen's mapping).

Error, on the materials each parametrisation is for (max over θ of |ΔF|; max over the 128 × 128 table of |ΔF̄|,
bilinear lookup, against the exact curve's own split sum): the held-out metals of the basis build (400 (η, κ), η 0.1–4, κ 1–8), Gulbrandsen's artist
grid (r, g), the F82-tint model's sweep (F0, tint).

Run: ``.venv/bin/python -m benchmarks.shader_cost [--width W --height H --frames N --rounds R --repeats M]
[--out FILE]`` (the report: ``--out report/shader_fresnel.md``).
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

from basis import default_basis
from basis.fresnel import fresnel_kernel
from basis.gulbrandsen import gulbrandsen_to_nk
from basis.models import fresnel_model
from basis.storage import shipped_path
from basis.training import holdout_materials
from benchmarks.gpu_compiler import compiler_estimates
from benchmarks.output import machine, publish
from handoff.exr import read_lut
from handoff.shaders import (
    ATLAS_INCLUDE_STEM,
    coefficients_per_pixel_gulbrandsen,
    coefficients_per_pixel_gulbrandsen_table,
    coefficients_per_pixel_model,
    coefficients_per_pixel_nk,
    coefficients_per_pixel_nk_table,
    shader_constants,
    shader_includes,
    unwarped_cosine,
    warped_cosine,
)
from handoff.shipped import COEFFICIENT_LUT, CURVE_LUT, LTC_LUT, shipped_tables
from handoff.tables import ATLAS_STEM
from preintegrate.lut import LutGrid, lut_lookup, lut_texel_weights

SIZE = 128
#: Texels of the diagnostic direct-light table: the fewest (in powers of two) at which linear interpolation in the
#: include's warped cosine holds the curves within issue 23's 1e-4 of the spline (5.6e-5; 256 texels miss by
#: 2.3e-4, and no width reaches the include's own 5e-5 below 1024).
CURVE_TABLE_SIZE = 512
#: The artist grid's largest reflectivity: beyond it (r → 1 with g → 0, η ~ 80) no four-term basis holds the curves
#: (``stiff_artist_error`` measures r = 0.95).
ARTIST_R_MAX = 0.9
VERTEX = "#version 330\nin vec2 p; void main() { gl_Position = vec4(p, 0.0, 1.0); }\n"
COMMON = """
uniform sampler2D basisLut; uniform sampler2D schlickLut; uniform sampler2D mapA; uniform sampler2D mapB;
uniform sampler2D mapC; uniform sampler2D coefficientLut; uniform sampler2D curveTable; uniform sampler2D ltcLut;
uniform vec2 size; uniform vec4 cR; uniform vec4 cG; uniform vec4 cB; uniform float roughness;
out vec4 colour;
const vec3 EYE = vec3(0.0, 0.0, 4.0), LIGHT = vec3(1.5, 2.0, 3.0);  // per-pixel V and L: nothing folds to a constant
float pow5(float x) { float x2 = x * x; return x2 * x2 * x; }  // Schlick's power as engines write it (Filament, HDRP, UE)
float ggx(float NdotH, float a) { float a2 = a * a; float d = NdotH * NdotH * (a2 - 1.0) + 1.0; return a2 / (3.14159265 * d * d); }
float smithV(float NdotV, float NdotL, float a) {
    float a2 = a * a;
    return 0.5 / (NdotL * sqrt(NdotV * NdotV * (1.0 - a2) + a2) + NdotV * sqrt(NdotL * NdotL * (1.0 - a2) + a2));
}
void main() {
    vec2 uv = gl_FragCoord.xy / size;
    vec2 q = uv * 2.0 - 1.0;
    float z2 = 1.0 - dot(q, q);
    vec3 N = normalize(vec3(q, sqrt(max(z2, 1e-4))));
    vec3 V = normalize(EYE - N), L = normalize(LIGHT - N), H = normalize(V + L);  // N: the unit sphere's point
    float NdotV = max(N.z, 1e-4), NdotL = max(dot(N, L), 0.0), NdotH = max(dot(N, H), 0.0), VdotH = max(dot(V, H), 0.0);
    vec3 prefiltered = 0.5 + 0.5 * N;
    vec3 Fbar, F;
    {variant}
    float a = roughness * roughness;
    colour = vec4(prefiltered * Fbar + F * (ggx(NdotH, a) * smithV(NdotV, NdotL, a) * NdotL), 1.0);
}
"""
VARIANTS = {
    "schlick": """vec3 F0 = texture(mapA, uv).rgb;
    vec2 sb = textureLod(schlickLut, vec2(NdotV, roughness), 0.0).rg;
    Fbar = F0 * sb.x + sb.y;
    F = F0 + (1.0 - F0) * pow5(1.0 - VdotH);""",
    "basis uniform": """Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, cR, cG, cB);
    F = fresnelBasisDirect(VdotH, cR, cG, cB);""",
    "basis per pixel (eta, kappa)": """vec4 pR, pG, pB;
    fresnelCoefficientsNK3(texture(mapA, uv).rgb, texture(mapB, uv).rgb, pR, pG, pB);
    Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, pR, pG, pB);
    F = fresnelBasisDirect(VdotH, pR, pG, pB);""",
    "basis per pixel (r, g)": """vec4 pR, pG, pB;
    fresnelCoefficientsGulbrandsen3(texture(mapA, uv).rgb, texture(mapB, uv).rgb, pR, pG, pB);
    Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, pR, pG, pB);
    F = fresnelBasisDirect(VdotH, pR, pG, pB);""",
    "basis per pixel (r, g), tables": """vec4 pR, pG, pB;
    fresnelCoefficientsGulbrandsenTable3(coefficientLut, texture(mapA, uv).rgb, texture(mapB, uv).rgb, pR, pG, pB);
    Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, pR, pG, pB);
    F = fresnelBasisDirectTable(curveTable, VdotH, pR, pG, pB);""",
    "basis per pixel (eta, kappa), tables": """vec3 eta = texture(mapA, uv).rgb, kappa = texture(mapB, uv).rgb;
    vec4 pR = fresnelCoefficientsNKTable(coefficientLut, eta.r, kappa.r);
    vec4 pG = fresnelCoefficientsNKTable(coefficientLut, eta.g, kappa.g);
    vec4 pB = fresnelCoefficientsNKTable(coefficientLut, eta.b, kappa.b);
    Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, pR, pG, pB);
    F = fresnelBasisDirectTable(curveTable, VdotH, pR, pG, pB);""",
    "basis uniform, curve table": """Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, cR, cG, cB);
    F = fresnelBasisDirectTable(curveTable, VdotH, cR, cG, cB);""",
    "basis per pixel (F0, F82 tint)": """vec3 f0 = texture(mapA, uv).rgb, tint = texture(mapB, uv).rgb;
    vec4 pR = fresnelCoefficientsF82Tint(f0.r, tint.r), pG = fresnelCoefficientsF82Tint(f0.g, tint.g);
    vec4 pB = fresnelCoefficientsF82Tint(f0.b, tint.b);
    Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, pR, pG, pB);
    F = fresnelBasisDirect(VdotH, pR, pG, pB);""",
    "schlick, two textures": """vec3 F0 = texture(mapA, uv).rgb * texture(mapB, uv).rgb;
    vec2 sb = textureLod(schlickLut, vec2(NdotV, roughness), 0.0).rg;
    Fbar = F0 * sb.x + sb.y;
    F = F0 + (1.0 - F0) * pow5(1.0 - VdotH);""",
    "exact x E": """vec3 eta = texture(mapA, uv).rgb, kappa = texture(mapB, uv).rgb;
    float E = textureLod(schlickLut, vec2(NdotV, roughness), 0.0).b;
    Fbar = E * vec3(fresnelExact(NdotV, eta.r, kappa.r), fresnelExact(NdotV, eta.g, kappa.g), fresnelExact(NdotV, eta.b, kappa.b));
    F = vec3(fresnelExact(VdotH, eta.r, kappa.r), fresnelExact(VdotH, eta.g, kappa.g), fresnelExact(VdotH, eta.b, kappa.b));""",
}
_GULBRANDSEN = VARIANTS["basis per pixel (r, g)"]
_CHANNELS = """vec3 r = fresnelSanitize3(texture(mapA, uv).rgb, 0.9999), g = fresnelSanitize3(texture(mapB, uv).rgb, 1.0);
    vec4 pR = {solve}(r.x, g.x), pG = {solve}(r.y, g.y), pB = {solve}(r.z, g.z);
    Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, pR, pG, pB);
    F = fresnelBasisDirect(VdotH, pR, pG, pB);"""
#: Where the (r, g) pass' cost goes: the same pass with one part taken out at a time (no product renders these).
DECOMPOSITION = {
    "(r, g) reading one texture": _GULBRANDSEN.replace("texture(mapB, uv).rgb", "texture(mapA, uv).brg"),
    "(r, g) without Gulbrandsen's mapping": _CHANNELS.format(solve="solveWithoutMapping"),
    "(r, g) without the fit-angle Fresnel": _CHANNELS.format(solve="mappingWithoutFit"),
}
DIAGNOSTICS = """
vec3 fresnelSanitize3(vec3 x, float hi) {
    return vec3(fresnelSanitize(x.x, 0.0, 0.0, hi), fresnelSanitize(x.y, 0.0, 0.0, hi), fresnelSanitize(x.z, 0.0, 0.0, hi));
}
vec4 solveWithoutMapping(float r, float g) { return fresnelCoefficientsSolve(r, 1.0 + r, g); }  // eta, kappa^2 stand-ins
vec4 mappingWithoutFit(float r, float g) {
    vec2 nk2 = fresnelGulbrandsenToEtaKappa2(r, g);
    return vec4(r, 1.0 - r, 0.01 * nk2);  // the mapping's outputs, kept alive, in place of c2, c3
}
uniform sampler2D curveLut;
vec3 directFromTable(float VdotH, vec4 cR, vec4 cG, vec4 cB) {  // b_0 .. b_3 at texel centres of the warped cosine
    float mu = fresnelSanitize(VdotH, 1.0, 0.0, 1.0);
    float x = mu * (1.0 + FRESNEL_CURVE_WARP) / (1.0 + FRESNEL_CURVE_WARP * mu);
    vec4 b = textureLod(curveLut, vec2(x * CURVE_TABLE_SCALE + CURVE_TABLE_OFFSET, 0.5), 0.0);
    return vec3(dot(cR, b), dot(cG, b), dot(cB, b));
}
"""
#: The (r, g) pass with the other direct-light form (diagnostics, not products).
#: The table form's row name (its accuracy is the table's; the other alternative evaluates no basis curve).
CURVE_TABLE_VARIANT = f"(r, g), direct light from a {CURVE_TABLE_SIZE}-texel table"
DIRECT_ALTERNATIVES = {
    CURVE_TABLE_VARIANT: _GULBRANDSEN.replace("fresnelBasisDirect", "directFromTable"),
    "(r, g), Schlick's F from c0 for the light (no curves: what they cost)": _GULBRANDSEN.replace(
        "F = fresnelBasisDirect(VdotH, pR, pG, pB);",
        "F = vec3(pR.x, pG.x, pB.x) + vec3(pR.y, pG.y, pB.y) * pow5(1.0 - VdotH);",
    ),
}
#: The coefficients solved offline: three RGBA textures, one per colour channel (what the per-pixel solve is
#: weighed against; linear filtering of coefficients filters F itself, which is linear in them).
SOLVED_OFFLINE = {
    "basis, coefficients from three textures (solved offline)": """vec4 pR = texture(mapA, uv), pG = texture(mapB, uv), pB = texture(mapC, uv);
    Fbar = fresnelBasisSplitSumRGB(basisLut, NdotV, roughness, pR, pG, pB);
    F = fresnelBasisDirect(VdotH, pR, pG, pB);""",
}
#: The tables' pass through the atlas include, every table the pass reads from one texture (``build --atlas``): what
#: one sampler costs against three.
ATLAS_VARIANT = "basis per pixel (r, g), tables in one atlas (one sampler)"
IN_ATLAS = {ATLAS_VARIANT: VARIANTS["basis per pixel (r, g), tables"]}
#: Every pass the benchmark times and compiles.
ALL_VARIANTS = {**VARIANTS, **DECOMPOSITION, **DIRECT_ALTERNATIVES, **SOLVED_OFFLINE, **IN_ATLAS}
SPLIT_SUM = """
vec3 fresnelBasisSplitSumRGB(sampler2D lut, float NdotV, float r, vec4 cR, vec4 cG, vec4 cB) {
    vec4 b = textureLod(lut, fresnelAtlasBasis(vec2(NdotV, r)), 0.0);  // the identity but in an atlas include
    return vec3(dot(cR, b), dot(cG, b), dot(cB, b));
}
"""


def fragment_source(variant: str, version: str = "330", atlas: bool = False, include: str | None = None) -> str:
    """The whole fragment shader of one variant: the generated include (``atlas``: the shipped atlas include;
    ``include``: this text instead, e.g. an older commit's), the diagnostics and :data:`COMMON` around the variant's
    lines (GLSL ``version``: 330 for llvmpipe, 450 for a Vulkan compiler)."""
    if include is None:
        include = (
            shipped_path(f"{ATLAS_INCLUDE_STEM}.glsl").read_text(encoding="utf-8")
            if atlas
            else dict(shader_includes())["fresnel_basis.glsl"]
        )
    return (
        f"#version {version}\n"
        + include
        + f"const float CURVE_TABLE_SCALE = {(CURVE_TABLE_SIZE - 1) / CURVE_TABLE_SIZE!r};\n"
        + f"const float CURVE_TABLE_OFFSET = {0.5 / CURVE_TABLE_SIZE!r};\n"
        + SPLIT_SUM
        + DIAGNOSTICS
        + COMMON.replace("{variant}", variant)
    )


def gpu_compiler_estimates() -> tuple[dict[str, dict[str, int]], str]:
    """ACO's statistics of every variant's fragment shader compiled for AMD RDNA 2 (:mod:`benchmarks.gpu_compiler`),
    and the compiler in words: a GPU's own compiler on the same shaders, where llvmpipe's software texture filtering
    dilutes the arithmetic."""
    return compiler_estimates(
        {name: fragment_source(body, "450", name in IN_ATLAS) for name, body in ALL_VARIANTS.items()}
    )


def rgba_upload(table: np.ndarray) -> np.ndarray:
    """A three-channel table padded to four, as an engine uploads it: WebGPU has no RGB formats, and Vulkan drivers
    rarely filter R32G32B32_SFLOAT (llvmpipe samples it through a slower path: the (r, g) tables' pass cost 3.36 ×
    Schlick's with an RGB32F coefficient table, 2.69 × with RGBA32F)."""
    if table.shape[-1] != 3:
        return table
    return np.concatenate([table, np.zeros(table.shape[:-1] + (1,), table.dtype)], axis=-1)


def smooth_map(rng, size: int = 256, cells: int = 8) -> np.ndarray:
    """(size, size, 4) random values in [0.05, 0.95] on a (cells + 1)² grid, interpolated linearly between them."""
    grid = rng.uniform(0.05, 0.95, (cells + 1, cells + 1, 4))
    # the linear interpolation's weights along one axis, (size, cells + 1): bilinear is the same along both
    weights = np.stack(
        [np.interp(np.linspace(0.0, cells, size), np.arange(cells + 1), e) for e in np.eye(cells + 1)], 1
    )
    return np.einsum("ia,abc,jb->ijc", weights, grid, weights)


#: The samplers of :func:`frame_times`' passes and their texture units (unit 8 holds the atlas; ltcLut, the shipped
#: LTC table, is read by the area-light passes of benchmarks.area_light_set).
TEXTURE_UNITS = {
    "basisLut": 0,
    "schlickLut": 1,
    "mapA": 2,
    "mapB": 3,
    "curveLut": 4,
    "mapC": 5,
    "coefficientLut": 6,
    "curveTable": 7,
    "ltcLut": 9,
}
#: The texture units that hold material maps, the rest tables.
MAP_UNITS = tuple(TEXTURE_UNITS[name] for name in ("mapA", "mapB", "mapC"))


def frame_times(
    width: int,
    height: int,
    frames: int,
    rounds: int,
    variants: dict[str, str] | None = None,
    includes: dict[str, str] | None = None,
    texel: str = "f4",
    maps: str | None = None,
    smooth: bool = False,
) -> tuple[dict[str, float], str]:
    """Median seconds per frame of each variant (default: :data:`ALL_VARIANTS`; rounds alternate the variants; a
    variant named in ``includes`` compiled with that include) and the renderer's name; every table uploaded as
    ``texel`` (moderngl's dtype: ``"f4"`` 32-bit floats, as the include asks; ``"f2"`` half floats, to see what
    filtering 32-bit texels costs) and the material maps as ``maps`` (the same by default; ``"f1"`` 8-bit unsigned
    normalised, as an engine ships painted maps); the maps' texels independent random values (every neighbour a
    different material, the per-pixel tables read incoherently), or with ``smooth`` random values on a 9 × 9 grid
    interpolated linearly (regions that blend, as painted maps mostly are)."""
    if texel not in ("f4", "f2"):
        raise ValueError(f"texel must be 'f4' or 'f2', not {texel!r}")
    maps = texel if maps is None else maps
    if maps not in ("f4", "f2", "f1"):
        raise ValueError(f"maps must be 'f4', 'f2' or 'f1', not {maps!r}")
    variants = ALL_VARIANTS if variants is None else variants
    includes = {} if includes is None else includes
    import moderngl

    context = moderngl.create_standalone_context(backend="egl")
    try:
        rng = np.random.default_rng(3)
        painted = [smooth_map(rng) if smooth else rng.uniform(0.05, 0.95, (256, 256, 4)) for _ in range(3)]
        textures = [
            *shipped_tables(),
            *painted[:2],
            curve_table(default_basis(), shader_constants()),
            painted[2],
            *(read_lut(shipped_path(name))[0] for name in (COEFFICIENT_LUT, CURVE_LUT, f"{ATLAS_STEM}.exr", LTC_LUT)),
        ]
        for unit, table in enumerate(textures):
            table = rgba_upload(table)
            dtype = maps if unit in MAP_UNITS else texel
            data = np.round(255.0 * table).astype("u1") if dtype == "f1" else np.ascontiguousarray(table, dtype)
            texture = context.texture(table.shape[1::-1], table.shape[2], data.tobytes(), dtype=dtype)
            texture.repeat_x = texture.repeat_y = False
            texture.use(unit)
        target = context.texture((width, height), 4, dtype="f2")
        framebuffer = context.framebuffer(color_attachments=[target])
        framebuffer.use()
        quad = context.buffer(np.array([-1, -1, 1, -1, -1, 1, 1, 1], dtype="f4").tobytes())
        passes = {}
        for name, variant in variants.items():
            program = context.program(
                vertex_shader=VERTEX,
                fragment_shader=fragment_source(variant, atlas=name in IN_ATLAS, include=includes.get(name)),
            )
            for uniform, index in TEXTURE_UNITS.items():
                if uniform in program:  # an atlas pass reads its three tables from the atlas, unit 8
                    atlased = name in IN_ATLAS and uniform in ("basisLut", "coefficientLut", "curveTable")
                    program[uniform] = 8 if atlased else index
            for uniform, value in (
                ("size", (width, height)),
                ("roughness", 0.5),
                ("cR", (0.9, 0.1, -0.02, 0.01)),
                ("cG", (0.75, 0.25, 0.01, 0.01)),
                ("cB", (0.42, 0.58, 0.03, 0.0)),
            ):
                if uniform in program:
                    program[uniform] = value
            passes[name] = context.vertex_array(program, [(quad, "2f", "p")])
        for draw in passes.values():  # warm-up: compile and first frame
            draw.render(moderngl.TRIANGLE_STRIP)
        context.finish()
        samples = {name: [] for name in passes}
        for _ in range(rounds):
            for name, draw in passes.items():
                started = time.perf_counter()
                for _ in range(frames):
                    draw.render(moderngl.TRIANGLE_STRIP)
                context.finish()
                samples[name].append((time.perf_counter() - started) / frames)
        return {name: statistics.median(values) for name, values in samples.items()}, context.info["GL_RENDERER"]
    finally:
        context.release()


def curve_table(basis, constants) -> np.ndarray:
    """(1, :data:`CURVE_TABLE_SIZE`, K): b_0 … b_3 of ``basis`` at evenly spaced points of the include's warped cosine
    x = μ (1 + w)/(1 + w μ), end points on the first and last texel centres."""
    return basis.evaluate_mu(unwarped_cosine(np.linspace(0.0, 1.0, CURVE_TABLE_SIZE), constants.curve_warp))[None]


#: Bits of the weight between two texels in a GPU's linear filter: Direct3D asks for at least 8 (its subtexel
#: precision), and GPUs that filter with 8-bit weights round a lookup to 1/256 of a texel.
FILTER_WEIGHT_BITS = 8


def curve_table_error(weight_bits: int | None = None) -> float:
    """max over μ and k of |linear interpolation of :func:`curve_table` in x − the basis' spline| (float64; the
    include's polynomial is ShaderConstants.curve_error on the same measure); with ``weight_bits``, the interpolation
    weight rounded to that many bits, as a GPU's filter rounds it."""
    basis, constants = default_basis(), shader_constants()
    mu = np.linspace(0.0, 1.0, 100001)
    table, exact = curve_table(basis, constants)[0], basis.evaluate_mu(mu)
    position = warped_cosine(mu, constants.curve_warp) * (CURVE_TABLE_SIZE - 1)
    left = np.minimum(np.floor(position).astype(int), CURVE_TABLE_SIZE - 2)
    weight = position - left
    if weight_bits is not None:
        weight = np.round(weight * 2.0**weight_bits) / 2.0**weight_bits
    interpolated = table[left] * (1.0 - weight[:, None]) + table[left + 1] * weight[:, None]
    return float(np.max(np.abs(interpolated - exact)))


def errors() -> dict[str, tuple[float, float]]:
    """(max |ΔF| over θ, max |ΔF̄| over the table) of each variant on the materials it is for."""
    basis = default_basis()
    theta = basis.theta
    mu = np.cos(theta)
    weights = lut_texel_weights(theta, SIZE)  # (SIZE², M): the exact split sum of any curve on theta
    basis_table, schlick_table = shipped_tables()
    grid = LutGrid(SIZE, SIZE)  # the shipped tables' grid
    nv, rr = np.meshgrid(grid.mu_o, grid.roughness)
    basis_fbar = basis_table.reshape(-1, 4)  # at a texel the lookup is the texel
    schlick_fbar = schlick_table.reshape(-1, 4)

    def measure(curves: np.ndarray, coefficients: np.ndarray) -> tuple[float, float]:
        """curves (N, M) exact; coefficients (N, 4): the basis' F and F̄ errors."""
        fitted = coefficients @ basis.curves
        return float(np.max(np.abs(fitted - curves))), float(
            np.max(np.abs(coefficients @ basis_fbar.T - curves @ weights.T))
        )

    metals = holdout_materials()["metals"]
    eta, kappa = metals
    metal_curves = fresnel_kernel(mu, eta[:, None], kappa[:, None])
    r, g = np.meshgrid(np.linspace(0.04, ARTIST_R_MAX, 12), np.linspace(0.0, 1.0, 11))
    r, g = r.ravel(), g.ravel()
    artist_curves = fresnel_kernel(mu, *(value[:, None] for value in gulbrandsen_to_nk(r, g)))
    f0, tint = np.meshgrid(np.linspace(0.04, 0.95, 10), np.linspace(0.0, 1.0, 9))
    f0, tint = f0.ravel(), tint.ravel()
    tint_curves = fresnel_model("adobe").evaluate(mu[None, :], f0=f0[:, None], tint=tint[:, None])
    f0_metals = metal_curves[:, 0]
    schlick = f0_metals[:, None] + (1.0 - f0_metals[:, None]) * (1.0 - mu) ** 5
    schlick_f = float(np.max(np.abs(schlick - metal_curves)))
    schlick_fbar = float(
        np.max(np.abs(f0_metals[:, None] * schlick_fbar[:, 0] + schlick_fbar[:, 1] - metal_curves @ weights.T))
    )
    e_table = lut_lookup(schlick_table, nv.ravel(), rr.ravel())[:, 2]
    coefficient_lut = read_lut(shipped_path(COEFFICIENT_LUT))[0]
    exact_e = float(np.max(np.abs(metal_curves_at(nv.ravel(), eta, kappa) * e_table - metal_curves @ weights.T)))
    return {
        "schlick": (schlick_f, schlick_fbar),
        "basis uniform": measure(metal_curves, coefficients_per_pixel_nk(eta, kappa)),
        "basis per pixel (eta, kappa)": measure(metal_curves, coefficients_per_pixel_nk(eta, kappa)),
        "basis per pixel (r, g)": measure(artist_curves, coefficients_per_pixel_gulbrandsen(r, g)),
        "basis per pixel (r, g), tables": measure(
            artist_curves, coefficients_per_pixel_gulbrandsen_table(coefficient_lut, r, g)
        ),
        "basis per pixel (eta, kappa), tables": measure(
            metal_curves, coefficients_per_pixel_nk_table(coefficient_lut, eta, kappa)
        ),
        "basis uniform, curve table": measure(metal_curves, coefficients_per_pixel_nk(eta, kappa)),
        "basis per pixel (F0, F82 tint)": measure(
            tint_curves, coefficients_per_pixel_model("f82-tint", f0=f0, tint=tint)
        ),
        "schlick, two textures": (schlick_f, schlick_fbar),
        "exact x E": (0.0, exact_e),
    }


def projection_errors() -> dict[str, tuple[float, float]]:
    """Per linear model of the include: (max |ΔF| over θ, max |ΔF̄| over the table) of its projection onto the basis
    against the model's own linear form, over a grid of its parameters in [0, 1]: the price of one shader for every
    model; beyond it, ``fresnel-lut build --model NAME`` writes the model's exact table."""
    from handoff.shaders import PER_PIXEL_MODELS, linear_model_curve

    basis = default_basis()
    mu = np.cos(basis.theta)
    weights = lut_texel_weights(basis.theta, SIZE)
    basis_fbar = shipped_tables()[0].reshape(-1, 4)
    grid = np.linspace(0.0, 1.0, 11)
    result = {}
    for model, (names, _) in PER_PIXEL_MODELS.items():
        values = np.meshgrid(*([grid] * len(names)))
        parameters = {name: value.ravel() for name, value in zip(names, values)}
        coefficients = coefficients_per_pixel_model(model, **parameters)
        curves = linear_model_curve(model, mu[None, :], **{name: value[:, None] for name, value in parameters.items()})
        result[model] = (
            float(np.max(np.abs(coefficients @ basis.curves - curves))),
            float(np.max(np.abs(coefficients @ basis_fbar.T - curves @ weights.T))),
        )
    return result


def stiff_artist_error() -> float:
    """max |ΔF| over θ of the (r, g) solve at r = 0.95, g in [0, 1] (the stiff corner beyond the artist grid)."""
    basis = default_basis()
    g = np.linspace(0.0, 1.0, 11)
    r = np.full_like(g, 0.95)
    curves = fresnel_kernel(np.cos(basis.theta), *(value[:, None] for value in gulbrandsen_to_nk(r, g)))
    return float(np.max(np.abs(coefficients_per_pixel_gulbrandsen(r, g) @ basis.curves - curves)))


def metal_curves_at(mu: np.ndarray, eta: np.ndarray, kappa: np.ndarray) -> np.ndarray:
    """(N, P): the exact curve of each material at the view cosines ``mu``."""
    return fresnel_kernel(mu[None, :], eta[:, None], kappa[:, None])


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--width", type=int, default=1280)
    parser.add_argument("--height", type=int, default=720)
    parser.add_argument("--frames", type=int, default=4, help="frames per variant per round (default 4)")
    parser.add_argument("--rounds", type=int, default=15, help="rounds alternating the variants (default 15)")
    parser.add_argument(
        "--repeats", type=int, default=3, help="whole measurements, each with its own context (default 3)"
    )
    parser.add_argument("--out", type=Path, default=None, help="also write the Markdown table here")
    arguments = parser.parse_args(argv)
    runs = [
        frame_times(arguments.width, arguments.height, arguments.frames, arguments.rounds)
        for _ in range(max(1, arguments.repeats))
    ]
    renderer = runs[0][1]
    measured = errors()
    estimates, compiler = gpu_compiler_estimates()
    lines = [
        f"Renderer: {renderer} on {machine()}; {arguments.width} x {arguments.height}, median of {arguments.rounds} rounds of "
        f"{arguments.frames} frames, variants alternated, {len(runs)} measurements: the median ratio and its range "
        "over them (the machine is shared: a ratio moves by about 0.1 from one measurement to the next). "
        f"GPU compiler: ACO (Mesa's AMD compiler) on {compiler} (AMD RDNA 2) through RADV's device-less mode, the same "
        "fragment shaders as GLSL 4.50: its instructions and its inverse throughput (cycles per 64 pixels of the busiest "
        "unit, texture latency hidden) as a ratio to Schlick's, a static estimate, not a timing. "
        "Command: `python -m benchmarks.shader_cost`.",
        "",
        "| variant | max abs dF over theta | max abs dFbar over the table | ms per frame | cost / Schlick | range "
        "| RDNA 2 instructions | RDNA 2 throughput cost / Schlick |",
        "|---|---|---|---|---|---|---|---|",
    ]

    def cost(name: str) -> tuple[float, str]:
        """Median ms per frame, and the median ratio to Schlick with its range."""
        ratios = [times[name] / times["schlick"] for times, _ in runs]
        milliseconds = statistics.median(1e3 * times[name] for times, _ in runs)
        return milliseconds, f"{statistics.median(ratios):.2f} | {min(ratios):.2f}-{max(ratios):.2f}"

    def compiled(name: str) -> str:
        """ACO's instructions and inverse-throughput ratio to Schlick's, as two cells."""
        throughput = estimates[name]["Inverse Throughput"] / estimates["schlick"]["Inverse Throughput"]
        return f"{estimates[name]['Instructions']} | {throughput:.2f}"

    for name in VARIANTS:
        f_error, fbar_error = measured[name]
        milliseconds, ratio = cost(name)
        lines.append(f"| {name} | {f_error:.2e} | {fbar_error:.2e} | {milliseconds:.2f} | {ratio} | {compiled(name)} |")
    lines += [
        "",
        "Where the (r, g) pass' cost goes: the same pass with one part taken out at a time (diagnostics, not products; "
        "the difference is the part's cost as a fraction of Schlick's pass):",
        "",
        "| variant | ms per frame | cost / Schlick | range | part's cost / Schlick | RDNA 2 instructions "
        "| RDNA 2 throughput cost / Schlick | part's RDNA 2 cost / Schlick |",
        "|---|---|---|---|---|---|---|---|",
    ]
    full = [times["basis per pixel (r, g)"] / times["schlick"] for times, _ in runs]
    full_estimate = estimates["basis per pixel (r, g)"]["Inverse Throughput"]
    for name in DECOMPOSITION:
        milliseconds, ratio = cost(name)
        part = statistics.median(f - times[name] / times["schlick"] for f, (times, _) in zip(full, runs))
        part_estimate = (full_estimate - estimates[name]["Inverse Throughput"]) / estimates["schlick"][
            "Inverse Throughput"
        ]
        lines.append(f"| {name} | {milliseconds:.2f} | {ratio} | {part:.2f} | {compiled(name)} | {part_estimate:.2f} |")
    constants, table_error = shader_constants(), curve_table_error()
    coarse_filter_error = curve_table_error(FILTER_WEIGHT_BITS)
    per_pixel_ms, per_pixel_ratio = cost("basis per pixel (r, g)")
    lines += [
        "",
        "Direct light: the include's polynomial against a table (max abs db: the curves b_k against the basis' "
        "spline over theta, float64):",
        "",
        "| direct light | max abs db over theta | ms per frame | cost / Schlick | range | RDNA 2 instructions "
        "| RDNA 2 throughput cost / Schlick |",
        "|---|---|---|---|---|---|---|",
        f"| polynomial of degree {constants.curve_degree} in the warped cosine (the include; the (r, g) row "
        f"above) | {constants.curve_error:.1e} | {per_pixel_ms:.2f} | {per_pixel_ratio} "
        f"| {compiled('basis per pixel (r, g)')} |",
    ]
    for name in DIRECT_ALTERNATIVES:
        milliseconds, ratio = cost(name)
        accuracy = (
            f"{table_error:.1e} ({coarse_filter_error:.1e} with {FILTER_WEIGHT_BITS}-bit filter weights)"
            if name == CURVE_TABLE_VARIANT
            else "not the basis' curves"
        )
        lines.append(f"| {name} | {accuracy} | {milliseconds:.2f} | {ratio} | {compiled(name)} |")
    lines += [
        "",
        "The solve per pixel against coefficients solved offline (three RGBA textures, one per channel, as an engine "
        "that solves its material maps at import would read them):",
        "",
        "| coefficients | ms per frame | cost / Schlick | range | RDNA 2 instructions | RDNA 2 throughput cost / Schlick |",
        "|---|---|---|---|---|---|",
        f"| solved per pixel from (r, g) (the include; the (r, g) row above) | {per_pixel_ms:.2f} | {per_pixel_ratio} "
        f"| {compiled('basis per pixel (r, g)')} |",
    ]
    for name in SOLVED_OFFLINE:
        milliseconds, ratio = cost(name)
        lines.append(f"| {name} | {milliseconds:.2f} | {ratio} | {compiled(name)} |")
    lines += [
        "",
        "One sampler: the tables' pass reading its three tables (basis, coefficients, curves) from the atlas of "
        "`build --atlas` through `fresnel_basis_atlas.glsl` (one multiply-add per read of the basis table; the per-pixel tables' constants include their rectangles), "
        "against three textures:",
        "",
        "| tables | ms per frame | cost / Schlick | range | RDNA 2 instructions | RDNA 2 throughput cost / Schlick |",
        "|---|---|---|---|---|---|",
    ]
    for name in ("basis per pixel (r, g), tables", ATLAS_VARIANT):
        milliseconds, ratio = cost(name)
        lines.append(f"| {name} | {milliseconds:.2f} | {ratio} | {compiled(name)} |")
    lines += [
        "",
        "Projection of each linear model onto the basis (its parameters on an 11-point grid in [0, 1] each; "
        "against the model's own linear form; beyond this, `fresnel-lut build --model NAME` writes its exact table):",
        "",
        "| model | max abs dF over theta | max abs dFbar over the table |",
        "|---|---|---|",
    ]
    lines += [f"| {model} | {f:.2e} | {fbar:.2e} |" for model, (f, fbar) in projection_errors().items()]
    lines += [
        "",
        f"(r, g) on r in [0.04, {ARTIST_R_MAX}], g in [0, 1]; at r = 0.95 the same solve misses by "
        f"{stiff_artist_error():.2f} (a four-term basis' limit, not the shader's). Schlick and exact x E on the "
        "same metals as the (eta, kappa) rows; the F82-tint sweep F0 in [0.04, 0.95], tint in [0, 1].",
    ]
    text = "\n".join(lines) + "\n"
    publish(text, arguments.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
