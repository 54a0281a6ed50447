"""The generated per-pixel includes of bases of other sizes (K = 2, 3, 6, 8 terms; ``basis --terms K`` then
``build``) run for real and match their Python mirrors, as the shipped four-term include does
(tests/luts/test_shaders_per_pixel.py): GLSL on Mesa's llvmpipe, WGSL on lavapipe, HLSL and GLSL ES compiled by
glslang.

K − 2 fit angles, a constant (K − 2) × (K − 2) inverse; K ≤ 4 returns one vec4 per channel, K > 4 a
``FresnelTerms8`` (terms 0-3 in ``.lo``, 4-7 in ``.hi``), read from the two textures of the build. What float32
allows the coefficients grows with the inverse's condition number (``ShaderConstants.float32_tolerance``: 2e-6 for
K ≤ 3, 5e-4 for this 6-term basis, 1e-2 for the 8-term one, whose default fit angles crowd between 1.29 and
1.5 rad); the Fresnel curve Σ c_k b_k they give, what an engine sees, with the solve's Lebesgue constant
(``float32_curve_tolerance``: 5e-7 for K ≤ 4, 5e-5 for K = 6, 2e-4 for K = 8: measured 8.8e-5 on llvmpipe, still
60 times below the basis' own fitting error).
"""

import shutil
import subprocess

import numpy as np
import pytest

from basis import coefficients_from_gulbrandsen, coefficients_from_nk
from basis.training import build_basis
from handoff.shaders import coefficients_per_pixel_gulbrandsen, coefficients_per_pixel_nk, shader_constants
from handoff.shaders import shader_includes as includes_of
from tests.conftest import (
    PER_PIXEL_CALLS,
    assert_per_pixel_outputs,
    gl_draw,
    gpu_missing,
    per_pixel_inputs,
    wgpu_compute,
    wgpu_device,
)

TERMS = (2, 3, 5, 6, 8)


@pytest.fixture(scope="module", params=TERMS, ids=[f"{k} terms" for k in TERMS])
def basis(request):
    return build_basis(count=5000, n_terms=request.param, grid_size=128)


def _wide(basis) -> bool:
    return basis.n_terms > 4


def _assert_outputs(outputs, inputs, basis, where):
    assert_per_pixel_outputs(outputs, inputs, where, shader_constants(basis))


def test_mirrors_agree_with_the_python_api(basis):
    """The K-term mirrors are the API's four-point solve (coefficients_from_nk, _gulbrandsen of the same basis)."""
    eta, kappa, a, b = per_pixel_inputs()[300:].T
    constants = shader_constants(basis)
    np.testing.assert_allclose(
        coefficients_per_pixel_nk(eta, kappa, constants), coefficients_from_nk(eta, kappa, basis), rtol=0, atol=1e-9
    )
    r = np.clip(a, 0.0, 0.99)
    np.testing.assert_allclose(
        coefficients_per_pixel_gulbrandsen(r, b, constants),
        coefficients_from_gulbrandsen(r, b, basis),
        rtol=0,
        atol=1e-8,
    )
    assert constants.curve_error <= 1e-4, constants.curve_error


def _glsl_main(calls, wide: bool) -> str:
    """One fragment shader writing ``calls``: one attachment each (K ≤ 4), two for the K > 4 records."""
    lines, outputs = [], 0
    for call in calls:
        if wide and "LutUV" not in call:
            lines.append(f"    {{ FresnelTerms8 t = {call}; out{outputs} = t.lo; out{outputs + 1} = t.hi; }}\n")
            outputs += 2
        else:
            lines.append(f"    out{outputs} = {call};\n")
            outputs += 1
    return (
        "\nuniform sampler2D inputs;\n"
        + "".join(f"layout(location = {k}) out vec4 out{k};\n" for k in range(outputs))
        + "void main() {\n    vec4 q = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);\n"
        + "".join(lines)
        + "}\n",
        outputs,
    )


