"""One sampler (issue 38 item 3): the shipped atlas (luts/fresnel_atlas_rgba.exr) read through its include
(luts/fresnel_basis_atlas.*) gives what the separate tables give through the build's include, on Mesa's llvmpipe
(GLSL) and lavapipe (WGSL): the split sums of the basis, Schlick and a linear model, the coefficient table, the curve
table and a rectangular light (the LTC table), over view cosines and roughnesses that reach every table's edges,
within 1e-6 (float32 coordinates one multiply-add apart; measured 8.3e-7 on the rectangular light, 4.5e-7 elsewhere); and
the packing itself (every table at its rectangle, the
guard ring its edge texels).
"""

import numpy as np

from basis.storage import shipped_path
from handoff.atlas import ATLAS_WIDTH, pack_atlas
from handoff.exr import read_lut
from handoff.shipped import BASIS_LUT, COEFFICIENT_LUT, CURVE_LUT, LTC_LUT, SCHLICK_LUT
from tests.conftest import gl_draw, wgpu_compute, wgpu_device, wgpu_texture_views

ROLES = {
    "basis": BASIS_LUT,
    "schlick": SCHLICK_LUT,
    "ltc": LTC_LUT,
    "coefficients": COEFFICIENT_LUT,
    "curves": CURVE_LUT,
}
TABLES = {role: read_lut(shipped_path(name))[0] for role, name in ROLES.items()}
ATLAS, ATLAS_HEADER = read_lut(shipped_path("fresnel_atlas_rgba.exr"))
INCLUDES = {
    name: shipped_path(name).read_text(encoding="utf-8")
    for name in ("fresnel_basis.glsl", "fresnel_basis_atlas.glsl", "fresnel_basis.wgsl", "fresnel_basis_atlas.wgsl")
}
SAMPLERS = ("basisLut", "schlickLut", "ltcLut", "coefficientLut", "curveLut")


def test_the_packing_holds_every_table_at_its_rectangle_inside_its_edge_texels():
    atlas, layout = pack_atlas(TABLES)
    np.testing.assert_array_equal(ATLAS, atlas.astype(np.float32))
    assert layout.width == ATLAS_WIDTH and layout.describe() in ATLAS_HEADER["convention"]
    for role, table in TABLES.items():
        x0, y0, w, h = layout.rects[role]
        channels = table.shape[2]
        np.testing.assert_array_equal(atlas[y0 : y0 + h, x0 : x0 + w, :channels], table)
        ring = atlas[y0 - 1 : y0 + h + 1, x0 - 1 : x0 + w + 1, :channels]
        np.testing.assert_array_equal(ring, np.pad(table, ((1, 1), (1, 1), (0, 0)), mode="edge"))


def _inputs() -> np.ndarray:
    """(1024, 4): NdotV, r (both over [0, 1] with their ends), Gulbrandsen's r and g."""
    rng = np.random.default_rng(3)
    values = rng.uniform(0.0, 1.0, (1024, 4))
    values[:8, :2] = [[0, 0], [1, 1], [0, 1], [1, 0], [0.5, 0], [0.5, 1], [0, 0.5], [1, 0.5]]
    values[8:16, 2:] = [[0, 0], [0.9999, 1], [0, 1], [0.9999, 0], [0.5, 0], [0.5, 1], [1e-6, 0.5], [0.99, 0.5]]
    return values.astype(np.float32)


GLSL_MAIN = """
uniform sampler2D inputs;
uniform sampler2D basisLut;
uniform sampler2D schlickLut;
uniform sampler2D ltcLut;
uniform sampler2D coefficientLut;
uniform sampler2D curveLut;
layout(location = 0) out vec4 split;
layout(location = 1) out vec4 coefficients;
layout(location = 2) out vec4 light;
void main() {
    vec4 a = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);
    vec4 c = fresnelCoefficientsGulbrandsenTable(coefficientLut, a.z, a.w);
    vec3 w = fresnelLinearF82Tint(a.z, a.w);
    split = vec4(fresnelBasisSplitSum(basisLut, a.x, a.y, c, c, c).x, fresnelSchlickSplitSum(schlickLut, a.x, a.y, vec3(a.z)).x,
                 fresnelLinearSplitSum(schlickLut, a.x, a.y, w, w, w).x, fresnelBasisDirectTable(curveLut, a.x, c, c, c).x);
    coefficients = c;
    vec3 N = vec3(0.0, 0.0, 1.0), V = normalize(vec3(sqrt(max(1.0 - a.x * a.x, 0.0)), 0.0, max(a.x, 1e-3)));
    vec3 corners[4] = vec3[4](vec3(-1.0, -0.5, 2.0), vec3(-1.0, 0.5, 2.0), vec3(1.0, 0.5, 2.0), vec3(1.0, -0.5, 2.0));
    light = vec4(fresnelBasisRectLight(ltcLut, basisLut, N, V, vec3(0.0), corners, a.y, c, c, c), 0.0);
}
"""


