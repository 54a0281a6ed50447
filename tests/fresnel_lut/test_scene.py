"""Scene builds (fresnel_lut/scene.py, fresnel-lut scene): only what a scene needs, and what it costs.

Independent checks: texels of the written tables against VNDF Monte Carlo of the material's own curve
(4σ), cropped rows against the full table interpolated in roughness (bounded by h²/8 · max |∂²F̄/∂r²|, estimated from the table, × 2),
and the chosen channel count against the per-layout errors the plan measured.
"""

import json

import numpy as np
import pytest

from basis.models import fresnel_model
from basis.storage import shipped_path
from fresnel_lut import cli
from fresnel_lut.scene import DEFAULT_TOLERANCE, SceneError, plan_scene, read_scene, write_scene
from handoff.exr import read_lut
from handoff.shipped import BASIS_LUT
from preintegrate.channels import basis_channels
from preintegrate.estimators import monte_carlo_albedo
from preintegrate.lut import LutGrid, build_table
from preintegrate.quadrature import directional_albedo

SIZE = 32


def scene_file(tmp_path, body: str, name="scene.toml", size: int = SIZE) -> str:
    path = tmp_path / name
    path.write_text(f"size = {size}\n" + body, encoding="utf-8")
    return path


SCHLICK_ONLY = """
[[material]]
name = "paint"
f0 = 0.04
roughness = [0.3, 0.7]
[[material]]
name = "rubber"
model = "fresnel-blend"
rs = [0.03, 0.04, 0.05]
roughness = 0.8
"""

DIELECTRICS = """
[[material]]
name = "window"
preset = "Glass BK7"
roughness = [0.2, 0.4]
[[material]]
name = "pond"
preset = "Water"
roughness = [0.25, 0.5]
"""


@pytest.mark.parametrize(
    "material",
    [
        'model = "schlick-external"\nf0 = [0.9, 0.6, 0.3]\neta_e = 1.33',
        'model = "schlick-external-metal"\nf0 = 0.5\neta_e = 2.0',
        'model = "fresnel-blend"\nrs = 0.04',
        'model = "generalized-schlick"\nr0 = 0.04\nr90 = 1.0\nexponent = 5.0',
    ],
)
def test_models_with_schlicks_functions_get_the_schlick_table(tmp_path, material):
    """A model whose fixed functions are Schlick's (1 - (1-x)^5, (1-x)^5) reads the Schlick table, not a
    second copy of it under its own name."""
    path = tmp_path / "scene.toml"
    path.write_text(f'[[material]]\nname = "m"\n{material}\nroughness = 0.4\n', encoding="utf-8")
    plan = plan_scene(read_scene(path))
    assert plan.tables == ("schlick",) and plan.layouts == {"m": "schlick"}
    assert plan.errors["m"] <= plan.scene.tolerance


def test_schlick_only_scene_gets_the_two_channel_table(tmp_path):
    plan = plan_scene(read_scene(scene_file(tmp_path, SCHLICK_ONLY)))
    assert plan.tables == ("schlick",) and set(plan.layouts.values()) == {"schlick"}
    assert {plan.path(name)["choice"] for name in plan.layouts} == {"exact table"}
    result = write_scene(plan, tmp_path / "out")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        *(f"fresnel_basis_scene.{language}" for language in ("glsl", "hlsl", "wgsl")),
        "scene_coefficients.json",
        "scene_ggx_schlick_rg.exr",
        "scene_report.md",
    ]
    table, header = read_lut(tmp_path / "out" / "scene_ggx_schlick_rg.exr")
    assert table.shape == (plan.rows, SIZE, 2) and header["roughness_range"] == "0.3,0.8"
    # a texel of the written table, combined with the paint's weights, against Monte Carlo of Schlick
    rows = np.linspace(0.3, 0.8, plan.rows)
    j, i = 1, 11
    mu_o = plan.grid.mu_o[i]
    fbar = table[j, i] @ np.array([0.04, 1.0])
    mean, error = monte_carlo_albedo(
        lambda x: fresnel_model("schlick").evaluate(x, f0=0.04), mu_o, rows[j] ** 2, samples=400_000, seed=3
    )
    assert abs(fbar - mean) < 4.0 * error + 1e-6
    assert max(plan.errors.values()) <= DEFAULT_TOLERANCE
    assert "Left out: basis-4" in result["text"]
    assert "Shader include: fresnel_basis_scene.glsl" in result["text"]
    assert "fresnelBasisLutUV addresses every table above (its rows span roughness 0.3-0.8)" in result["text"]


