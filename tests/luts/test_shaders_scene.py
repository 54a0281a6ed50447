"""A scene build's generated include (``fresnel-lut scene`` on a scene whose table holds a whole basis) runs for real:
its per-pixel functions match their Python mirrors for the scene's own basis and grid, and its table coordinates
read the written table (cropped roughness rows, √μo columns) so that the JSON's coefficients give the exact
split sum of every material within the error the plan reports. A scene without such a table (Schlick's) is read
by the shipped split-sum include at the remapped roughness (r − lo)/(hi − lo) its comment gives, to the same
bound.

GLSL on Mesa's llvmpipe; the HLSL and WGSL come from the same generator as the default build's, which
tests/luts/test_shaders_terms.py runs for bases of every size.
"""

import json
from pathlib import Path

import numpy as np
import pytest

from basis.angles import theta_spline
from basis.eigenbasis import Basis, default_basis
from fresnel_lut.scene import plan_scene, read_scene, write_scene
from handoff.exr import read_lut
from handoff.shaders import shader_constants
from handoff.shaders.include import PIXEL_TABLE_FUNCTIONS
from preintegrate.quadrature import directional_albedo
from tests.conftest import PER_PIXEL_CALLS, PER_PIXEL_GLSL_MAIN, assert_per_pixel_outputs, gl_draw, per_pixel_inputs

#: The shipped dielectrics example (four measured presets, r 0.15–0.4) on 32 columns: its own four-term basis holds
#: it (the plan's errors 1.1e-3 to 2.0e-3 at this width).
EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "dielectrics.toml"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    folder = tmp_path_factory.mktemp("scene")
    (folder / "scene.toml").write_text("size = 32\n" + EXAMPLE.read_text(encoding="utf-8"), encoding="utf-8")
    plan = plan_scene(read_scene(folder / "scene.toml"))
    assert plan.tables == ("scene-basis-4",)
    write_scene(plan, folder / "out")
    return plan, folder / "out"


def test_the_scene_writes_the_includes_of_its_own_basis(built):
    plan, out = built
    document = json.loads((out / "scene_coefficients.json").read_text(encoding="utf-8"))
    trained = Basis.read(out / "scene_basis.json")
    assert document["shader_includes"] == [f"fresnel_basis_scene.{suffix}" for suffix in ("glsl", "hlsl", "wgsl")]
    for name in document["shader_includes"]:
        text = (out / name).read_text(encoding="utf-8")
        assert f"fresnel:basis_hash = {trained.content_hash}" in text and "fresnel-lut scene scene.toml" in text
        # no per-pixel tables exist for the scene's own basis, so its include offers none of their functions
        assert not [function for function in PIXEL_TABLE_FUNCTIONS if function + "(" in text], name
        assert "fresnelCoefficientsGulbrandsen(" in text
    report = (out / "scene_report.md").read_text(encoding="utf-8")
    assert (
        f"Shader include: fresnel_basis_scene.glsl, fresnel_basis_scene.hlsl, fresnel_basis_scene.wgsl, generated from basis {trained.content_hash}"
        in report
    )


def test_a_scene_whose_rows_start_above_the_mirror_takes_the_rect_lights_fresnel_from_the_polynomial(built):
    """The scene's rows start at r = 0.15, so its table has no mirror row: its ``fresnelBasisRectLight`` evaluates the
    direct-light polynomial at V·H* (the default build's reads the table at (V·H*, r'), down to its r = 0 row), and so
    does the mirror; the functions that read down to r = 0 are left out of its include."""
    from handoff.shaders import direct_fresnel, rect_light_punctual, shader_includes

    plan, out = built
    constants = shader_constants(Basis.read(out / "scene_basis.json"), plan.grid)
    assert not constants.grid.holds_mirror
    text = (out / "fresnel_basis_scene.glsl").read_text(encoding="utf-8")
    body = text[text.index("vec3 fresnelBasisRectLight(") :]
    assert "fresnelBasisDirect(VdotH, cR, cG, cB)" in body[: body.index("\n}")]
    assert "fresnelBasisSmoothed" not in text and "fresnelMirrorLutUV" not in text
    default = dict(shader_includes())["fresnel_basis.glsl"]
    body = default[default.index("vec3 fresnelBasisRectLight(") :]
    assert "fresnelBasisSmoothed(lut, VdotH, spread, b.x, cR, cG, cB)" in body[: body.index("\n}")]
    coefficients, v_dot_h = np.full((5, 3, 4), 0.2), np.linspace(0.0, 1.0, 5)
    (table_path,) = [path for path in out.glob("*.exr") if "basis" in path.name]
    table = read_lut(table_path)[0]
    np.testing.assert_array_equal(
        rect_light_punctual(table, coefficients, v_dot_h, constants),
        direct_fresnel(coefficients, v_dot_h[:, None], constants),
    )


def test_glsl_per_pixel_on_mesa_llvmpipe_matches_the_mirrors_of_the_scene_basis(built):
    """The per-pixel calls of the default build's include test (their inputs' edges and bad values included),
    against the mirrors with the scene basis' constants on the scene's grid."""
    plan, out = built
    include = (out / "fresnel_basis_scene.glsl").read_text(encoding="utf-8")
    inputs = per_pixel_inputs()
    outputs = gl_draw(
        "#version 330\n" + include + PER_PIXEL_GLSL_MAIN,
        [inputs.reshape(32, 32, 4)],
        {"inputs": 0},
        len(PER_PIXEL_CALLS),
    )
    constants = shader_constants(Basis.read(out / "scene_basis.json"), plan.grid)
    assert_per_pixel_outputs(outputs, inputs, "llvmpipe, scene include", constants)


