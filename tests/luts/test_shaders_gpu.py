"""The shipped shader include runs for real, against the Python API on a grid of (NdotV, r) that holds texel centres,
midpoints, edges and values out of range:

* GLSL: compiled by glslangValidator (GLSL 330, 450, ES 300 and SPIR-V for Vulkan) and executed on OpenGL
  (Mesa's llvmpipe through a headless EGL context, moderngl);
* WGSL: executed by WebGPU (wgpu on Mesa's lavapipe Vulkan driver) in a compute shader;
* HLSL: compiled to SPIR-V by glslang's HLSL front end.

Each fragment of a 32 × 32 framebuffer reads its own (NdotV, r) from an input texture, so neighbouring
fragments ask for distant texels: screen-space derivatives are large, and a LUT read with texture() would
take a coarse mip level of a mipmapped table. The include reads level 0 (textureLod), so the mipmapped and
the plain texture must give the same answer. The set-up (make's .installed-stamp, as root) installs
glslang-tools and Mesa (OpenGL and Vulkan); under CI=true a missing tool is a failure, not a skip.
"""

import shutil
import struct
import subprocess

import numpy as np
import pytest

from basis import coefficients_from_nk
from basis.storage import shipped_path
from handoff.exr import read_lut
from handoff.formats import ktx2_bytes
from handoff.shipped import BASIS_LUT, SCHLICK_LUT, shipped_lut, shipped_tables
from preintegrate.lut import LutGrid, lut_lookup
from preintegrate.multiple_scattering import basis_albedo
from tests.conftest import gl_draw, gpu_missing, wgpu_compute, wgpu_device

INCLUDE = shipped_path("fresnel_basis.glsl").read_text(encoding="utf-8")
GOLD = coefficients_from_nk([0.18, 0.42, 1.37], [3.42, 2.35, 1.77])  # (3, 4)
F0 = np.array([0.9, 0.6, 0.3])


def _grid() -> tuple[np.ndarray, np.ndarray]:
    """1024 (NdotV, r): centres, midpoints and edges of the 128² grid, 0 and 1, and out-of-range values."""
    special = np.array([0.0, 0.5 / 128, 1.0 / 128, 0.3, 0.5 + 0.25 / 128, 1.0 - 0.5 / 128, 1.0, -0.2, 1.3])
    rng = np.random.default_rng(15)
    n_dot_v = np.concatenate([np.repeat(special, special.size), rng.uniform(-0.1, 1.1, 1024 - special.size**2)])
    roughness = np.concatenate([np.tile(special, special.size), rng.uniform(-0.1, 1.1, 1024 - special.size**2)])
    return n_dot_v, roughness


FRAGMENT = """#version 330
{include}
uniform sampler2D basisLut;
uniform sampler2D schlickLut;
uniform sampler2D inputs;
uniform vec4 cR; uniform vec4 cG; uniform vec4 cB; uniform vec3 F0; uniform vec4 averages;
layout(location = 0) out vec4 basisOut;
layout(location = 1) out vec4 schlickOut;
layout(location = 2) out vec4 multipleOut;
void main() {{
    vec2 q = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0).rg;
    basisOut = vec4(fresnelBasisSplitSum(basisLut, q.x, q.y, cR, cG, cB), 1.0);
    schlickOut = vec4(fresnelSchlickSplitSum(schlickLut, q.x, q.y, F0), 1.0);
    multipleOut = vec4(fresnelBasisMultipleScattering(basisLut, q.x, q.y, cR, cG, cB), 1.0);
}}
"""


def _draw(fragment: str, tables, uniforms: dict, outputs: int, mipmaps: bool = False) -> list[np.ndarray]:
    """:func:`tests.conftest.gl_draw` with the fragments' (NdotV, r) of :func:`_grid` on the unit after the tables;
    the first three channels of each output, (1024, 3)."""
    n_dot_v, roughness = _grid()
    inputs = np.stack([n_dot_v, roughness], -1).reshape(32, 32, 2)
    drawn = gl_draw(fragment, [*tables, inputs], {"inputs": len(tables), **uniforms}, outputs, mipmaps=mipmaps)
    return [values[:, :3] for values in drawn]


