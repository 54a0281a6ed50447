"""The generated GLSL include's ES 3.00 path in a real browser: WebGL 2 in headless Chromium (Debian's ``chromium``,
SwiftShader), driven by Playwright for Python with the system browser (no browser download). Every per-pixel function
renders into an RGBA32F target (EXT_color_buffer_float) whose floats are read back and compared with the Python
mirrors, as on llvmpipe (tests/luts/test_shaders_per_pixel.py): coefficients within 1e-5, direct-light curves within
1e-4 of the basis' spline, nothing NaN or inf, and no error on the page's console. Under ``CI=true`` a missing
browser or Playwright fails the test (the set-up installs both).
"""

import numpy as np

from benchmarks.browser import browser_page
from handoff.shaders import shader_includes
from tests.conftest import (
    LINEAR_CALLS,
    PER_PIXEL_CALLS,
    assert_linear_outputs,
    assert_per_pixel_outputs,
    chromium,
    per_pixel_inputs,
)

FRAGMENT = """#version 300 es
precision highp float;
precision highp int;
precision highp sampler2D;
{include}
uniform sampler2D inputs;
uniform sampler2D table0;
uniform sampler2D table1;
uniform int mode;
out vec4 result;
void main() {{
    vec4 q = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);
{branches}
}}
"""
PAGE = """<!doctype html><html><body><canvas id="c" width="32" height="32"></canvas><script>
function run(fragmentSource, inputs, modes, tables) {
  const gl = document.getElementById("c").getContext("webgl2");
  if (!gl) return {error: "no WebGL 2"};
  if (!gl.getExtension("EXT_color_buffer_float")) return {error: "no EXT_color_buffer_float"};
  if (tables.length && !gl.getExtension("OES_texture_float_linear")) return {error: "no OES_texture_float_linear"};
  const compile = (type, source) => {
    const shader = gl.createShader(type); gl.shaderSource(shader, source); gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(shader));
    return shader;
  };
  const program = gl.createProgram();
  gl.attachShader(program, compile(gl.VERTEX_SHADER,
    "#version 300 es\\nin vec2 p; void main() { gl_Position = vec4(p, 0.0, 1.0); }"));
  gl.attachShader(program, compile(gl.FRAGMENT_SHADER, fragmentSource));
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) return {error: gl.getProgramInfoLog(program)};
  gl.useProgram(program);
  const input = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, input);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, 32, 32, 0, gl.RGBA, gl.FLOAT, new Float32Array(inputs));
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.NEAREST);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.NEAREST);
  const target = gl.createTexture();
  gl.bindTexture(gl.TEXTURE_2D, target);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, 32, 32, 0, gl.RGBA, gl.FLOAT, null);
  const framebuffer = gl.createFramebuffer();
  gl.bindFramebuffer(gl.FRAMEBUFFER, framebuffer);
  gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, target, 0);
  if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) return {error: "float target incomplete"};
  gl.activeTexture(gl.TEXTURE0);
  gl.bindTexture(gl.TEXTURE_2D, input);
  gl.uniform1i(gl.getUniformLocation(program, "inputs"), 0);
  tables.forEach((table, index) => {  // RGBA32F, bilinear, clamp to edge: as the include expects its tables
    const texture = gl.createTexture();
    gl.activeTexture(gl.TEXTURE1 + index);
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA32F, table.width, table.height, 0, gl.RGBA, gl.FLOAT,
                  new Float32Array(table.data));
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
    gl.uniform1i(gl.getUniformLocation(program, "table" + index), 1 + index);
  });
  const quad = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, quad);
  gl.bufferData(gl.ARRAY_BUFFER, new Float32Array([-1, -1, 1, -1, -1, 1, 1, 1]), gl.STATIC_DRAW);
  const position = gl.getAttribLocation(program, "p");
  gl.enableVertexAttribArray(position);
  gl.vertexAttribPointer(position, 2, gl.FLOAT, false, 0, 0);
  gl.viewport(0, 0, 32, 32);
  const outputs = [];
  for (let mode = 0; mode < modes; ++mode) {
    gl.uniform1i(gl.getUniformLocation(program, "mode"), mode);
    gl.drawArrays(gl.TRIANGLE_STRIP, 0, 4);
    const pixels = new Float32Array(32 * 32 * 4);
    gl.readPixels(0, 0, 32, 32, gl.RGBA, gl.FLOAT, pixels);
    outputs.push(Array.from(pixels));
  }
  return {outputs: outputs, renderer: gl.getParameter(gl.RENDERER)};
}
</script></body></html>"""