def test_dielectric_scene_gets_the_terms_the_measurements_justify(tmp_path):
    """Four channels at 1/255, and then the scene's own basis, more accurate than the generic one; three
    generic terms at 0.013, where one term fewer or Schlick fail (16 columns: no layout reaches one 10-bit step
    there, so the plan aims at the tolerance and need not prefer four terms for accuracy)."""
    plan = plan_scene(read_scene(scene_file(tmp_path, f"tolerance = {DEFAULT_TOLERANCE}\n" + DIELECTRICS)))
    full = plan.full_errors
    assert plan.tables == ("scene-basis-4",)
    assert plan.path("window")["choice"] == "basis"
    assert "no linear model's table holds a curve of its kind" in plan.path("window")["why"]
    assert all(full["scene-basis-4"][name] < full["basis-4"][name] for name in plan.layouts)
    assert any(full["basis-3"][name] > DEFAULT_TOLERANCE for name in plan.layouts)
    plan = plan_scene(read_scene(scene_file(tmp_path, "tolerance = 0.013\n" + DIELECTRICS, size=16)))
    full = plan.full_errors
    assert plan.tables == ("basis-3",)
    assert all(full["basis-3"][name] <= 0.013 for name in plan.layouts)
    assert any(full["basis-2"][name] > 0.013 for name in plan.layouts)  # one term fewer fails
    assert any(full["schlick"][name] > 0.013 for name in plan.layouts)


def test_narrow_range_is_cropped_and_matches_the_full_table(tmp_path):
    plan = plan_scene(read_scene(scene_file(tmp_path, DIELECTRICS)))
    write_scene(plan, tmp_path / "out")
    cropped, header = read_lut(tmp_path / "out" / "scene_ggx_own_basis_rgba.exr")
    assert header["roughness_range"] == "0.2,0.5" and cropped.shape[0] == plan.rows < SIZE
    channels = basis_channels(plan.candidates["scene-basis-4"].trained)
    rows = np.linspace(0.2, 0.5, plan.rows)
    # exact: the rows are integrated at their own roughness
    direct = directional_albedo(channels.functions, plan.grid.mu_o[None, :], (rows**2)[:, None])
    np.testing.assert_allclose(cropped, direct, atol=2e-6)
    # the full table of the same channels, interpolated linearly in r, agrees within its interpolation error
    full_grid = LutGrid(SIZE, SIZE)  # the scene's columns (the default build's), rows over 0–1
    full = build_table(channels, full_grid)
    spacing = 1.0 / (SIZE - 1)
    interpolated = np.stack(
        [[np.interp(rows, full_grid.roughness, full[:, i, k]) for k in range(4)] for i in range(SIZE)]
    ).transpose(2, 0, 1)
    curvature = np.max(np.abs(np.diff(full, 2, axis=0)), axis=0) / spacing**2  # max |∂²F̄/∂r²| per texel column
    # linear interpolation error ≤ h²/8 · max |∂²F̄/∂r²|; the second difference of a 16-row table
    # underestimates the derivative's maximum, hence the factor 2
    bound = 2.0 * spacing**2 / 8.0 * curvature + 1e-6
    assert np.all(np.abs(interpolated - cropped) <= bound[None])