def _render(mipmaps: bool) -> list[np.ndarray]:
    uniforms = {
        "basisLut": 0,
        "schlickLut": 1,
        **{name: tuple(GOLD[k]) for k, name in enumerate(("cR", "cG", "cB"))},
        "F0": tuple(F0),
    }
    return _draw(FRAGMENT.format(include=INCLUDE), shipped_tables(), uniforms, outputs=3, mipmaps=mipmaps)


def _expected() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    n_dot_v, roughness = (np.clip(values, 0.0, 1.0) for values in _grid())
    basis_table, schlick_table = shipped_tables()
    basis = lut_lookup(basis_table, n_dot_v, roughness) @ GOLD.T
    scale_bias = lut_lookup(schlick_table, n_dot_v, roughness)
    multiple = basis_albedo(GOLD, n_dot_v, roughness, tables=(basis_table, schlick_table))
    return basis, F0 * scale_bias[:, :1] + scale_bias[:, 1:2], multiple


SIX_TERMS_FRAGMENT = """#version 330
{include}
uniform sampler2D basisLut;
uniform sampler2D basisLut2;
uniform sampler2D inputs;
uniform vec4 cR; uniform vec4 cG; uniform vec4 cB; uniform vec4 eR; uniform vec4 eG; uniform vec4 eB;
layout(location = 0) out vec4 basisOut;
void main() {{
    vec2 q = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0).rg;
    FresnelTerms8 tR = fresnelTerms8(cR, eR), tG = fresnelTerms8(cG, eG), tB = fresnelTerms8(cB, eB);
    basisOut = vec4(fresnelBasisSplitSum(basisLut, basisLut2, q.x, q.y, tR, tG, tB), 1.0);
}}
"""


def test_six_terms_in_two_tables_on_mesa_llvmpipe_match_the_python_api(tmp_path):
    """A six-term basis (``basis --terms 6``, then ``build``): terms 0-3 in ggx_basis_rgba.exr, 4-5 in the R, G
    of ggx_basis_rgba_2.exr, a two-channel texture whose A reads as 1 (its coefficient is 0), read by the include
    that build writes (FresnelTerms8 per channel, two textures). Measured: max |GPU − Python| 1.4e-7."""
    from basis.training import build_basis
    from fresnel_lut.cli import main

    basis = build_basis(count=5000, n_terms=6, grid_size=128)
    basis.write(tmp_path / "basis6.json")
    assert main(["build", "--basis", str(tmp_path / "basis6.json"), "--size", "32", "--out", str(tmp_path)]) == 0
    first, header = read_lut(tmp_path / BASIS_LUT)
    second, second_header = read_lut(tmp_path / "ggx_basis_rgba_2.exr")
    assert first.shape[-1] == 4 and second.shape[-1] == 2 and second_header["terms"] == "4-5 of 6"
    coefficients = coefficients_from_nk([0.18, 0.42, 1.37], [3.42, 2.35, 1.77], basis)  # (3, 6)
    extra = np.zeros((3, 4))
    extra[:, :2] = coefficients[:, 4:]
    uniforms = {
        "basisLut": 0,
        "basisLut2": 1,
        **{f"c{colour}": tuple(coefficients[k, :4]) for k, colour in enumerate("RGB")},
        **{f"e{colour}": tuple(extra[k]) for k, colour in enumerate("RGB")},
    }
    include = (tmp_path / "fresnel_basis.glsl").read_text(encoding="utf-8")
    (gpu,) = _draw(SIX_TERMS_FRAGMENT.format(include=include), (first, second), uniforms, outputs=1)
    clipped = [np.clip(values, 0.0, 1.0) for values in _grid()]
    grid = LutGrid(32, 32)
    expected = grid.lookup(np.concatenate([first, second], axis=-1), *clipped) @ coefficients.T
    np.testing.assert_allclose(gpu, expected, rtol=0, atol=1e-6)