def _render_in_webgl2(fragment: str, texels: list, modes: int, tables=()) -> dict:
    """The page's ``run`` of ``fragment`` over a 32 × 32 texture of ``texels`` for ``modes`` draws, with ``tables``
    ((H, W, C) arrays, uploaded as RGBA32F with bilinear filtering to uniforms ``table0``, ``table1``, …), in a fresh
    headless Chromium; no error on the page or its console."""
    uploads = []
    for table in tables:
        rgba = np.zeros(table.shape[:2] + (4,), np.float32)
        rgba[..., : table.shape[2]] = table
        uploads.append({"width": table.shape[1], "height": table.shape[0], "data": rgba.ravel().tolist()})
    with chromium() as browser:
        page, messages = browser_page(browser)
        page.set_content(PAGE)
        result = page.evaluate(
            "([source, inputs, modes, tables]) => run(source, inputs, modes, tables)",
            [fragment, texels, modes, uploads],
        )
    assert "error" not in result, result.get("error")
    assert not [text for kind, text in messages if kind in ("error", "pageerror")], messages
    return result


def test_glsl_es_per_pixel_in_webgl2_matches_the_mirrors():
    include = dict(shader_includes())["fresnel_basis.glsl"]
    branches = "\n".join(
        f"    {'if' if k == 0 else 'else if'} (mode == {k}) result = {call};" for k, call in enumerate(PER_PIXEL_CALLS)
    )
    fragment = FRAGMENT.format(include=include, branches=branches)
    inputs = per_pixel_inputs()
    texels = inputs.astype(np.float32).ravel().tolist()  # Playwright carries NaN and ±inf
    result = _render_in_webgl2(fragment, texels, len(PER_PIXEL_CALLS))
    values = [np.array(output, dtype=np.float64).reshape(1024, 4) for output in result["outputs"]]
    assert_per_pixel_outputs(values, inputs, f"WebGL 2 ({result['renderer']})")


def test_glsl_es_linear_models_in_webgl2_match_the_mirrors():
    """Issue 39: the linear models' weights and punctual light (conftest.LINEAR_CALLS) in WebGL 2, as on llvmpipe."""
    include = dict(shader_includes())["fresnel_basis.glsl"]
    branches = "\n".join(
        f"    {'if' if k == 0 else 'else if'} (mode == {k}) result = {call};" for k, call in enumerate(LINEAR_CALLS)
    )
    inputs = per_pixel_inputs()
    result = _render_in_webgl2(
        FRAGMENT.format(include=include, branches=branches),
        inputs.astype(np.float32).ravel().tolist(),
        len(LINEAR_CALLS),
    )
    values = [np.array(output, dtype=np.float64).reshape(1024, 4) for output in result["outputs"]]
    assert_linear_outputs(values, inputs, f"WebGL 2 ({result['renderer']})")


AREA_BODY = """
    vec3 shift = vec3((gl_FragCoord.x - 16.0) * 0.25, 0.0, (gl_FragCoord.y - 16.0) * 0.12 - 1.2);
    vec3 corners[4] = vec3[4](vec3(-1.0, -0.5, 2.0) + shift, vec3(-1.0, 0.5, 2.0) + shift, vec3(1.0, 0.5, 0.6) + shift,
                              vec3(1.0, -0.5, 0.6) + shift);
    result = vec4(max(fresnelLtcClippedVector(q, corners).z, 0.0), 0.0, 0.0, 0.0);
"""


