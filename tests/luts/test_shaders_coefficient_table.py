"""The per-pixel tables (issue 38): ``fresnelCoefficientsGulbrandsenTable``, ``fresnelCoefficientsNKTable`` and
``fresnelBasisDirectTable`` of the
generated include, with the shipped luts/fresnel_coefficients_rgb.exr and luts/fresnel_curves_rgb.exr, run for real on
Mesa's llvmpipe (GLSL) and lavapipe (WGSL through wgpu) against their Python mirrors
(``coefficients_per_pixel_gulbrandsen_table``, ``…_nk_table``, ``direct_fresnel_table``), over (r, g) spanning the
table, its edges
(r = 0, r → 1, g at 0 and 1) and bad values (NaN, ±inf, negative, beyond 1), and V·H over [0, 1] and the same bad
values: no NaN or inf, the coefficients and F(V·H) within 1e-5 of the mirrors' exact linear weights (float32
coordinates and filtering; measured 3.4e-6 and 2.5e-6 on both), and r ≤ 0 exactly 0 (the column of r = 0 read alone,
a quarter texel beside its centre). A NaN goes to an end of its range by its sign bit (``fresnelUnitClamp``).

Against the float64 model and exact Fresnel: tests/basis/test_coefficient_table.py.
"""

import numpy as np

from basis.storage import shipped_path
from handoff.exr import read_lut
from handoff.shaders import (
    coefficients_per_pixel_gulbrandsen_table,
    coefficients_per_pixel_nk_table,
    direct_fresnel_table,
    shader_includes,
)
from handoff.shipped import COEFFICIENT_LUT, CURVE_LUT
from tests.conftest import gl_draw, wgpu_compute, wgpu_device, wgpu_texture_views

INCLUDES = dict(shader_includes())
TABLE, HEADER = read_lut(shipped_path(COEFFICIENT_LUT))
CURVES = read_lut(shipped_path(CURVE_LUT))[0]  # (1, 2048, 3)
#: float32 coordinates and filtering against float64 (measured 3.4e-6 on llvmpipe and lavapipe).
TOLERANCE = 1e-5
#: The (η, κ) path: r and g in float32 before the lookup, where y = 1 − (1 − g)^¼ has unbounded slope at g → 1: at
#: η ≤ 1e-3 with κ ~ 5 (r → 0.9999, g within 6e-8 of 1) the coefficients move by 1.7e-4 (measured, both drivers) for
#: inputs float32 cannot tell apart; for η > 1e-3 by 6.1e-5 at most.
NK_TOLERANCE = 2e-4


def _inputs() -> np.ndarray:
    """(1024, 4): r, g in the first two lanes, over the table and its edges and bad values."""
    rng = np.random.default_rng(38)
    r, g = rng.uniform(0.0, 1.0, 1024), rng.uniform(0.0, 1.0, 1024)
    r[:64] = rng.uniform(0.95, 0.9999, 64)  # where the table bends most
    r[64:128] = rng.uniform(0.0, 1e-3, 64)  # η → 1
    special = [0.0, 0.9999, 1.0, np.nan, np.inf, -np.inf, -0.5, 2.0, 1e-12, 0.5]
    r[128 : 128 + 10], g[138 : 138 + 10] = special, special
    g[148:158] = [0.0, 1.0, 0.0, 1.0, np.nan, 0.0, 1.0, 0.5, 1.0, 0.0]
    v_dot_h = rng.uniform(0.0, 1.0, 1024)
    v_dot_h[:10] = special
    v_dot_h[10:74] = rng.uniform(0.0, 1e-3, 64)  # grazing, where the curves bend
    v_dot_h[74] = -np.nan
    return np.stack([r, g, v_dot_h, np.zeros_like(r)], axis=-1).astype(np.float32)


