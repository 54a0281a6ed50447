"""The generated includes' rectangular light (``fresnelBasisRectLight``, ``fresnelSchlickRectLight``,
``fresnelLinearRectLight``, ``fresnelLtcRect``, ``fresnelLtcUV``) and the linear models' split sums
(``fresnelLinearSplitSum``, ``fresnelLinearMultipleScattering``: an F82-tint material's exact path) run for real with the shipped tables and match their Python mirrors
(handoff/shaders/mirrors.py ``rect_light_specular``, preintegrate/ltc.py): GLSL on Mesa's llvmpipe, WGSL on lavapipe
(the WebGL 2 path: tests/luts/test_shaders_webgl.py).

1024 shading points: normals and views spanning the hemisphere (views at and beyond grazing, along the normal),
roughness 0 … 1 with its edges, a 2 × 1 light above them that slides across the horizon. Tolerance, float32 against
float64: 1e-5 on the LTC integral (at most 1), the specular and the table coordinates, nothing NaN or inf (the
specular measured 3.8e-6 on llvmpipe and lavapipe; 4.9e-6 with the weight √I of the lobe's limit that shipped before
preintegrate.ltc's LOBE_WEIGHT_POWER); the specular's 1e-5 times, per point, what the LTC's share above the horizon
(preintegrate.ltc.toward_upper_share) multiplies float32's rounding of the integral by, its relative slope
1 + m (1/H − 1) x^m / (1 + (1/H − 1) x^m), x = min(I/H, 1) (:func:`_upper_share_slope`: at most 1 + m (1 − H); 3.5 at
the worst of these points, N·V 0, r 0.13, H 0.62, where the specular measured 1.4e-5).
``fresnelLtcUV(NdotV, r)``, the public tables' √(1 − N·V), is compared away from the normal only: for a view along
the normal, float32's N·V (within 6e-8 of 1) moves it by up to 2.4e-4, 0.016 texels, and a sharp lobe's light by
3e-4; ``fresnelLtcRect`` reads the table through |N × V| (``fresnelLtcUVSine``) and holds 1e-5 there too."""

import numpy as np

from basis.storage import shipped_path
from handoff.exr import read_lut
from handoff.shaders import (
    linear_rect_light_specular,
    linear_split_sum,
    linear_weights,
    ltc_coordinates,
    rect_light_specular,
    shader_includes,
)
from handoff.shipped import BASIS_LUT, LTC_LUT, SCHLICK_LUT
from preintegrate.ltc import (
    ALPHA_FLOOR,
    UPPER_SHARE_POWER,
    horizon_ltc_vector,
    lobe_density_ratio,
    lobe_ratio_bound,
    ltc_direction,
    ltc_grid,
    ltc_solid_angle,
    ltc_upper_share,
    rect_light_half_cosine,
    rect_light_integral,
    toward_lobe_limit,
)
from preintegrate.lut import LutGrid
from tests.conftest import gl_draw, wgpu_compute, wgpu_device, wgpu_texture_views

INCLUDES = dict(shader_includes())
COEFFICIENTS = np.array([[0.9, 0.1, -0.02, 0.01], [0.75, 0.25, 0.01, 0.01], [0.42, 0.58, 0.03, 0.0]])
F0 = np.array([0.95, 0.64, 0.54])
#: An F82-tint (OpenPBR specular_color) material's weights of the Schlick table's R, G, A, one row per colour.
WEIGHTS = linear_weights("f82-tint", f0=F0, tint=np.array([0.9, 0.75, 0.6]))
OUTPUTS = 5
LIGHT = np.array([[-1.0, -0.5, 2.0], [-1.0, 0.5, 2.0], [1.0, 0.5, 2.0], [1.0, -0.5, 2.0]])  # faces -z, three.js winding


def _tables():
    return [read_lut(shipped_path(name))[0] for name in (LTC_LUT, BASIS_LUT, SCHLICK_LUT)]


def _inputs():
    """(1024, 4) twice: (N, r) and (V, shift of the light along x)."""
    rng = np.random.default_rng(24)
    count = 1024
    normal = rng.normal(size=(count, 3))
    normal[:, 2] = np.abs(normal[:, 2]) + 0.3
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    view = rng.normal(size=(count, 3))
    view /= np.linalg.norm(view, axis=-1, keepdims=True)
    view[:64] = normal[:64]  # along the normal: the frame's fallback
    roughness = rng.uniform(0.0, 1.0, count)
    roughness[64:80] = [0.0, 1.0, 1e-4, 0.999, *np.linspace(0.0, 0.05, 12)]
    shift = rng.uniform(-4.0, 4.0, count)
    return np.concatenate([normal, roughness[:, None]], -1), np.concatenate([view, shift[:, None]], -1)


