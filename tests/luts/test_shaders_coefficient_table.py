"""The coefficient-table path (issue 38): ``fresnelCoefficientsGulbrandsenTable`` of the generated include, with the
shipped luts/fresnel_coefficients_rg.exr, run for real on Mesa's llvmpipe (GLSL) and lavapipe (WGSL through wgpu)
against its Python mirror (``handoff.shaders.coefficients_per_pixel_gulbrandsen_table``), over (r, g) spanning the
table, its edges (r = 0, r → 1, g at 0 and 1) and bad values (NaN, ±inf, negative, beyond 1): no NaN or inf, and the
coefficients within 1e-5 of the mirror's exact bilinear weights (float32 coordinates and filtering; measured 3.4e-6 on
both).

Against the float64 model and exact Fresnel: tests/basis/test_coefficient_table.py.
"""

import numpy as np

from basis.storage import shipped_path
from handoff.exr import read_lut
from handoff.shaders import coefficients_per_pixel_gulbrandsen_table, shader_includes
from handoff.shipped import COEFFICIENT_LUT
from tests.conftest import gl_draw, wgpu_compute, wgpu_device

INCLUDES = dict(shader_includes())
TABLE, HEADER = read_lut(shipped_path(COEFFICIENT_LUT))
#: float32 coordinates and filtering against float64 (measured 3.4e-6 on llvmpipe and lavapipe).
TOLERANCE = 1e-5


def _inputs() -> np.ndarray:
    """(1024, 4): r, g in the first two lanes, over the table and its edges and bad values."""
    rng = np.random.default_rng(38)
    r, g = rng.uniform(0.0, 1.0, 1024), rng.uniform(0.0, 1.0, 1024)
    r[:64] = rng.uniform(0.95, 0.9999, 64)  # where the table bends most
    r[64:128] = rng.uniform(0.0, 1e-3, 64)  # η → 1
    special = [0.0, 0.9999, 1.0, np.nan, np.inf, -np.inf, -0.5, 2.0, 1e-12, 0.5]
    r[128 : 128 + 10], g[138 : 138 + 10] = special, special
    g[148:158] = [0.0, 1.0, 0.0, 1.0, np.nan, 0.0, 1.0, 0.5, 1.0, 0.0]
    return np.stack([r, g, np.zeros_like(r), np.zeros_like(r)], axis=-1).astype(np.float32)


def _assert(outputs: np.ndarray, inputs: np.ndarray, where: str) -> None:
    expected = coefficients_per_pixel_gulbrandsen_table(TABLE, inputs[:, 0], inputs[:, 1])
    assert np.all(np.isfinite(outputs)), f"{where}: non-finite output"
    error = float(np.max(np.abs(outputs - expected)))
    assert error <= TOLERANCE, f"{where}: max |GPU - mirror| {error:.3g}"


GLSL_MAIN = """
uniform sampler2D inputs;
uniform sampler2D coefficientLut;
out vec4 coefficients;
void main() {
    vec4 a = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);
    coefficients = fresnelCoefficientsGulbrandsenTable(coefficientLut, a.x, a.y);
}
"""


def test_glsl_on_mesa_llvmpipe_matches_the_mirror():
    inputs = _inputs()
    (outputs,) = gl_draw(
        "#version 330\n" + INCLUDES["fresnel_basis.glsl"] + GLSL_MAIN,
        [inputs.reshape(32, 32, 4), TABLE],
        {"inputs": 0, "coefficientLut": 1},
        1,
    )
    _assert(outputs, inputs, "llvmpipe")


WGSL_MAIN = """
@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4f>;
@group(0) @binding(2) var coefficientLut: texture_2d<f32>;
@group(0) @binding(3) var linearClamp: sampler;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&inputs)) { return; }
    outputs[i] = fresnelCoefficientsGulbrandsenTable(coefficientLut, linearClamp, inputs[i].x, inputs[i].y);
}
"""


def test_wgsl_on_webgpu_lavapipe_matches_the_mirror(monkeypatch):
    import wgpu

    inputs = _inputs()
    device = wgpu_device(monkeypatch, features=("float32-filterable",))
    usage = wgpu.BufferUsage
    input_buffer = device.create_buffer_with_data(data=inputs.tobytes(), usage=usage.STORAGE)
    output_buffer = device.create_buffer(size=len(inputs) * 16, usage=usage.STORAGE | usage.COPY_SRC)
    rgba = np.zeros(TABLE.shape[:2] + (4,), np.float32)
    rgba[..., : TABLE.shape[2]] = TABLE
    texture = device.create_texture(
        size=(TABLE.shape[1], TABLE.shape[0], 1),
        format=wgpu.TextureFormat.rgba32float,
        usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST,
    )
    device.queue.write_texture(
        {"texture": texture},
        rgba.tobytes(),
        {"bytes_per_row": TABLE.shape[1] * 16, "rows_per_image": TABLE.shape[0]},
        (TABLE.shape[1], TABLE.shape[0], 1),
    )
    sampler = device.create_sampler(mag_filter="linear", min_filter="linear")
    data = wgpu_compute(
        device,
        INCLUDES["fresnel_basis.wgsl"] + WGSL_MAIN,
        [{"buffer": input_buffer}, {"buffer": output_buffer}, texture.create_view(), sampler],
        output_buffer,
        len(inputs),
    )
    _assert(np.frombuffer(data, np.float32).reshape(len(inputs), 4), inputs, "lavapipe")


def test_the_table_is_the_shipped_basis_and_its_axes():
    """The header names the include's basis and the axes the include addresses."""
    assert HEADER["basis_hash"] in INCLUDES["fresnel_basis.glsl"].splitlines()[0]
    assert TABLE.shape == (128, 512, 2) and "x = r^(1/4) - sqrt(1 - r)/2" in HEADER["convention"]