def test_glsl_es_area_light_in_webgl2_matches_the_mirror():
    """``fresnelLtcClippedVector`` (clipping to the shading horizon, then in the cosine's space, Lambert's edges) in
    WebGL 2 for the shipped LTC table's matrices, under a tilted light that slides across both horizons pixel by pixel:
    within 1e-5 of :func:`preintegrate.ltc.horizon_ltc_vector` in float64 (the table fetch is tested on llvmpipe and
    lavapipe)."""
    from basis.storage import shipped_path
    from handoff.exr import read_lut
    from handoff.shipped import LTC_LUT
    from preintegrate.ltc import horizon_ltc_vector

    include = dict(shader_includes())["fresnel_basis.glsl"]
    table = read_lut(shipped_path(LTC_LUT))[0]
    rng = np.random.default_rng(25)
    stored = table.reshape(-1, 4)[rng.integers(0, table.shape[0] * table.shape[1], 1024)].astype(np.float32)
    result = _render_in_webgl2(FRAGMENT.format(include=include, branches=AREA_BODY), stored.ravel().tolist(), 1)
    got = np.array(result["outputs"][0], dtype=np.float64).reshape(32, 32, 4)[..., 0]
    y, x = np.mgrid[0:32, 0:32] + 0.5
    shift = np.stack([(x - 16.0) * 0.25, np.zeros_like(x), (y - 16.0) * 0.12 - 1.2], -1)
    light = np.array([[-1.0, -0.5, 2.0], [-1.0, 0.5, 2.0], [1.0, 0.5, 0.6], [1.0, -0.5, 0.6]])
    corners = light[None, None] + shift[:, :, None, :]
    want = np.maximum(horizon_ltc_vector(stored.astype(np.float64).reshape(32, 32, 4), corners)[..., 2], 0.0)
    crossing = (corners[..., 2].min(-1) < 0.0) & (corners[..., 2].max(-1) > 0.0)
    assert np.sum(crossing & (want > 1e-3)) >= 50  # the shading horizon's clip is exercised
    assert np.all(np.isfinite(got))
    assert np.max(np.abs(got - want)) <= 1e-5, np.max(np.abs(got - want))


def test_glsl_es_per_pixel_tables_in_webgl2_match_the_mirrors():
    """Issue 38: ``fresnelCoefficientsGulbrandsenTable``, ``fresnelCoefficientsNKTable`` and ``fresnelBasisDirectTable``
    with the shipped per-pixel tables (RGBA32F, bilinear: OES_texture_float_linear) in WebGL 2, over the inputs of
    tests/luts/test_shaders_coefficient_table.py: the coefficients within 1e-5 of the mirrors (2e-4 for (η, κ), whose
    r and g float32 computes before the lookup), F(V·H) within 1e-5, nothing NaN or inf."""
    from basis.storage import shipped_path
    from handoff.exr import read_lut
    from handoff.shaders import (
        coefficients_per_pixel_gulbrandsen_table,
        coefficients_per_pixel_nk_table,
        direct_fresnel_table,
    )
    from handoff.shipped import COEFFICIENT_LUT, CURVE_LUT

    table, curves = (read_lut(shipped_path(name))[0] for name in (COEFFICIENT_LUT, CURVE_LUT))
    rng = np.random.default_rng(38)
    r, g, v_dot_h = (rng.uniform(0.0, 1.0, 1024) for _ in range(3))
    special = [0.0, 0.9999, 1.0, np.nan, np.inf, -np.inf, -0.5, 2.0, 1e-12, 0.5]
    r[:10], g[10:20], v_dot_h[20:30] = special, special, special
    r[30:94] = rng.uniform(0.95, 0.9999, 64)
    inputs = np.stack([r, g, v_dot_h, np.zeros_like(r)], axis=-1).astype(np.float32)
    body = """
    vec4 c = fresnelCoefficientsGulbrandsenTable(table0, q.x, q.y);
    if (mode == 0) result = c;
    else if (mode == 1) result = vec4(fresnelBasisDirectTable(table1, q.z, c, c, c).x, 0.0, 0.0, 0.0);
    else result = fresnelCoefficientsNKTable(table0, q.x * 4.0, q.y * 8.0);
"""
    include = dict(shader_includes())["fresnel_basis.glsl"]
    result = _render_in_webgl2(
        FRAGMENT.format(include=include, branches=body), inputs.ravel().tolist(), 3, (table, curves)
    )
    coefficients, direct, nk = (np.array(output, dtype=np.float64).reshape(1024, 4) for output in result["outputs"])
    assert all(np.all(np.isfinite(values)) for values in (coefficients, direct, nk))
    expected = coefficients_per_pixel_gulbrandsen_table(table, inputs[:, 0], inputs[:, 1])
    assert np.max(np.abs(coefficients - expected)) <= 1e-5, np.max(np.abs(coefficients - expected))
    light = direct_fresnel_table(curves, expected, inputs[:, 2])
    assert np.max(np.abs(direct[:, 0] - light)) <= 1e-5, np.max(np.abs(direct[:, 0] - light))
    with np.errstate(invalid="ignore"):
        eta, kappa = inputs[:, 0] * np.float32(4.0), inputs[:, 1] * np.float32(8.0)
    error = np.max(np.abs(nk - coefficients_per_pixel_nk_table(table, eta, kappa)))
    assert error <= 2e-4, error