def _as_read(a, b, light=LIGHT, step=1.0):
    """The inputs as the shaders read them (float32): (N, r, V, N·V, |N × V|, the light's corners (…, 4, 3) shifted
    along x by ``step`` × each input's shift)."""
    a, b = a.astype(np.float32).astype(np.float64), b.astype(np.float32).astype(np.float64)
    normal, roughness, view, shift = a[:, :3], a[:, 3], b[:, :3], b[:, 3]
    corners = light[None] + np.stack([step * shift, np.zeros_like(shift), np.zeros_like(shift)], -1)[:, None, :]
    n_dot_v = np.clip(np.sum(normal * view, axis=-1), 0.0, 1.0)
    return normal, roughness, view, n_dot_v, np.linalg.norm(np.cross(normal, view), axis=-1), corners


def _texel(ltc, n_dot_v, roughness, sine):
    """The LTC table read at (N·V, r) through |N × V|, as ``fresnelLtcRectVector`` reads it."""
    return ltc_grid(ltc.shape[0]).lookup(ltc, n_dot_v, np.clip(roughness, 0, 1), sine)


def _ltc_integral(ltc, normal, roughness, view, n_dot_v, sine, corners, albedo=None, upper_power=UPPER_SHARE_POWER):
    """``fresnelLtcRect``'s float64 mirror: the table read at (N·V, r) through |N × V|, integrated over the light;
    with ``albedo`` E, ``fresnelLtcRectVector``'s for E (taken toward the lobe's punctual limit and then, unless
    ``upper_power`` is None, toward the LTC's share above the horizon)."""
    stored = _texel(ltc, n_dot_v, roughness, sine)
    position = np.zeros((len(normal), 3))
    if albedo is None:
        return rect_light_integral(stored, normal, view, position, corners)
    rough = np.clip(roughness, 0, 1)
    return rect_light_half_cosine(stored, normal, view, position, corners, rough, albedo, upper_power=upper_power)[0]


def _expected(a, b, ltc, basis, schlick):
    normal, roughness, view, n_dot_v, sine, corners = _as_read(a, b)
    position = np.zeros((len(a), 3))
    coefficients = np.broadcast_to(COEFFICIENTS, (len(a), 3, 4))
    specular = rect_light_specular(ltc, basis, normal, view, position, corners, roughness, coefficients)
    integral = _ltc_integral(ltc, normal, roughness, view, n_dot_v, sine, corners)
    s = LutGrid(schlick.shape[1], schlick.shape[0]).lookup(schlick, n_dot_v, np.clip(roughness, 0, 1))
    toward = _ltc_integral(ltc, normal, roughness, view, n_dot_v, sine, corners, albedo=s[:, 2])
    schlick_specular = toward[:, None] * (F0[None] * s[:, :1] + s[:, 1:2])
    uv = ltc_coordinates(n_dot_v, roughness)
    uv[:64] = np.nan  # views along the normal: fresnelLtcUV's √(1 − N·V) is float32's N·V rounding (see above)
    weights = np.broadcast_to(WEIGHTS, (len(a), 3, 3))
    linear = linear_split_sum(schlick, n_dot_v, roughness, weights)
    compensated = linear_split_sum(schlick, n_dot_v, roughness, weights, multiple_scattering=True)
    linear_rect_light = linear_rect_light_specular(ltc, schlick, normal, view, position, corners, roughness, weights)
    return [
        np.concatenate([specular, integral[:, None]], -1),
        np.concatenate([schlick_specular, np.zeros((len(a), 1))], -1),
        np.concatenate([ltc_grid(ltc.shape[0]).texture_coordinates(n_dot_v, roughness, sine), uv], -1),
        np.concatenate([linear_rect_light, np.zeros((len(a), 1))], -1),
        np.concatenate([linear, compensated[:, :1]], -1),
    ]