def test_glsl_on_mesa_llvmpipe_matches_the_mirrors(basis):
    include = dict(includes_of(basis))["fresnel_basis.glsl"]
    inputs = per_pixel_inputs()
    wide = _wide(basis)
    groups = [PER_PIXEL_CALLS[:4], PER_PIXEL_CALLS[4:]]  # at most 8 attachments per draw
    outputs = []
    for calls in groups:
        main, count = _glsl_main(calls, wide)
        drawn = gl_draw("#version 330\n" + include + main, [inputs.reshape(32, 32, 4)], {"inputs": 0}, count)
        k = 0
        for call in calls:
            if wide and "LutUV" not in call:
                outputs.append(np.concatenate([drawn[k], drawn[k + 1]], axis=-1))
                k += 2
            else:
                outputs.append(drawn[k])
                k += 1
    _assert_outputs(outputs, inputs, basis, "llvmpipe")


def test_wgsl_on_webgpu_lavapipe_matches_the_mirrors(basis, monkeypatch):
    import wgpu

    include = dict(includes_of(basis))["fresnel_basis.wgsl"]
    lanes = 2 if _wide(basis) else 1
    stride = len(PER_PIXEL_CALLS) * lanes
    body = ""
    for k, call in enumerate(PER_PIXEL_CALLS):
        at = f"{stride}u * i + {k * lanes}u"
        if lanes == 2 and "LutUV" not in call:
            body += f"    {{ let t = {call}; outputs[{at}] = t.lo; outputs[{at} + 1u] = t.hi; }}\n"
        else:
            body += f"    outputs[{at}] = {call};\n"
    main = (
        "\n@group(0) @binding(0) var<storage, read> inputs: array<vec4f>;\n"
        "@group(0) @binding(1) var<storage, read_write> outputs: array<vec4f>;\n"
        "@compute @workgroup_size(64)\nfn main(@builtin(global_invocation_id) id: vec3<u32>) {\n"
        "    let i = id.x;\n    if (i >= arrayLength(&inputs)) { return; }\n    let q = inputs[i];\n" + body + "}\n"
    )
    device = wgpu_device(monkeypatch)
    inputs = per_pixel_inputs().astype(np.float32)
    usage = wgpu.BufferUsage
    input_buffer = device.create_buffer_with_data(data=inputs.tobytes(), usage=usage.STORAGE)
    output_buffer = device.create_buffer(size=len(inputs) * stride * 16, usage=usage.STORAGE | usage.COPY_SRC)
    data = wgpu_compute(
        device, include + main, [{"buffer": input_buffer}, {"buffer": output_buffer}], output_buffer, len(inputs)
    )
    output = np.frombuffer(data, np.float32).reshape(len(inputs), len(PER_PIXEL_CALLS), 4 * lanes)
    _assert_outputs([output[:, k] for k in range(len(PER_PIXEL_CALLS))], inputs, basis, "lavapipe")


def _validator():
    path = shutil.which("glslangValidator")
    if path is None:
        gpu_missing("glslangValidator (Debian glslang-tools)")
    return path