def _draw(include: str, textures, units: dict) -> list[np.ndarray]:
    return gl_draw("#version 330\n" + include + GLSL_MAIN, textures, {"inputs": 0, **units}, 3)


def test_glsl_atlas_on_llvmpipe_reads_what_the_separate_tables_read():
    inputs = _inputs().reshape(32, 32, 4)
    separate = _draw(
        INCLUDES["fresnel_basis.glsl"],
        [inputs, *(TABLES[role] for role in ROLES)],
        {sampler: 1 + k for k, sampler in enumerate(SAMPLERS)},
    )
    atlas = _draw(INCLUDES["fresnel_basis_atlas.glsl"], [inputs, ATLAS], {sampler: 1 for sampler in SAMPLERS})
    for name, one, other in zip(("split sums", "coefficients", "rectangular light"), separate, atlas):
        assert np.all(np.isfinite(other)), name
        assert np.max(np.abs(one - other)) <= 1e-6, (name, float(np.max(np.abs(one - other))))


WGSL_MAIN = """
@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4f>;
@group(0) @binding(2) var basisLut: texture_2d<f32>;
@group(0) @binding(3) var schlickLut: texture_2d<f32>;
@group(0) @binding(4) var coefficientLut: texture_2d<f32>;
@group(0) @binding(5) var curveLut: texture_2d<f32>;
@group(0) @binding(6) var linearClamp: sampler;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&inputs)) { return; }
    let a = inputs[i];
    let c = fresnelCoefficientsGulbrandsenTable(coefficientLut, linearClamp, a.z, a.w);
    let w = fresnelLinearF82Tint(a.z, a.w);
    outputs[2u * i] = vec4f(fresnelBasisSplitSum(basisLut, linearClamp, a.x, a.y, c, c, c).x,
                            fresnelSchlickSplitSum(schlickLut, linearClamp, a.x, a.y, vec3f(a.z)).x,
                            fresnelLinearSplitSum(schlickLut, linearClamp, a.x, a.y, w, w, w).x,
                            fresnelBasisDirectTable(curveLut, linearClamp, a.x, c, c, c).x);
    outputs[2u * i + 1u] = c;
}
"""


def _wgsl(device, include: str, textures: list[np.ndarray]) -> np.ndarray:
    import wgpu

    inputs = _inputs()
    usage = wgpu.BufferUsage
    input_buffer = device.create_buffer_with_data(data=inputs.tobytes(), usage=usage.STORAGE)
    output_buffer = device.create_buffer(size=len(inputs) * 32, usage=usage.STORAGE | usage.COPY_SRC)
    views = wgpu_texture_views(device, textures)
    sampler = device.create_sampler(mag_filter="linear", min_filter="linear")
    data = wgpu_compute(
        device,
        include + WGSL_MAIN,
        [{"buffer": input_buffer}, {"buffer": output_buffer}, *views, sampler],
        output_buffer,
        len(inputs),
    )
    return np.frombuffer(data, np.float32).reshape(len(inputs), 2, 4)


def test_wgsl_atlas_on_lavapipe_reads_what_the_separate_tables_read(monkeypatch):
    device = wgpu_device(monkeypatch, features=("float32-filterable",))
    separate = _wgsl(
        device,
        INCLUDES["fresnel_basis.wgsl"],
        [TABLES[role] for role in ("basis", "schlick", "coefficients", "curves")],
    )
    atlas = _wgsl(device, INCLUDES["fresnel_basis_atlas.wgsl"], [ATLAS] * 4)
    assert np.all(np.isfinite(atlas))
    assert np.max(np.abs(separate - atlas)) <= 1e-6, float(np.max(np.abs(separate - atlas)))
