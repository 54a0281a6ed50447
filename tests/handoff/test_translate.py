"""The GLSL subset's printer (handoff/shaders/translate.py): what it makes of each construct, and the one-line error
for what the subset does not hold. Whether the printed includes compile and compute what their Python mirrors do is
tests/luts/ (glslang, Mesa's llvmpipe and lavapipe, WebGL 2)."""

from __future__ import annotations

import pytest

from handoff.shaders.translate import ShaderSourceError, translate

FUNCTION = """// a comment stays
float pick(float x, float y)
{
    float a = (x > 0.0) ? ((y > 0.0) ? y : -y) : x;  // nested
    y = a * 2.0;
    return (x < y) ? mix(x, y, 0.5) : atan(y, x);
}
"""


def test_conditionals_nest_into_select_and_a_reassigned_parameter_is_copied():
    wgsl = translate(FUNCTION, "wgsl")
    assert "fn pick(x: f32, yIn: f32) -> f32" in wgsl and "    var y = yIn;" in wgsl
    assert "let a: f32 = select(x, (select(-y, y, (y > 0.0))), (x > 0.0));  // nested" in wgsl
    assert "return select(atan2(y, x), mix(x, y, 0.5), (x < y));" in wgsl
    assert "// a comment stays" in wgsl
    hlsl = translate(FUNCTION, "hlsl")
    assert "float pick(float x, float y)" in hlsl and "lerp(x, y, 0.5)" in hlsl and "atan2(y, x)" in hlsl
    assert translate(FUNCTION, "glsl") == FUNCTION


TEXTURES = """vec3 fetch(sampler2D lut, vec2 uv)
{
    return textureLod(lut, uv, 0.0).rgb;
}

vec3 twice(sampler2D table, vec2 uv, float k)
{
    vec3 p[4];
    for (int i = 0; i < 4; ++i)
    {
        p[i] = fetch(table, uv) * k;
    }
    return p[0] + p[3];
}
"""


def test_textures_take_one_sampler_which_calls_pass_on():
    hlsl = translate(TEXTURES, "hlsl")
    assert "float3 fetch(Texture2D<float4> lut, SamplerState linearClamp, float2 uv)" in hlsl
    assert "lut.SampleLevel(linearClamp, uv, 0).rgb" in hlsl and "fetch(table, linearClamp, uv) * k" in hlsl
    assert "float3 p[4];" in hlsl and "for (int i = 0; i < 4; ++i)" in hlsl
    wgsl = translate(TEXTURES, "wgsl")
    assert "fn fetch(lut: texture_2d<f32>, linearClamp: sampler, uv: vec2f) -> vec3f" in wgsl
    assert "textureSampleLevel(lut, linearClamp, uv, 0.0).rgb" in wgsl
    assert "var p: array<vec3f, 4>;" in wgsl and "for (var i = 0; i < 4; i++)" in wgsl


def test_constants_structs_and_out_parameters():
    source = """const vec2 SCALE = vec2(1.0, 2.0);  // two
const float TABLE[3] = float[3](
    1.0,
    2.0,
    3.0
);
struct Pair
{
    vec4 lo;  // first
    vec4 hi;
};

void both(float x, out float a, out float b)
{
    a = x;
    b = -x;
}
"""
    hlsl = translate(source, "hlsl")
    assert "static const float2 SCALE = float2(1.0, 2.0);  // two" in hlsl
    assert "static const float TABLE[3] = {\n    1.0,\n    2.0,\n    3.0\n};" in hlsl
    assert "struct Pair\n{\n    float4 lo;  // first\n    float4 hi;\n};" in hlsl
    assert "void both(float x, out float a, out float b)" in hlsl
    wgsl = translate(source, "wgsl")
    assert "const SCALE: vec2f = vec2f(1.0, 2.0);  // two" in wgsl
    assert "var<private> TABLE: array<float, 3> = array<float, 3>(" not in wgsl
    assert "var<private> TABLE: array<f32, 3> = array<f32, 3>(\n    1.0," in wgsl
    assert "struct Pair\n{\n    lo: vec4f,  // first\n    hi: vec4f,\n}" in wgsl
    assert "// both: GLSL and HLSL only (WGSL has no out parameters)" in wgsl


@pytest.mark.parametrize(
    "source, fragment",
    [
        ("float f(float x)\n{\n    return textureLod(t, x, 1.0);\n}\n", "reads level 0 only"),
        ("float f(float x) {\n    return x;\n}\n", "not a declaration the subset knows"),
        ("float f(float x)\n{\n    while (x > 0.0) x -= 1.0;\n}\n", "a statement the subset does not know"),
        ("float f(inout float x)\n{\n    return x;\n}\n", "a parameter the subset does not know"),
        ("float f(float x)\n{\n    return x > 0.0 ? x;\n}\n", "a conditional without its ':'"),
        ("uniform float x;\n", "not a declaration the subset knows"),
        ("#ifndef SWITCH\n#define SWITCH 2\n#endif\n", "a switch is #ifndef NAME"),
    ],
)
def test_what_the_subset_does_not_hold_is_one_line_naming_it(source, fragment):
    with pytest.raises(ShaderSourceError, match=fragment) as refused:
        translate(source, "wgsl")
    assert "\n" not in str(refused.value)


def test_an_unknown_language_is_refused():
    with pytest.raises(ShaderSourceError, match=r"language must be one of \['glsl', 'hlsl', 'wgsl'\]"):
        translate("", "msl")


def test_a_switch_is_a_define_in_hlsl_and_a_pipeline_constant_in_wgsl():
    source = "#ifndef SOLVE\n#define SOLVE false\n#endif\nfloat f(float x)\n{\n    if (SOLVE)\n    {\n        return x;\n    }\n    return -x;\n}\n"
    assert translate(source, "hlsl").startswith("#ifndef SOLVE\n#define SOLVE false\n#endif\n")
    wgsl = translate(source, "wgsl")
    assert wgsl.startswith("override SOLVE: bool = false;\nfn f(x: f32) -> f32") and "    if (SOLVE)" in wgsl