def test_hlsl_and_glsl_es_compile(basis, tmp_path):
    """The K-term include as an engine calls it: coefficients of both textures, the split sum, the light, the
    average; HLSL to SPIR-V and GLSL ES 3.00."""
    includes = dict(includes_of(basis))
    wide = _wide(basis)
    second = ("lut2, ", "lut2, ") if wide else ("", "")
    kind = "FresnelTerms8" if wide else "float4"
    hlsl = f"""
Texture2D<float4> lut;
Texture2D<float4> lut2;
SamplerState linearClamp;
float4 PixelMain(float4 position : SV_Position) : SV_Target
{{
    {kind} cR, cG, cB;
    fresnelCoefficientsGulbrandsen3(float3(0.9, 0.8, 0.5), float3(0.9, 0.9, 0.2), cR, cG, cB);
    {kind} tint = fresnelCoefficientsF82Tint(0.5, 0.5);
    float3 light = fresnelBasisDirect(0.5, cR, cG, tint) + fresnelBasisAverage(cR, cG, cB);
    return float4(light + fresnelBasisSplitSum(lut, {second[0]}linearClamp, 0.5, 0.3, cR, cG, cB), 1.0);
}}
"""
    (tmp_path / "material.hlsl").write_text(includes["fresnel_basis.hlsl"] + hlsl, encoding="utf-8")
    arguments = ["-D", "-V", "-e", "PixelMain", "-S", "frag", str(tmp_path / "material.hlsl")]
    compiled = subprocess.run([_validator(), *arguments, "-o", str(tmp_path / "m.spv")], capture_output=True, text=True)
    assert compiled.returncode == 0, compiled.stdout + compiled.stderr
    glsl = f"""
uniform highp sampler2D lut;
uniform highp sampler2D lut2;
out vec4 colour;
void main()
{{
    {kind.replace("float4", "vec4")} cR, cG, cB;
    fresnelCoefficientsNK3(vec3(0.18, 0.42, 1.37), vec3(3.42, 2.35, 1.77), cR, cG, cB);
    vec3 light = fresnelBasisDirect(0.5, cR, cG, cB) + fresnelBasisAverage(cR, cG, cB);
    colour = vec4(light + fresnelBasisSplitSum(lut, {second[1]}0.5, 0.3, cR, cG, cB), 1.0);
}}
"""
    head = "#version 300 es\nprecision highp float;\nprecision highp int;\n"
    (tmp_path / "material.frag").write_text(head + includes["fresnel_basis.glsl"] + glsl, encoding="utf-8")
    checked = subprocess.run([_validator(), str(tmp_path / "material.frag")], capture_output=True, text=True)
    assert checked.returncode == 0, checked.stdout + checked.stderr


def test_the_coefficient_table_path_of_other_sizes_on_llvmpipe(basis):
    """``fresnelCoefficientsGulbrandsenTable`` of a K-term include with a table of its basis (K − 1 channels; here the
    four-point table, seconds to build) against the mirror: c0 = r, c1 = f90 − r and the fetch, within 1e-5; K = 2
    reads nothing and K = 6, 8 (no table: more than five terms) solve, as their mirrors do."""
    from basis.coefficient_table import coefficient_table
    from handoff.shaders import coefficients_per_pixel_gulbrandsen_table

    k = basis.n_terms
    tabled = 3 <= k <= 5
    table = coefficient_table(basis, fit="four-point") if tabled else np.zeros((128, 512, 1))
    rgba = np.zeros(table.shape[:2] + (4,))
    rgba[..., : min(table.shape[2], 4)] = table[..., :4]
    inputs = per_pixel_inputs()
    wide = _wide(basis)
    main = """
uniform sampler2D inputs;
uniform sampler2D coefficientLut;
layout(location = 0) out vec4 lo;
layout(location = 1) out vec4 hi;
void main() {
    vec4 a = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0);
    TERMS c = fresnelCoefficientsGulbrandsenTable(coefficientLut, a.z, a.w);
    OUTPUTS
}
""".replace("TERMS", "FresnelTerms8" if wide else "vec4").replace(
        "OUTPUTS", "lo = c.lo;\n    hi = c.hi;" if wide else "lo = c;\n    hi = vec4(0.0);"
    )
    include = dict(includes_of(basis))["fresnel_basis.glsl"]
    uniforms = {"inputs": 0, "coefficientLut": 1} if tabled else {"inputs": 0}
    lo, hi = gl_draw("#version 330\n" + include + main, [inputs.reshape(32, 32, 4), rgba], uniforms, 2)
    got = np.concatenate([lo, hi], axis=-1)[:, :k]
    expected = coefficients_per_pixel_gulbrandsen_table(
        table if tabled else None, inputs[:, 2], inputs[:, 3], shader_constants(basis)
    )
    assert np.all(np.isfinite(got))
    tolerance = 1e-5 if k <= 5 else shader_constants(basis).float32_tolerance
    assert np.max(np.abs(got - expected)) <= tolerance, float(np.max(np.abs(got - expected)))