def test_unmeetable_tolerance_is_refused_by_name_and_nothing_is_written(tmp_path, capsys):
    path = scene_file(
        tmp_path,
        """
tolerance = 0.0001
[[material]]
name = "old copper"
f0 = [0.95, 0.64, 0.54]
f82 = [0.93, 0.60, 0.50]
roughness = [0.3, 0.6]
""",
    )
    with pytest.raises(SceneError, match=r"material 'old copper' cannot meet tolerance 0.0001.*use tolerance >= "):
        plan_scene(read_scene(path))
    assert cli.main(["scene", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "old copper" in err and "Traceback" not in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize(
    "body, message",
    [
        ("[[material]\nname = 'x'", "not valid TOML"),
        ("[[material]]\nname = 'x'\nf0 = 0.04", "roughness (a number or [low, high]) is missing"),
        ("colour = 1\n[[material]]\nf0 = 0.04\nroughness = 0.5", "unknown keys ['colour']"),
        ("[[material]]\npreset = 'Unobtainium'\nroughness = 0.5", "material must be one of"),
        ("[[material]]\nf0 = 1.5\nroughness = 0.5", "f0 must be in [0, 1]"),
        ("[[material]]\nf0 = 0.04\nroughness = [0.6, 0.2]", "[low, high]"),
        (
            "[[material]]\nname='a'\nf0 = 0.04\nroughness = 0.5\n[[material]]\nname='a'\nf0 = 0.04\nroughness = 0.5",
            "appears twice",
        ),
        ("[[material]]\nf0 = 0.04\nkappa = 1\nroughness = 0.5", "give one of"),
        ("space = 'P3'\n[[material]]\nf0 = 0.04\nroughness = 0.5", "space must be one of"),
    ],
)
def test_bad_scene_files(tmp_path, body, message, capsys):
    path = scene_file(tmp_path, body)
    with pytest.raises(SceneError, match=None) as caught:
        read_scene(path)
    assert message in str(caught.value)
    assert cli.main(["scene", str(path), "--out", str(tmp_path / "out")]) == 2
    assert message in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_json_scene_and_coefficients_file(tmp_path):
    path = tmp_path / "scene.json"
    path.write_text(
        json.dumps(
            {
                "size": SIZE,
                "tolerance": 0.01,
                "material": [
                    {"name": "gold", "preset": "Gold", "roughness": [0.4, 0.6]},
                    {"name": "steel", "eta": [2.9, 2.9, 2.8], "kappa": [3.1, 3.0, 2.9], "roughness": 0.5},
                ],
            }
        ),
        encoding="utf-8",
    )
    plan = plan_scene(read_scene(path))
    write_scene(plan, tmp_path / "out")
    document = json.loads((tmp_path / "out" / "scene_coefficients.json").read_text(encoding="utf-8"))
    for name, entry in document["materials"].items():
        table, header = read_lut(tmp_path / "out" / entry["lut"])
        assert np.array(entry["coefficients"]).shape == (3, table.shape[-1])
        assert document["convention"] == header["convention"] and "sqrt(mu_o) = i / (width - 1)" in header["convention"]
        assert entry["max_abs_error_fbar"] <= document["tolerance"]
        assert (tmp_path / "out" / entry["lut"]).exists()


def test_interrupted_write_leaves_nothing_half_written(tmp_path, monkeypatch):
    """The tables, scene_coefficients.json and scene_report.md are renamed together: a failure at the
    last rename rolls the others back, no temporary is left, and the folder the write created is removed."""
    import basis.storage

    plan = plan_scene(read_scene(scene_file(tmp_path, DIELECTRICS)))
    original, calls = basis.storage.os.replace, []

    def failing(source, target):
        calls.append(target)
        if str(target).endswith("scene_report.md"):
            raise KeyboardInterrupt
        return original(source, target)

    monkeypatch.setattr(basis.storage.os, "replace", failing)
    with pytest.raises(KeyboardInterrupt):
        write_scene(plan, tmp_path / "out")
    assert len(calls) >= 3
    assert not (tmp_path / "out").exists()


def test_f82_material_gets_its_own_exact_table_when_the_basis_cannot_hold_it(tmp_path):
    """A strong-dip F0/F82 copper: the basis reaches only ~1e-2, Hoffman 2019's own three channels
    (exact split sum: the dip stays in [0, 1]) meet 1/255; the written table combines to Monte Carlo."""
    path = scene_file(  # 32 columns: the lookup alone costs 6.8e-4 (lookup_floor)
        tmp_path,
        """
[[material]]
name = "old copper"
f0 = [0.95, 0.64, 0.54]
f82 = [0.93, 0.60, 0.50]
roughness = [0.3, 0.6]
""",
        name="f82.toml",
    )
    plan = plan_scene(read_scene(path))
    assert plan.full_errors["basis-4"]["old copper"] > DEFAULT_TOLERANCE
    assert plan.tables == ("model:f82",) and plan.errors["old copper"] <= DEFAULT_TOLERANCE
    # README's rule, said where the plan is written: a linear model inside [0, 1] takes its exact table
    assert plan.path("old copper") == {
        "choice": "exact table",
        "why": f"model:f82 holds its curve exactly: what remains ({plan.errors['old copper']:.2e} in Fbar) is the "
        "bilinear lookup",
    }
    result = write_scene(plan, tmp_path / "out")
    written = json.loads((tmp_path / "out" / "scene_coefficients.json").read_text(encoding="utf-8"))
    assert written["materials"]["old copper"]["path"] == plan.path("old copper")
    assert "- old copper: exact table (model:f82 holds its curve exactly" in result["text"]
    table, header = read_lut(tmp_path / "out" / "scene_ggx_f82.exr")
    assert table.shape[-1] == 3 and "x (1-x)^6" in header["combination"]
    weights = np.array(plan.coefficients["old copper"])
    rows = np.linspace(0.3, 0.6, plan.rows)
    j, i = 0, 9
    model = fresnel_model("f82")
    f0, f82 = np.array([0.95, 0.64, 0.54]), np.array([0.93, 0.60, 0.50])
    mean, error = monte_carlo_albedo(
        lambda x: model.evaluate(x[..., None], f0=f0, f82=f82), plan.grid.mu_o[i], rows[j] ** 2, samples=400_000, seed=8
    )
    np.testing.assert_array_less(np.abs(weights @ table[j, i] - mean), 4.0 * error + 1e-6)


def test_a_linear_model_the_scenes_basis_holds_as_well_says_why_it_is_not_on_its_exact_table(tmp_path):
    """An F82-tint brass beside a glass: the scene's own basis, which the glass needs, holds the brass as closely as
    its exact table (both at the 32-column lookup floor, 7.9e-4), so the plan ships one table and says so."""
    body = DIELECTRICS.split("[[material]]")[1]
    path = scene_file(
        tmp_path,
        "[[material]]"
        + body
        + '[[material]]\nname = "brass"\nmodel = "adobe"\nf0 = [0.9, 0.8, 0.5]\ntint = [0.97, 0.95, 0.9]\n'
        + "roughness = [0.3, 0.5]\n",
    )
    plan = plan_scene(read_scene(path))
    assert plan.tables == ("scene-basis-4",)
    path = plan.path("brass")
    assert path["choice"] == "basis" and "its exact table model:adobe" in path["why"], path
    assert plan.full_errors["scene-basis-4"]["brass"] <= plan.full_errors["model:adobe"]["brass"] * 1.01


#: Scene files with values of the wrong type or form → words the one-line error must contain.
BAD_SCENES = {
    "table eta": ('[[material]]\nname="m"\neta={r=1}\nkappa=0\nroughness=0.3\n', "eta must be a number or 3 numbers"),
    "date f0": ('[[material]]\nname="m"\nf0=1979-05-27\nroughness=0.3\n', "f0 must be a number"),
    "table roughness": ('[[material]]\nname="m"\nf0=0.04\nroughness={a=1}\n', "roughness must be a number"),
    "list preset": ('[[material]]\nname="m"\npreset=["Gold"]\nroughness=0.3\n', "preset must be a material's name"),
    "list tolerance": (
        'tolerance=[0.1]\n[[material]]\nname="m"\nf0=0.04\nroughness=0.3\n',
        "tolerance must be a number",
    ),
    "list space": ('space=["sRGB"]\n[[material]]\nname="m"\nf0=0.04\nroughness=0.3\n', "space must be one of"),
    "boolean roughness": ('[[material]]\nname="m"\nf0=0.04\nroughness=true\n', "roughness must be a number"),
    "boolean f0": ('[[material]]\nname="m"\nf0=true\nroughness=0.3\n', "f0 must be a number"),
    "table name": ("[[material]]\nname={a=1}\nf0=0.04\nroughness=0.3\n", "name must be printable text"),
    "text roughness": ('[[material]]\nname="m"\nf0=0.04\nroughness="0.3"\n', "got '0.3' (text)"),
    "text f0": ('[[material]]\nname="m"\nf0=["a","b","c"]\nroughness=0.3\n', "material 'm': f0 must be"),
    "NUL in a name": ('[[material]]\nname="a\\u0000b"\nf0=0.04\nroughness=0.3\n', "name must be printable"),
    "size 1024": ('size=1024\n[[material]]\nname="m"\nf0=0.04\nroughness=0.3\n', "at most 256 columns"),
    "float size": ('size=64.5\n[[material]]\nname="m"\nf0=0.04\nroughness=0.3\n', "size must be an integer"),
    "model parameter a table": (
        '[[material]]\nname="m"\nmodel="f82"\nf0={x=1}\nf82=0.5\nroughness=0.3\n',
        "f0 must be",
    ),
    "model a list": ('[[material]]\nname="m"\nmodel=["f82"]\nroughness=0.3\n', "model must be a model's name"),
}


@pytest.mark.parametrize("case", sorted(BAD_SCENES))
def test_values_of_the_wrong_type_are_one_line_naming_file_material_and_key(case, tmp_path):
    text, words = BAD_SCENES[case]
    path = tmp_path / "scene.toml"
    path.write_text(text, encoding="utf-8")
    with pytest.raises(SceneError) as info:
        read_scene(path)
    message = str(info.value)
    assert words in message and str(path) in message and len(message.splitlines()) == 1


def test_a_device_or_huge_file_is_refused_unread(tmp_path):
    with pytest.raises(SceneError, match="/dev/zero is a device, not a regular file"):
        read_scene("/dev/zero")
    big = tmp_path / "big.toml"
    big.write_bytes(b"# " + b"x" * (1 << 20) + b"\n")
    with pytest.raises(SceneError, match="more than the 1,048,576"):
        read_scene(big)
    binary = tmp_path / "binary.toml"
    binary.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(SceneError, match="not UTF-8"):
        read_scene(binary)


def test_rebuilding_into_a_used_folder_removes_the_previous_scenes_tables(tmp_path):
    out = tmp_path / "out"
    for _ in range(2):  # the same scene again: its own scene basis is not taken for a stale file
        write_scene(plan_scene(read_scene(scene_file(tmp_path, DIELECTRICS))), out)
        assert (out / "scene_ggx_own_basis_rgba.exr").exists() and (out / "scene_basis.json").exists()
    write_scene(plan_scene(read_scene(scene_file(tmp_path, SCHLICK_ONLY))), out)
    assert sorted(p.name for p in out.iterdir()) == [
        *(f"fresnel_basis_scene.{language}" for language in ("glsl", "hlsl", "wgsl")),
        "scene_coefficients.json",
        "scene_ggx_schlick_rg.exr",
        "scene_report.md",
    ]


def test_a_scene_beside_a_default_build_leaves_the_builds_includes_alone(tmp_path):
    """A scene written into a folder that holds a default build (tables and their includes) adds its own includes
    under their own names and leaves the build's bytes as they were: the build's include and tables still share
    one basis."""
    out = tmp_path / "out"
    out.mkdir()
    shipped = {name: shipped_path(name).read_bytes() for name in ("fresnel_basis.glsl", BASIS_LUT)}
    for name, data in shipped.items():
        (out / name).write_bytes(data)
    result = write_scene(plan_scene(read_scene(scene_file(tmp_path, DIELECTRICS))), out)
    assert [path.name for path in result["shader_includes"]] == [
        f"fresnel_basis_scene.{suffix}" for suffix in ("glsl", "hlsl", "wgsl")
    ]
    assert all((out / name).read_bytes() == data for name, data in shipped.items())


def test_coefficients_file_is_the_same_bytes_whatever_the_hash_seed(tmp_path):
    """A model material's parameters keep the scene file's order in scene_coefficients.json: with two
    string-hash seeds the file was written in two orders (a set was iterated)."""
    import os
    import subprocess
    import sys

    path = tmp_path / "scene.toml"
    path.write_text(
        'size = 16\ntolerance = 0.05\n[[material]]\nname = "lacquer"\nmodel = "adobe"\nf0 = [0.9, 0.7, 0.4]\n'
        "tint = [0.6, 0.8, 1.0]\nroughness = [0.3, 0.6]\n",
        encoding="utf-8",
    )
    written = []
    for seed in ("0", "1"):  # these two wrote different orders before the fix
        out = tmp_path / f"out{seed}"
        subprocess.run(
            [sys.executable, "-m", "fresnel_lut.cli", "scene", str(path), "--out", str(out)],
            check=True,
            capture_output=True,
            env={**os.environ, "PYTHONHASHSEED": seed},
        )
        written.append((out / "scene_coefficients.json").read_bytes())
    assert all(text == written[0] for text in written)


def test_separable_scene_matches_an_independent_separable_integral_at_its_texels(tmp_path, capsys):
    """Issue 22: ``visibility = "separable"`` reaches the scene's tables. Texels of the Schlick table against adaptive
    cubature over ω_i with G1(o) G1(i) re-typed in tests/references (1e-6: float32 storage, the cubature's 1e-10);
    the height-correlated integral differs by far more at r = 0.8 near grazing (0.2), so the test tells the two
    apart."""
    from tests.references.integration import reference_albedo

    path = scene_file(tmp_path, 'visibility = "separable"\n' + SCHLICK_ONLY)
    assert cli.main(["scene", str(path), "--out", str(tmp_path / "out")]) == 0
    table, header = read_lut(tmp_path / "out" / "scene_ggx_schlick_rg.exr")
    assert header["convention"].endswith("GGX with separable Smith G2 = G1(omega_o) * G1(omega_i)")
    rows = np.linspace(0.3, 0.8, table.shape[0])
    schlick = lambda x: np.stack([1.0 - (1.0 - x) ** 5, (1.0 - x) ** 5], axis=-1)  # noqa: E731 (the two channels)
    columns = LutGrid(SIZE, SIZE).mu_o  # a scene's columns are the default build's
    for j, i in ((0, 2), (table.shape[0] - 1, 1), (table.shape[0] - 1, 8), (1, SIZE - 1)):
        separable = reference_albedo(schlick, columns[i], rows[j] ** 2, visibility="separable")
        np.testing.assert_allclose(table[j, i], separable, rtol=0, atol=1e-6)
    correlated = reference_albedo(schlick, columns[1], rows[-1] ** 2, visibility="height-correlated")
    assert np.max(np.abs(correlated - table[-1, 1])) > 1e-2
    document = json.loads((tmp_path / "out" / "scene_coefficients.json").read_text(encoding="utf-8"))
    assert document["visibility"] == "separable"


def test_scene_visibility_on_the_command_line_and_a_conflict(tmp_path, capsys):
    path = scene_file(tmp_path, SCHLICK_ONLY)
    assert cli.main(["scene", str(path), "--out", str(tmp_path / "a"), "--visibility", "separable"]) == 0
    assert read_lut(tmp_path / "a" / "scene_ggx_schlick_rg.exr")[1]["convention"].endswith("G1(omega_i)")
    stated = scene_file(tmp_path, 'visibility = "height-correlated"\n' + SCHLICK_ONLY, name="stated.toml")
    capsys.readouterr()
    assert cli.main(["scene", str(stated), "--out", str(tmp_path / "b"), "--visibility", "separable"]) == 2
    assert "says visibility = 'height-correlated'" in capsys.readouterr().err and not (tmp_path / "b").exists()
    bad = scene_file(tmp_path, 'visibility = "smith"\n' + SCHLICK_ONLY, name="bad.toml")
    assert cli.main(["scene", str(bad), "--out", str(tmp_path / "c")]) == 2
    assert "visibility must be one of ['height-correlated', 'separable']" in capsys.readouterr().err


def test_a_scene_build_writes_every_format_with_the_same_values(tmp_path, capsys):
    """Issue 22: scene builds write KTX2, 16-bit PNG and C headers through the build's writer; each holds the EXR's
    values (KTX2 exactly, read by the reference reader; PNG within half its 16-bit step)."""
    from tests.references.ktx2 import read_ktx2

    path = scene_file(tmp_path, DIELECTRICS)
    out = tmp_path / "out"
    assert cli.main(["scene", str(path), "--out", str(out), "--format", "exr,ktx2,png16,header"]) == 0
    document = json.loads((out / "scene_coefficients.json").read_text(encoding="utf-8"))
    assert document["formats"] == ["exr", "ktx2", "png16", "header"]
    stems = {
        name[: -len(".exr")]
        for entry in document["materials"].values()
        for key in ("lut", "second_lut")
        if (name := entry.get(key))
    }
    assert sorted(p.name for p in out.iterdir()) == sorted(
        [f"{stem}{suffix}" for stem in stems for suffix in (".exr", ".ktx2", ".png", ".h")]
        + ["scene_basis.json"] * ("scene_basis" in document)
        + document["shader_includes"]
        + ["scene_coefficients.json", "scene_report.md"]
    )
    for stem in stems:
        table, _ = read_lut(out / f"{stem}.exr")
        ktx = read_ktx2((out / f"{stem}.ktx2").read_bytes())
        np.testing.assert_array_equal(ktx["texels"][..., : table.shape[2]], table)
    # a rebuild with EXR alone removes the other formats of the scene's set
    assert cli.main(["scene", str(path), "--out", str(out)]) == 0
    assert {p.suffix for p in out.iterdir()} == {".exr", ".json", ".md", ".glsl", ".hlsl", ".wgsl"}


@pytest.mark.parametrize(
    "body",
    [
        'space = "sRGB"\n[[material]]\nname = "gold"\npreset = "Gold"\nroughness = [0.2, 0.6]\n',
        '[[material]]\nname = "matched"\neta = 1.0\nkappa = 0.0\nroughness = 0.5\n'
        '[[material]]\nname = "mirror"\neta = 1.5\nkappa = 1e6\nroughness = 0.3\n'
        '[[material]]\nname = "none"\nreflectivity = 0.0\nedge_tint = 1.0\nroughness = 0.4\n',
    ],
    ids=["sRGB gold (F0 red 1.038)", "constant curves"],
)
def test_scenes_that_used_to_fail_build(tmp_path, capsys, body):
    """Issue 26 item 7: a scene of sRGB Gold alone failed with numpy's 'Singular matrix' (a trial step of the scene
    basis' refinement), one of constant curves with 'no training curve has F(pi/2) - F(0) > 0'. Both build, and every
    material meets the tolerance."""
    path = tmp_path / "scene.toml"
    path.write_text(body, encoding="utf-8")
    assert cli.main(["scene", str(path), "--out", str(tmp_path / "out")]) == 0
    document = json.loads((tmp_path / "out" / "scene_coefficients.json").read_text(encoding="utf-8"))
    assert all(entry["max_abs_error_fbar"] <= DEFAULT_TOLERANCE for entry in document["materials"].values())


def test_names_are_escaped_in_the_report_and_one_spelling_each(tmp_path, capsys):
    """Issue 26 item 18: a name with '|' broke the report's table; NFC and NFD spellings of one name were two
    materials (now: the same name twice, refused)."""
    body = '[[material]]\nname = "a|b *c*"\nf0 = 0.04\nroughness = 0.5\n'
    path = scene_file(tmp_path, body)
    assert cli.main(["scene", str(path), "--out", str(tmp_path / "out")]) == 0
    report = (tmp_path / "out" / "scene_report.md").read_text(encoding="utf-8")
    row = next(line for line in report.splitlines() if line.startswith("| a"))
    assert row.startswith("| a\\|b \\*c\\* |") and row.count(" | ") == 5
    twice = scene_file(
        tmp_path,
        '[[material]]\nname = "Caf\u00e9"\nf0 = 0.04\nroughness = 0.5\n'
        '[[material]]\nname = "Cafe\u0301"\nf0 = 0.05\nroughness = 0.5\n',
        name="twice.toml",
    )
    assert cli.main(["scene", str(twice), "--out", str(tmp_path / "twice")]) == 2
    assert "appears twice" in capsys.readouterr().err