def _upper_share_slope(a, b, ltc, schlick):
    """(1024,) per point, 1 + m (1/H − 1) x^m / (1 + (1/H − 1) x^m), x = min(I/H, 1): the relative slope of
    preintegrate.ltc.toward_upper_share at the mirror's integral I before it (the lobe's limit with the Schlick table's
    E), what it multiplies float32's relative rounding of I by; H the texel's ltc_upper_share."""
    read = _as_read(a, b)
    _, roughness, _, n_dot_v, sine, _ = read
    albedo = LutGrid(schlick.shape[1], schlick.shape[0]).lookup(schlick, n_dot_v, np.clip(roughness, 0, 1))[:, 2]
    integral = _ltc_integral(ltc, *read, albedo=albedo, upper_power=None)
    upper = ltc_upper_share(_texel(ltc, n_dot_v, roughness, sine))
    raised = (1.0 / upper - 1.0) * np.minimum(integral / upper, 1.0) ** UPPER_SHARE_POWER
    return 1.0 + UPPER_SHARE_POWER * raised / (1.0 + raised)


#: The outputs that hold a rectangular light's specular (the LTC integral toward the lobe's limit and the horizon).
RECT_OUTPUTS = (0, 1, 3)


def _assert(outputs, expected, where, slope=None):
    """Each output within 1e-5 of the mirror; the rectangular lights' (:data:`RECT_OUTPUTS`) within 1e-5 × ``slope``
    per point where given (:func:`_upper_share_slope`); nothing NaN or inf."""
    for k, (got, want) in enumerate(zip(outputs, expected)):
        got = np.asarray(got, dtype=np.float64)
        assert np.all(np.isfinite(got)), (where, k)
        error = np.abs(got - want).reshape(len(want), -1)
        scale = slope[:, None] if slope is not None and k in RECT_OUTPUTS else 1.0
        assert np.all(np.isnan(error) | (error <= 1e-5 * scale)), (where, k, float(np.nanmax(error / scale)))


def test_the_rect_lights_fresnel_reads_the_curves_on_the_basis_tables_mirror_row():
    """``fresnelBasisRectLight`` reads F̃ from the basis table at (V·H*, r') (``rect_light_punctual``), F(V·H*) itself
    for a small light (r' = 0), where the split sum is the curve itself: there b̄0 = 1 exactly and the terms match the basis' own spline curves to float32 at
    the columns and within 7e-4 between them (bilinear; measured 6.7e-4, b3 near μ = 0.06, 1e-4 for b1), against the
    direct-light polynomial's 2.2e-5."""
    from basis.eigenbasis import default_basis

    basis_table = _tables()[1]
    grid = LutGrid(basis_table.shape[1], basis_table.shape[0])
    assert grid.holds_mirror
    assert np.all(basis_table[0, :, 0] == 1.0)
    at_columns = grid.lookup(basis_table, grid.mu_o, np.zeros(grid.width))
    assert np.max(np.abs(at_columns - default_basis().evaluate_mu(grid.mu_o))) <= 1e-7
    mu = np.linspace(0.0, 1.0, 4001)
    between = grid.lookup(basis_table, mu, np.zeros_like(mu))
    assert np.max(np.abs(between - default_basis().evaluate_mu(mu))) <= 7e-4


GLSL_MAIN = """
uniform sampler2D ltcLut;
uniform sampler2D basisLut;
uniform sampler2D schlickLut;
uniform sampler2D inputA;
uniform sampler2D inputB;
uniform vec4 cR; uniform vec4 cG; uniform vec4 cB; uniform vec3 f0;
uniform vec3 wR; uniform vec3 wG; uniform vec3 wB;
uniform vec3 light[4];
layout(location = 0) out vec4 out0;
layout(location = 1) out vec4 out1;
layout(location = 2) out vec4 out2;
layout(location = 3) out vec4 out3;
layout(location = 4) out vec4 out4;
void main() {
    vec4 a = texelFetch(inputA, ivec2(gl_FragCoord.xy), 0), b = texelFetch(inputB, ivec2(gl_FragCoord.xy), 0);
    vec3 corners[4];
    for (int i = 0; i < 4; ++i) corners[i] = light[i] + vec3(b.w, 0.0, 0.0);
    vec3 P = vec3(0.0);
    out0 = vec4(fresnelBasisRectLight(ltcLut, basisLut, a.xyz, b.xyz, P, corners, a.w, cR, cG, cB),
                fresnelLtcRect(ltcLut, a.xyz, b.xyz, P, corners, a.w));
    out1 = vec4(fresnelSchlickRectLight(ltcLut, schlickLut, a.xyz, b.xyz, P, corners, a.w, f0), 0.0);
    float NdotV = clamp(dot(a.xyz, b.xyz), 0.0, 1.0);
    out2 = vec4(fresnelLtcUVSine(NdotV, length(cross(a.xyz, b.xyz)), a.w), fresnelLtcUV(NdotV, a.w));
    out3 = vec4(fresnelLinearRectLight(ltcLut, schlickLut, a.xyz, b.xyz, P, corners, a.w, wR, wG, wB), 0.0);
    out4 = vec4(fresnelLinearSplitSum(schlickLut, NdotV, a.w, wR, wG, wB),
                fresnelLinearMultipleScattering(schlickLut, NdotV, a.w, wR, wG, wB).x);
}
"""