@pytest.mark.parametrize("mipmaps", [False, True], ids=["plain texture", "mipmapped texture"])
def test_glsl_on_mesa_llvmpipe_matches_the_python_api(mipmaps):
    """Measured: max |GPU − Python| 1.1e-7 (float32) with and without mipmaps, 2.2e-7 with the multiple-
    scattering terms; the former include's texture()
    was off by 0.63 on the mipmapped table (a coarse level picked from the fragments' derivatives)."""
    basis, schlick, multiple = _render(mipmaps)
    expected_basis, expected_schlick, expected_multiple = _expected()
    np.testing.assert_allclose(basis, expected_basis, rtol=0, atol=1e-6)
    np.testing.assert_allclose(schlick, expected_schlick, rtol=0, atol=1e-6)
    np.testing.assert_allclose(multiple, expected_multiple, rtol=0, atol=2e-6)  # the multiple-scattering terms


def _validator():
    path = shutil.which("glslangValidator")
    if path is None:
        gpu_missing("glslangValidator (Debian glslang-tools)")
    return path


WRAPPERS = {
    "330": ("#version 330\n", "uniform sampler2D lut;\nout vec4 colour;\n"),
    "450": ("#version 450\n", "layout(binding = 0) uniform sampler2D lut;\nlayout(location = 0) out vec4 colour;\n"),
    "es300": (
        "#version 300 es\nprecision highp float;\nprecision highp sampler2D;\n",
        "uniform sampler2D lut;\nout vec4 colour;\n",
    ),
}


@pytest.mark.parametrize("version", sorted(WRAPPERS))
def test_glsl_include_compiles(version, tmp_path):
    """The include compiles as GLSL 3.30, 4.50 and ES 3.00 (WebGL 2), and 4.50 also to SPIR-V for Vulkan."""
    validator = _validator()
    head, declarations = WRAPPERS[version]
    source = tmp_path / f"lut_{version}.frag"
    source.write_text(
        head
        + INCLUDE
        + declarations
        + """
void main() {
    colour = vec4(fresnelBasisSplitSum(lut, 0.5, 0.3, vec4(1.0), vec4(0.5), vec4(0.25))
                  + fresnelBasisMultipleScattering(lut, 0.5, 0.3, vec4(1.0), vec4(0.5), vec4(0.25))
                  + fresnelSchlickSplitSum(lut, 0.5, 0.3, vec3(0.04)), 1.0);
}
""",
        encoding="utf-8",
    )
    checked = subprocess.run([validator, str(source)], capture_output=True, text=True)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    if version == "450":
        spirv = subprocess.run(
            [validator, "-V", str(source), "-o", str(tmp_path / "lut.spv")], capture_output=True, text=True
        )
        assert spirv.returncode == 0 and (tmp_path / "lut.spv").stat().st_size > 0, spirv.stdout + spirv.stderr


def test_hlsl_include_compiles_to_spirv(tmp_path):
    """The HLSL include (Shader Model 4+, SampleLevel at 0) through glslang's HLSL front end to SPIR-V."""
    validator = _validator()
    source = tmp_path / "lut.hlsl"
    source.write_text(
        shipped_path("fresnel_basis.hlsl").read_text(encoding="utf-8")
        + """
Texture2D<float4> basisLut : register(t0);
Texture2D<float4> schlickLut : register(t1);
SamplerState linearClamp : register(s0);
float4 PixelMain(float4 position : SV_Position) : SV_Target
{
    return float4(fresnelBasisSplitSum(basisLut, linearClamp, 0.5, 0.3, float4(1, 0, 0, 0), float4(0, 1, 0, 0),
                                       float4(0, 0, 1, 0))
                  + fresnelBasisMultipleScattering(basisLut, linearClamp, 0.5, 0.3, float4(1, 0, 0, 0),
                                                   float4(0, 1, 0, 0), float4(0, 0, 1, 0))
                  + fresnelSchlickSplitSum(schlickLut, linearClamp, 0.5, 0.3, float3(0.04, 0.04, 0.04)), 1.0);
}
""",
        encoding="utf-8",
    )
    compiled = subprocess.run(
        [validator, "-D", "-V", "-e", "PixelMain", "-S", "frag", str(source), "-o", str(tmp_path / "lut.spv")],
        capture_output=True,
        text=True,
    )
    assert compiled.returncode == 0 and (tmp_path / "lut.spv").stat().st_size > 0, compiled.stdout + compiled.stderr