def _error_grid(plan, material) -> tuple[np.ndarray, np.ndarray]:
    """(μo, r) of the plan's error grid for one material: the columns and the midpoints in √μo between them, and of
    33 roughnesses over the scene's range those in the material's, with its end points."""
    root = np.arange(2 * plan.columns - 1) / (2.0 * (plan.columns - 1))
    roughness = np.linspace(*plan.roughness_range, 33)
    inside = (roughness >= material.roughness[0]) & (roughness <= material.roughness[1])
    roughness = np.unique(np.concatenate([roughness[inside], material.roughness]))
    mu, r = np.meshgrid(root**2, roughness)
    return mu.ravel(), r.ravel()


def _exact_split_sum(material, mu, r) -> np.ndarray:
    """(P, 3) F̄ of the material's exact curve (a spline in θ of its samples), integrated directly."""
    exact = theta_spline(default_basis().theta, material.curve, axis=0)
    return directional_albedo(lambda x: exact(np.arccos(np.clip(x, 0, 1))), mu, r**2)


FRAGMENT = """#version 330
{include}
uniform sampler2D lut;
uniform sampler2D inputs;
uniform vec4 cR;
uniform vec4 cG;
uniform vec4 cB;
out vec4 colour;
void main() {{
    vec2 q = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0).rg;
    colour = vec4(fresnelBasisSplitSum(lut, q.x, q.y, cR, cG, cB), 1.0);
}}
"""


def test_the_include_reads_the_written_table_to_the_exact_split_sum(built):
    """The written EXR on llvmpipe through fresnelBasisSplitSum with the JSON's coefficients, at the plan's error
    grid of each material (μo from 0 to 1, the columns and the midpoints in √μo; of 33 roughnesses over the
    scene's range those in the material's, and its end points), against F̄ of the material's exact curve
    integrated directly: within the error the plan reports for it, plus float32's 1e-6 (measured: the plan's own
    figures to 4e-8)."""
    plan, out = built
    include = (out / "fresnel_basis_scene.glsl").read_text(encoding="utf-8")
    document = json.loads((out / "scene_coefficients.json").read_text(encoding="utf-8"))
    table, _ = read_lut(out / "scene_ggx_own_basis_rgba.exr")
    for material in plan.scene.materials:
        coefficients = np.array(document["materials"][material.name]["coefficients"])  # (3, 4)
        mu, r = _error_grid(plan, material)
        inputs = np.zeros((64 * 64, 4), dtype=np.float32)
        inputs[: mu.size, 0], inputs[: mu.size, 1] = mu, r
        uniforms = {"lut": 0, "inputs": 1, **{f"c{c}": tuple(coefficients[k]) for k, c in enumerate("RGB")}}
        (gpu,) = gl_draw(FRAGMENT.format(include=include), [table, inputs.reshape(64, 64, 4)], uniforms, 1, size=64)
        error = float(np.max(np.abs(gpu[: mu.size, :3] - _exact_split_sum(material, mu, r))))
        assert error <= plan.errors[material.name] + 1e-6, (material.name, error, plan.errors[material.name])


SCHLICK_FRAGMENT = """#version 330
{include}
uniform sampler2D lut;
uniform sampler2D inputs;
uniform vec3 f0;
out vec4 colour;
void main() {{
    vec2 q = texelFetch(inputs, ivec2(gl_FragCoord.xy), 0).rg;
    colour = vec4(fresnelSchlickSplitSum(lut, q.x, q.y, f0), 1.0);
}}
"""


def test_a_schlick_scene_reads_through_its_own_include(tmp_path):
    """The shipped Schlick example on 32 columns: scene_ggx_schlick_rg.exr through the scene's own include
    (fresnel_basis_scene.glsl: its rows' remap built in, the roughness given as it is), F0 from the JSON (its weights
    are (F0, 1)), against each material's exact split sum on the plan's error grid: within the plan's error plus
    float32's 1e-6."""
    (tmp_path / "scene.toml").write_text(
        "size = 32\n" + (EXAMPLE.parent / "schlick_only.toml").read_text(encoding="utf-8"), encoding="utf-8"
    )
    plan = plan_scene(read_scene(tmp_path / "scene.toml"))
    assert plan.tables == ("schlick",)
    write_scene(plan, tmp_path / "out")
    include = (tmp_path / "out" / "fresnel_basis_scene.glsl").read_text(encoding="utf-8")
    document = json.loads((tmp_path / "out" / "scene_coefficients.json").read_text(encoding="utf-8"))
    table, header = read_lut(tmp_path / "out" / "scene_ggx_schlick_rg.exr")
    low, high = (float(value) for value in header["roughness_range"].split(","))
    for material in plan.scene.materials:
        weights = np.array(document["materials"][material.name]["coefficients"])  # (3, 2): (F0, 1) per channel
        assert np.all(weights[:, 1] == 1.0)
        mu, r = _error_grid(plan, material)
        inputs = np.zeros((64 * 64, 4), dtype=np.float32)
        inputs[: mu.size, 0], inputs[: mu.size, 1] = mu, r
        uniforms = {"lut": 0, "inputs": 1, "f0": tuple(weights[:, 0])}
        (gpu,) = gl_draw(SCHLICK_FRAGMENT.format(include=include), [table, inputs.reshape(64, 64, 4)], uniforms, 1, 64)
        error = float(np.max(np.abs(gpu[: mu.size, :3] - _exact_split_sum(material, mu, r))))
        assert error <= plan.errors[material.name] + 1e-6, (material.name, error, plan.errors[material.name])