def test_glsl_rect_light_on_mesa_llvmpipe_matches_the_mirrors():
    ltc, basis, schlick = _tables()
    a, b = _inputs()
    uniforms = {"ltcLut": 0, "basisLut": 1, "schlickLut": 2, "inputA": 3, "inputB": 4, "f0": tuple(F0)}
    uniforms.update({f"c{colour}": tuple(COEFFICIENTS[k]) for k, colour in enumerate("RGB")})
    uniforms.update({f"w{colour}": tuple(WEIGHTS[k]) for k, colour in enumerate("RGB")})
    uniforms["light"] = [tuple(corner) for corner in LIGHT]
    outputs = gl_draw(
        "#version 330\n" + INCLUDES["fresnel_basis.glsl"] + GLSL_MAIN,
        [ltc, basis, schlick, a.reshape(32, 32, 4), b.reshape(32, 32, 4)],
        uniforms,
        OUTPUTS,
    )
    _assert(outputs, _expected(a, b, ltc, basis, schlick), "llvmpipe", _upper_share_slope(a, b, ltc, schlick))


WGSL_MAIN = """
@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;
@group(0) @binding(1) var<storage, read_write> outputs: array<vec4f>;
@group(0) @binding(2) var ltcLut: texture_2d<f32>;
@group(0) @binding(3) var basisLut: texture_2d<f32>;
@group(0) @binding(4) var schlickLut: texture_2d<f32>;
@group(0) @binding(5) var linearClamp: sampler;
const LIGHT = array<vec3f, 4>(vec3f(-1.0, -0.5, 2.0), vec3f(-1.0, 0.5, 2.0), vec3f(1.0, 0.5, 2.0), vec3f(1.0, -0.5, 2.0));
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&inputs) / 2u) { return; }
    let a = inputs[2u * i];
    let b = inputs[2u * i + 1u];
    var corners: array<vec3f, 4>;
    for (var k = 0; k < 4; k = k + 1) { corners[k] = LIGHT[k] + vec3f(b.w, 0.0, 0.0); }
    let P = vec3f(0.0);
    let cR = vec4f(COEFFICIENTS_R); let cG = vec4f(COEFFICIENTS_G); let cB = vec4f(COEFFICIENTS_B);
    let wR = vec3f(WEIGHTS_R); let wG = vec3f(WEIGHTS_G); let wB = vec3f(WEIGHTS_B);
    outputs[5u * i] = vec4f(fresnelBasisRectLight(ltcLut, basisLut, linearClamp, a.xyz, b.xyz, P, corners, a.w, cR, cG, cB),
                            fresnelLtcRect(ltcLut, linearClamp, a.xyz, b.xyz, P, corners, a.w));
    outputs[5u * i + 1u] = vec4f(fresnelSchlickRectLight(ltcLut, schlickLut, linearClamp, a.xyz, b.xyz, P, corners, a.w,
                                                         vec3f(F0)), 0.0);
    let NdotV = clamp(dot(a.xyz, b.xyz), 0.0, 1.0);
    outputs[5u * i + 2u] = vec4f(fresnelLtcUVSine(NdotV, length(cross(a.xyz, b.xyz)), a.w), fresnelLtcUV(NdotV, a.w));
    outputs[5u * i + 3u] = vec4f(fresnelLinearRectLight(ltcLut, schlickLut, linearClamp, a.xyz, b.xyz, P, corners, a.w,
                                                        wR, wG, wB), 0.0);
    outputs[5u * i + 4u] = vec4f(fresnelLinearSplitSum(schlickLut, linearClamp, NdotV, a.w, wR, wG, wB),
                                 fresnelLinearMultipleScattering(schlickLut, linearClamp, NdotV, a.w, wR, wG, wB).x);
}
"""