def _nk(inputs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The (η, κ) both passes derive from a texel's first two lanes, in float32 as the GPU does."""
    with np.errstate(invalid="ignore"):
        return inputs[:, 0] * np.float32(4.0), inputs[:, 1] * np.float32(8.0)


def _assert(coefficients: np.ndarray, direct: np.ndarray, nk: np.ndarray, inputs: np.ndarray, where: str) -> None:
    assert np.all(np.isfinite(nk)), f"{where}: non-finite output"
    error = float(np.max(np.abs(nk - coefficients_per_pixel_nk_table(TABLE, *_nk(inputs)))))
    assert error <= NK_TOLERANCE, f"{where}: (eta, kappa) coefficients, max |GPU - mirror| {error:.3g}"
    expected = coefficients_per_pixel_gulbrandsen_table(TABLE, inputs[:, 0], inputs[:, 1])
    assert np.all(np.isfinite(coefficients)) and np.all(np.isfinite(direct)), f"{where}: non-finite output"
    error = float(np.max(np.abs(coefficients - expected)))
    assert error <= TOLERANCE, f"{where}: coefficients, max |GPU - mirror| {error:.3g}"
    dark = inputs[:, 0] <= 0.0
    assert dark.sum() >= 2 and np.all(coefficients[dark] == 0.0), f"{where}: r <= 0 reflects {coefficients[dark]}"
    expected = np.stack(
        [
            direct_fresnel_table(CURVES, expected, inputs[:, 2]),
            direct_fresnel_table(CURVES, expected[::-1], inputs[:, 2]),
        ],
        axis=-1,
    )
    error = float(np.max(np.abs(direct[:, :2] - expected)))
    assert error <= TOLERANCE, f"{where}: direct light from the curve table, max |GPU - mirror| {error:.3g}"


GLSL_MAIN = """
uniform sampler2D inputs;
uniform sampler2D coefficientLut;
uniform sampler2D curveLut;
layout(location = 0) out vec4 coefficients;
layout(location = 1) out vec4 direct;
layout(location = 2) out vec4 nk;
void main() {
    ivec2 texel = ivec2(gl_FragCoord.xy);
    vec4 a = texelFetch(inputs, texel, 0);
    vec4 mirrored = texelFetch(inputs, ivec2(31, 31) - texel, 0);  // the coefficients of the texel opposite
    coefficients = fresnelCoefficientsGulbrandsenTable(coefficientLut, a.x, a.y);
    vec4 other = fresnelCoefficientsGulbrandsenTable(coefficientLut, mirrored.x, mirrored.y);
    direct = vec4(fresnelBasisDirectTable(curveLut, a.z, coefficients, other, other).xy, 0.0, 0.0);
    nk = fresnelCoefficientsNKTable(coefficientLut, a.x * 4.0, a.y * 8.0);
}
"""


def test_glsl_on_mesa_llvmpipe_matches_the_mirror():
    inputs = _inputs()
    coefficients, direct, nk = gl_draw(
        "#version 330\n" + INCLUDES["fresnel_basis.glsl"] + GLSL_MAIN,
        [inputs.reshape(32, 32, 4), TABLE, CURVES],
        {"inputs": 0, "coefficientLut": 1, "curveLut": 2},
        3,
    )
    _assert(coefficients, direct, nk, inputs, "llvmpipe")


WGSL_MAIN = """
@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4f>;
@group(0) @binding(2) var coefficientLut: texture_2d<f32>;
@group(0) @binding(3) var curveLut: texture_2d<f32>;
@group(0) @binding(4) var linearClamp: sampler;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    let count = arrayLength(&inputs);
    if (i >= count) { return; }
    let a = inputs[i];
    let mirrored = inputs[count - 1u - i];  // the texel opposite, as the GLSL pass reads it
    let c = fresnelCoefficientsGulbrandsenTable(coefficientLut, linearClamp, a.x, a.y);
    let other = fresnelCoefficientsGulbrandsenTable(coefficientLut, linearClamp, mirrored.x, mirrored.y);
    outputs[3u * i] = c;
    outputs[3u * i + 1u] = vec4f(fresnelBasisDirectTable(curveLut, linearClamp, a.z, c, other, other).xy, 0.0, 0.0);
    outputs[3u * i + 2u] = fresnelCoefficientsNKTable(coefficientLut, linearClamp, a.x * 4.0, a.y * 8.0);
}
"""


def test_wgsl_on_webgpu_lavapipe_matches_the_mirror(monkeypatch):
    import wgpu

    inputs = _inputs()
    device = wgpu_device(monkeypatch, features=("float32-filterable",))
    usage = wgpu.BufferUsage
    input_buffer = device.create_buffer_with_data(data=inputs.tobytes(), usage=usage.STORAGE)
    output_buffer = device.create_buffer(size=len(inputs) * 48, usage=usage.STORAGE | usage.COPY_SRC)
    views = wgpu_texture_views(device, (TABLE, CURVES))
    sampler = device.create_sampler(mag_filter="linear", min_filter="linear")
    data = wgpu_compute(
        device,
        INCLUDES["fresnel_basis.wgsl"] + WGSL_MAIN,
        [{"buffer": input_buffer}, {"buffer": output_buffer}, *views, sampler],
        output_buffer,
        len(inputs),
    )
    output = np.frombuffer(data, np.float32).reshape(len(inputs), 3, 4)
    _assert(output[:, 0], output[:, 1], output[:, 2], inputs, "lavapipe")


def test_the_table_is_the_shipped_basis_and_its_axes():
    """The header names the include's basis and the axes the include addresses."""
    assert HEADER["basis_hash"] in INCLUDES["fresnel_basis.glsl"].splitlines()[0]
    assert TABLE.shape == (128, 512, 3) and "x = r^(1/4) - sqrt(1 - r)/2" in HEADER["convention"]
    assert HEADER["channels"] == "c2,c3,f90" and HEADER["fit"] == "weighted"


SWITCH_MAIN = """
uniform sampler2D inputs;
uniform sampler2D coefficientLut;
uniform sampler2D curveLut;
layout(location = 0) out vec4 gulbrandsen;
layout(location = 1) out vec4 nk;
layout(location = 2) out vec4 direct;
void main() {
    vec4 a = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);
    gulbrandsen = fresnelCoefficientsGulbrandsenSelected(coefficientLut, a.x, a.y);
    nk = fresnelCoefficientsNKSelected(coefficientLut, a.x * 4.0, a.y * 8.0);
    direct = vec4(fresnelBasisDirectSelected(curveLut, a.z, gulbrandsen, gulbrandsen, gulbrandsen), 0.0);
}
"""


def test_the_switch_selects_either_path_on_llvmpipe():
    """``FRESNEL_BASIS_SOLVE`` (default false: the tables; ``#define FRESNEL_BASIS_SOLVE true``: the solve): the
    ``…Selected`` functions give exactly what the chosen path's own functions give."""
    inputs = _inputs()
    include = INCLUDES["fresnel_basis.glsl"]
    outputs = {}
    for solve in (False, True):
        define = "#define FRESNEL_BASIS_SOLVE true\n" if solve else ""
        outputs[solve] = gl_draw(
            "#version 330\n" + define + include + SWITCH_MAIN,
            [inputs.reshape(32, 32, 4), TABLE, CURVES],
            {"inputs": 0} if solve else {"inputs": 0, "coefficientLut": 1, "curveLut": 2},  # the compiler keeps one
            3,
        )
    paths = {
        False: (
            "fresnelCoefficientsGulbrandsenTable(coefficientLut, a.x, a.y)",
            "fresnelCoefficientsNKTable(coefficientLut, a.x * 4.0, a.y * 8.0)",
            "fresnelBasisDirectTable(curveLut, ",
        ),
        True: (
            "fresnelCoefficientsGulbrandsen(a.x, a.y)",
            "fresnelCoefficientsNK(a.x * 4.0, a.y * 8.0)",
            "fresnelBasisDirect(",
        ),
    }
    for solve, (gulbrandsen, nk, direct) in paths.items():
        own = (
            SWITCH_MAIN.replace("fresnelCoefficientsGulbrandsenSelected(coefficientLut, a.x, a.y)", gulbrandsen)
            .replace("fresnelCoefficientsNKSelected(coefficientLut, a.x * 4.0, a.y * 8.0)", nk)
            .replace("fresnelBasisDirectSelected(curveLut, ", direct)
        )
        expected = gl_draw(
            "#version 330\n" + include + own,
            [inputs.reshape(32, 32, 4), TABLE, CURVES],
            {"inputs": 0} if solve else {"inputs": 0, "coefficientLut": 1, "curveLut": 2},  # the solve reads no table
            3,
        )
        for got, want in zip(outputs[solve], expected):
            np.testing.assert_array_equal(got, want)
    assert np.max(np.abs(outputs[True][0] - outputs[False][0])) > 1e-4  # two paths, not one


def test_the_switch_is_a_pipeline_constant_in_wgsl(monkeypatch):
    """WGSL has no preprocessor: ``override FRESNEL_BASIS_SOLVE`` set at pipeline creation selects the solve."""
    import wgpu

    inputs = _inputs()
    device = wgpu_device(monkeypatch, features=("float32-filterable",))
    usage = wgpu.BufferUsage
    main = """
@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4f>;
@group(0) @binding(2) var coefficientLut: texture_2d<f32>;
@group(0) @binding(3) var linearClamp: sampler;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&inputs)) { return; }
    outputs[2u * i] = fresnelCoefficientsGulbrandsenSelected(coefficientLut, linearClamp, inputs[i].x, inputs[i].y);
    outputs[2u * i + 1u] = fresnelCoefficientsGulbrandsen(inputs[i].x, inputs[i].y);
}
"""
    (view,) = wgpu_texture_views(device, [TABLE])
    sampler = device.create_sampler(mag_filter="linear", min_filter="linear")
    results = {}
    for solve in (False, True):
        input_buffer = device.create_buffer_with_data(data=inputs.tobytes(), usage=usage.STORAGE)
        output_buffer = device.create_buffer(size=len(inputs) * 32, usage=usage.STORAGE | usage.COPY_SRC)
        data = wgpu_compute(
            device,
            INCLUDES["fresnel_basis.wgsl"] + main,
            [{"buffer": input_buffer}, {"buffer": output_buffer}, view, sampler],
            output_buffer,
            len(inputs),
            constants={"FRESNEL_BASIS_SOLVE": 1} if solve else None,
        )
        results[solve] = np.frombuffer(data, np.float32).reshape(len(inputs), 2, 4)
    np.testing.assert_array_equal(results[True][:, 0], results[True][:, 1])  # the solve, when set
    assert np.max(np.abs(results[False][:, 0] - results[False][:, 1])) > 1e-4  # the tables, by default