WGSL_MAIN = """
struct Coefficients { cR: vec4<f32>, cG: vec4<f32>, cB: vec4<f32>, F0: vec4<f32> };
@group(0) @binding(0) var basisLut: texture_2d<f32>;
@group(0) @binding(1) var schlickLut: texture_2d<f32>;
@group(0) @binding(2) var linearClamp: sampler;
@group(0) @binding(3) var<storage, read> inputs: array<vec2<f32>>;
@group(0) @binding(4) var<storage, read_write> outputs: array<vec4<f32>>;
@group(0) @binding(5) var<uniform> c: Coefficients;
@compute @workgroup_size(64)
fn main(@builtin(global_invocation_id) id: vec3<u32>) {
    let i = id.x;
    if (i >= arrayLength(&inputs)) { return; }
    let q = inputs[i];
    outputs[2u * i] = vec4<f32>(fresnelBasisSplitSum(basisLut, linearClamp, q.x, q.y, c.cR, c.cG, c.cB), 1.0);
    outputs[2u * i + 1u] = vec4<f32>(fresnelSchlickSplitSum(schlickLut, linearClamp, q.x, q.y, c.F0.xyz), 1.0);
}
"""


def test_wgsl_on_webgpu_lavapipe_matches_the_python_api(monkeypatch):
    """The tables reach the GPU as KTX2 (``build --format ktx2``) level data. Measured: max |GPU − Python|
    1.4e-7 (basis) and 1.0e-7 (Schlick), float32 tables with the float32-filterable feature."""
    device = wgpu_device(monkeypatch, ["float32-filterable"])
    import wgpu

    def view(name):
        """Upload as a KTX2 loader does: the file's level 0 bytes, as they stand, to the format its vkFormat
        names (109 = VK_FORMAT_R32G32B32A32_SFLOAT = rgba32float)."""
        table, header = read_lut(shipped_lut(name))
        ktx = ktx2_bytes(table, header)
        vk_format, width, height = struct.unpack_from("<I4xII", ktx, 12)
        level_offset, level_length = struct.unpack_from("<2Q", ktx, 80)
        assert vk_format == 109
        texture = device.create_texture(
            size=(width, height, 1),
            format=wgpu.TextureFormat.rgba32float,
            usage=wgpu.TextureUsage.TEXTURE_BINDING | wgpu.TextureUsage.COPY_DST,
        )
        device.queue.write_texture(
            {"texture": texture},
            ktx[level_offset : level_offset + level_length],
            {"bytes_per_row": width * 16, "rows_per_image": height},
            (width, height, 1),
        )
        return texture.create_view()

    n_dot_v, roughness = _grid()
    inputs = np.stack([n_dot_v, roughness], -1).astype(np.float32)
    uniform = np.concatenate([GOLD.ravel(), F0, [0.0]]).astype(np.float32)
    usage = wgpu.BufferUsage
    input_buffer = device.create_buffer_with_data(data=inputs.tobytes(), usage=usage.STORAGE)
    output_buffer = device.create_buffer(size=len(inputs) * 2 * 16, usage=usage.STORAGE | usage.COPY_SRC)
    uniform_buffer = device.create_buffer_with_data(data=uniform.tobytes(), usage=usage.UNIFORM)
    sampler = device.create_sampler(
        mag_filter="linear", min_filter="linear", address_mode_u="clamp-to-edge", address_mode_v="clamp-to-edge"
    )
    data = wgpu_compute(
        device,
        shipped_path("fresnel_basis.wgsl").read_text(encoding="utf-8") + WGSL_MAIN,
        [
            view(BASIS_LUT),
            view(SCHLICK_LUT),
            sampler,
            {"buffer": input_buffer},
            {"buffer": output_buffer},
            {"buffer": uniform_buffer},
        ],
        output_buffer,
        len(inputs),
    )
    output = np.frombuffer(data, np.float32).reshape(len(inputs), 2, 4)
    expected_basis, expected_schlick, _ = _expected()
    np.testing.assert_allclose(output[:, 0, :3], expected_basis, rtol=0, atol=1e-6)
    np.testing.assert_allclose(output[:, 1, :3], expected_schlick, rtol=0, atol=1e-6)