def test_wgsl_rect_light_on_webgpu_lavapipe_matches_the_mirrors(monkeypatch):
    import wgpu

    ltc, basis, schlick = _tables()
    a, b = _inputs()
    device = wgpu_device(monkeypatch, features=("float32-filterable",))
    usage = wgpu.BufferUsage
    inputs = np.stack([a, b], axis=1).astype(np.float32)
    input_buffer = device.create_buffer_with_data(data=inputs.tobytes(), usage=usage.STORAGE)
    output_buffer = device.create_buffer(size=len(a) * OUTPUTS * 16, usage=usage.STORAGE | usage.COPY_SRC)
    views = wgpu_texture_views(device, (ltc, basis, schlick))
    sampler = device.create_sampler(mag_filter="linear", min_filter="linear")
    code = INCLUDES["fresnel_basis.wgsl"] + WGSL_MAIN
    for colour, row, weights in zip("RGB", COEFFICIENTS, WEIGHTS):
        code = code.replace(f"COEFFICIENTS_{colour}", ", ".join(f"{value:.9g}" for value in row))
        code = code.replace(f"WEIGHTS_{colour}", ", ".join(f"{float(np.float32(value)):.9g}" for value in weights))
    code = code.replace("vec3f(F0)", "vec3f(" + ", ".join(f"{value:.9g}" for value in F0) + ")")
    data = wgpu_compute(
        device,
        code,
        [{"buffer": input_buffer}, {"buffer": output_buffer}, *views, sampler],
        output_buffer,
        len(a),
    )
    output = np.frombuffer(data, np.float32).reshape(len(a), OUTPUTS, 4)
    _assert(
        [output[:, k] for k in range(OUTPUTS)],
        _expected(a, b, ltc, basis, schlick),
        "lavapipe",
        _upper_share_slope(a, b, ltc, schlick),
    )


LTC_MAIN = """
uniform sampler2D ltcLut;
uniform sampler2D inputA;
uniform sampler2D inputB;
uniform vec3 light[4];
uniform float albedo;
layout(location = 0) out vec4 out0;
void main() {
    vec4 a = texelFetch(inputA, ivec2(gl_FragCoord.xy), 0), b = texelFetch(inputB, ivec2(gl_FragCoord.xy), 0);
    vec3 corners[4];
    for (int i = 0; i < 4; ++i) corners[i] = light[i] + vec3(b.w * length(light[0] - light[2]) * 0.5, 0.0, 0.0);
    out0 = vec4(fresnelLtcRect(ltcLut, a.xyz, b.xyz, vec3(0.0), corners, a.w),
                fresnelLtcRectVector(ltcLut, a.xyz, b.xyz, vec3(0.0), corners, a.w, albedo).w, 0.0, 0.0);
}
"""


def test_glsl_ltc_integral_of_tiny_and_far_lights_on_llvmpipe():
    """``fresnelLtcRect`` in float32 for a light 2e-3 × 1e-3 two units away, one 0.06 × 0.03 and one 200 × 100 a
    thousand away (long, nearly parallel edge vectors), over the inputs above, each sliding across the horizon by its
    own half diagonal per unit of shift, against the float64 mirror relative to the light's largest value: within 1e-4
    (measured 9.1e-5 for the tiny light, whose integral is at most 3e-6 here, 5.4e-5 for the small one and 1.6e-7 for
    the far one; the edges' p × q had cost
    the tiny light 3.8e-3, where p × (q − p) keeps 9.1e-5), nothing NaN or inf. The tiny light's four edge terms,
    each about its width over its distance (5e-4), cancel to its share of the lobe, about a thousand times smaller:
    float32's rounding of each (6e-8) leaves some 6e-5 of it, at pixels that move with any change in the rounding
    (θ / sin θ from atan gave 6.7e-5 at another pixel; from the polynomial in 1 − cos θ, 9.1e-5; the same polynomial
    in cos θ, whose Horner sum rounds as its coefficients do, 2.0e-4). The same for the integral taken toward the
    lobe's punctual limit (``fresnelLtcRectVector`` with E = 0.8), whose ratio of the lobe to the LTC's density
    float32 must hold for a light this small, and which multiplies the integral's rounding by up to
    preintegrate.ltc's lobe_ratio_bound: LOBE_RATIO_MAX for the tiny light, up to LOBE_RATIO_PER_SIZE √Ω for the
    others (measured 7.6e-5, 6.1e-5 and 2.4e-7; a bound of 4 for any light gave the tiny one 1.6e-4, none 1.2e-2;
    LOBE_RATIO_PER_SIZE at 400 instead of 100 gives the small one 1.2e-4, at 200 what 100 does)."""
    ltc = _tables()[0]
    a, b = _inputs()
    for light in (LIGHT * [1e-3, 1e-3, 1.0], LIGHT * [3e-2, 3e-2, 1.0], LIGHT * [100.0, 100.0, 500.0]):
        light = light.astype(np.float32).astype(np.float64)
        outputs = gl_draw(
            "#version 330\n" + INCLUDES["fresnel_basis.glsl"] + LTC_MAIN,
            [ltc, a.reshape(32, 32, 4), b.reshape(32, 32, 4)],
            {"ltcLut": 0, "inputA": 1, "inputB": 2, "light": [tuple(corner) for corner in light], "albedo": 0.8},
            1,
        )
        got = np.asarray(outputs[0], dtype=np.float64).reshape(-1, 4)[:, :2]
        read = _as_read(a, b, light, np.linalg.norm(light[0] - light[2]) * 0.5)
        assert np.all(np.isfinite(got))
        for column, albedo in enumerate((None, 0.8)):
            want = _ltc_integral(ltc, *read, albedo=albedo)
            assert np.sum(want > 0.0) > 200, np.sum(want > 0.0)
            error = np.max(np.abs(got[:, column] - want)) / np.max(want)
            assert error <= 1e-4, (light[0], albedo, error)


def test_glsl_the_lights_spread_on_llvmpipe():
    """``fresnelLtcRectVector`` toward the lobe's punctual limit (E = 0.8) under lights 1 to 8 wide two units above,
    centred on the mirror direction of views at N·V 0.05 to 0.6 with r 0.2 to 0.8, where the light's spread
    (preintegrate.ltc.lobe_spread, from fresnelLtcDiskSolidAngle) keeps more of the LTC's integral than the weight I^p
    alone: against the float64 mirror within 1e-5 (measured 4.4e-7, 4.9e-7 and 7.4e-7), nothing NaN or inf, on 1024
    values per light of which the spread moves at least 100 by more than 1e-3 (measured 140, 387 and 443), so that the
    comparison holds the spread's own arithmetic (the inputs above exercise it at about ten)."""
    ltc = _tables()[0]
    mu, roughness = (grid.ravel() for grid in np.meshgrid(np.linspace(0.05, 0.6, 32), np.linspace(0.2, 0.8, 32)))
    view = np.stack([np.sqrt(1.0 - mu * mu), np.zeros_like(mu), mu], -1)
    a = np.concatenate([np.tile([0.0, 0.0, 1.0], (len(mu), 1)), roughness[:, None]], -1)
    for scale in (0.5, 2.0, 4.0):
        light = (LIGHT * [scale, scale, 1.0]).astype(np.float32).astype(np.float64)
        step = np.linalg.norm(light[0] - light[2]) * 0.5
        b = np.concatenate([view, (-2.0 * view[:, :1] / mu[:, None]) / step], -1)  # the centre on the mirror direction
        outputs = gl_draw(
            "#version 330\n" + INCLUDES["fresnel_basis.glsl"] + LTC_MAIN,
            [ltc, a.reshape(32, 32, 4), b.reshape(32, 32, 4)],
            {"ltcLut": 0, "inputA": 1, "inputB": 2, "light": [tuple(corner) for corner in light], "albedo": 0.8},
            1,
        )
        got = np.asarray(outputs[0], dtype=np.float64).reshape(-1, 4)[:, 1]
        read = _as_read(a, b, light, step)
        want = _ltc_integral(ltc, *read, albedo=0.8)
        assert np.all(np.isfinite(got))
        error = np.max(np.abs(got - want))
        assert error <= 1e-5, (scale, error)
        # the same without the spread (the normal is z and the view in the xz plane: the corners are in the frame)
        stored = ltc_grid(ltc.shape[0]).lookup(ltc, read[3], read[1], read[4])
        vector = horizon_ltc_vector(stored, read[5])
        integral = np.maximum(vector[:, 2], 0.0)
        alpha = np.maximum(read[1] ** 2, ALPHA_FLOOR)
        direction = ltc_direction(stored, vector)
        ratio = lobe_density_ratio(stored, direction, read[3], alpha, 0.8, sine=read[4])
        bound = lobe_ratio_bound(integral, ltc_solid_angle(stored, vector))
        moved = np.sum(np.abs(want - toward_lobe_limit(integral, np.minimum(ratio, bound))) > 1e-3)
        assert moved >= 100, (scale, moved)


SMOOTHED_MAIN = """
uniform sampler2D basisLut;
uniform sampler2D schlickLut;
uniform sampler2D inputs;
uniform vec4 cR; uniform vec4 cG; uniform vec4 cB;
uniform vec3 wR; uniform vec3 wG; uniform vec3 wB;
layout(location = 0) out vec4 basis;
layout(location = 1) out vec4 linear;
void main() {
    vec4 a = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);
    basis = vec4(fresnelBasisSmoothed(basisLut, a.x, a.y, 0.8, cR, cG, cB), 0.0);
    linear = vec4(fresnelLinearSmoothed(schlickLut, a.x, a.y, 0.8, wR, wG, wB), 0.0);
}
"""


def test_glsl_the_rect_lights_fresnel_average_takes_any_input_into_the_tables():
    """``fresnelBasisSmoothed`` and ``fresnelLinearSmoothed`` (F̃ of the rect lights, times E = 0.8) on llvmpipe at
    (x, r) over [0, 1], beyond it, ±inf and ±NaN: finite everywhere and, at the inputs clamped to [0, 1] as the
    shaders clamp them (an integer clamp of the bits: NaN to an end by its sign), their mirrors' values
    (``rect_light_punctual``; the Schlick table's split sum over its B, ``linear_split_sum``) to 1e-5 relative to
    max(1, value): E / E' grows where E' is small, at large r (up to 2.6 here, E' 0.31 at x = r = 1)."""
    from handoff.shaders import bits_clamp, linear_split_sum, rect_light_punctual

    _, basis_table, schlick = _tables()
    rng = np.random.default_rng(41)
    odd = np.array([-0.5, -0.0, 0.0, 1.0, 1.5, np.inf, -np.inf, np.nan, -np.nan], dtype=np.float32)
    pairs = rng.uniform(0.0, 1.0, (1024, 2)).astype(np.float32)
    pairs[: odd.size**2] = np.stack(np.meshgrid(odd, odd, indexing="ij"), axis=-1).reshape(-1, 2)
    inputs = np.concatenate([pairs, np.zeros((1024, 2), np.float32)], axis=1)
    uniforms = {"basisLut": 0, "schlickLut": 1, "inputs": 2}
    uniforms.update({f"c{colour}": tuple(COEFFICIENTS[k]) for k, colour in enumerate("RGB")})
    uniforms.update({f"w{colour}": tuple(WEIGHTS[k]) for k, colour in enumerate("RGB")})
    basis, linear = gl_draw(
        "#version 330\n" + INCLUDES["fresnel_basis.glsl"] + SMOOTHED_MAIN,
        [basis_table, schlick, inputs.reshape(32, 32, 4)],
        uniforms,
        2,
    )
    assert np.all(np.isfinite(basis)) and np.all(np.isfinite(linear))
    x, r = (bits_clamp(pairs[:, k].astype(np.float64), 0.0, 1.0) for k in (0, 1))  # fresnelUnitClamp's
    coefficients = np.broadcast_to(COEFFICIENTS, (len(x), *COEFFICIENTS.shape))
    want_basis = 0.8 * rect_light_punctual(basis_table, coefficients, x, spread=r)
    grid = LutGrid(schlick.shape[1], schlick.shape[0])
    albedo = np.maximum(grid.lookup(schlick, x, r)[:, 2:3], 1e-4)
    want_linear = 0.8 * linear_split_sum(schlick, x, r, np.broadcast_to(WEIGHTS, (len(x), *WEIGHTS.shape))) / albedo
    for name, got, want in (("basis", basis[:, :3], want_basis), ("linear", linear[:, :3], want_linear)):
        error = np.abs(got - want) / np.maximum(1.0, np.abs(want))
        assert np.max(error) <= 1e-5, (name, float(np.max(error)), float(np.max(np.abs(want))))
