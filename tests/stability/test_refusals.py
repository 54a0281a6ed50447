"""Issue 36 items 13 and 14: values out of range, options given twice and JSON keys named twice are refused with one
line before any work; a generated include never holds a number it cannot compile; a model whose name has a dash
writes a C header.
"""

from __future__ import annotations

import json
import subprocess

import numpy as np
import pytest

from basis.eigenbasis import Basis, BasisFileError, shipped_basis_path
from basis.presets import PresetFileError, material_presets, shipped_presets_path
from basis.validation import ParameterError
from fresnel_lut.scene import SceneError, read_scene
from handoff.exr import LutFileError, exr_writer, read_lut
from handoff.shaders import shader_includes
from preintegrate.lut import LutGrid
from tests.conftest import assert_one_line_error, run


@pytest.mark.parametrize(
    "roughness, fragment",
    [("[0, 1e-320]", "narrower than 1e-06"), ("[0.5, 0.5000000001]", "narrower than 1e-06")],
)
def test_a_roughness_range_too_narrow_to_address_is_refused(tmp_path, roughness, fragment):
    """Item 13: ``roughness = [0, 1e-320]`` wrote includes holding ``inf, nan`` that do not compile, exit 0."""
    scene = tmp_path / "scene.toml"
    scene.write_text(f'[[material]]\nname = "g"\npreset = "Gold"\nroughness = {roughness}\n', encoding="utf-8")
    with pytest.raises(SceneError, match=fragment):
        read_scene(scene)


def test_materials_whose_roughnesses_span_too_little_are_refused(tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(
        '[[material]]\nname = "a"\npreset = "Gold"\nroughness = 0\n'
        '[[material]]\nname = "b"\npreset = "Gold"\nroughness = 1e-320\n',
        encoding="utf-8",
    )
    with pytest.raises(SceneError, match="span 0 to .* narrower than 1e-06"):
        read_scene(scene)


def test_an_include_is_never_written_with_a_number_it_cannot_compile():
    """Item 13: a generated include always compiles: a constant that is no finite float32 is refused before any text
    exists (here a grid over a subnormal roughness range, whose row scale is inf)."""
    grid = LutGrid(8, 4, rows="endpoints", roughness_range=(0.0, 1e-320))
    with pytest.raises(ParameterError, match="finite float32"):
        shader_includes(grid=grid)


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["build", "--size", "8", "--size", "16", "--out", "{tmp}"], "--size is given twice"),
        (["coeffs", "--eta", "1", "2", "3", "--eta", "1", "2", "3", "--kappa", "0", "0", "0"], "--eta is given twice"),
        (["build", "--size", "8", "--ltc", "--ltc-size", "0", "--out", "{tmp}"], "--ltc-size must be an integer in"),
    ],
)
def test_options_given_twice_or_out_of_range_are_refused(tmp_path, capsys, argv, fragment):
    """Item 13: repeated options took the last value silently; ``--ltc-size 0`` built 64 x 64."""
    assert run([item.format(tmp=tmp_path / "out") for item in argv]) == 2
    error = capsys.readouterr().err
    assert_one_line_error(error)
    assert fragment in error and not (tmp_path / "out").exists()


def test_a_table_edited_to_hold_a_huge_value_is_refused(tmp_path):
    """Item 13: ``read_lut`` accepted a table re-hashed around a texel of 1e30."""
    table = np.full((4, 4, 1), 0.5)
    table[1, 2, 0] = 1e30
    path = tmp_path / "ggx_edited.exr"
    exr_writer(table, ("Y",), {"channels": "Y"})(path)  # sealed: the hash verifies
    with pytest.raises(LutFileError, match="holds a texel of 1e\\+30"):
        read_lut(path)


def _with_duplicate_key(text: str, key: str) -> str:
    """The JSON ``text`` with its first ``"key":`` named twice (the first value stays, a second follows)."""
    marker = f'"{key}":'
    head, tail = text.split(marker, 1)
    value_end = tail.index(",")
    return head + marker + tail[:value_end] + "," + marker + tail


@pytest.mark.parametrize(
    "source, key, reader, error",
    [
        (shipped_basis_path, "format", Basis.read, BasisFileError),
        (shipped_presets_path, "format", material_presets, PresetFileError),
    ],
)
def test_a_json_key_named_twice_is_refused(tmp_path, source, key, reader, error):
    """Item 13: a duplicate key took the last value silently."""
    path = tmp_path / "file.json"
    path.write_text(_with_duplicate_key(source().read_text(encoding="utf-8"), key), encoding="utf-8")
    with pytest.raises(error, match=f"the key '{key}' appears twice"):
        reader(path)


def test_a_scene_naming_a_key_twice_is_refused(tmp_path):
    scene = tmp_path / "scene.json"
    scene.write_text(
        '{"tolerance": 0.01, "tolerance": 0.5, "material": [{"name": "g", "preset": "Gold", "roughness": 0.5}]}',
        encoding="utf-8",
    )
    with pytest.raises(SceneError, match="the key 'tolerance' appears twice"):
        read_scene(scene)


def test_a_basis_whose_training_field_is_malformed_is_one_clear_line(tmp_path):
    """Item 14: a list as ``training`` gave "dictionary update sequence element #0"."""
    document = json.loads(shipped_basis_path().read_text(encoding="utf-8"))
    document["training"] = [1, 2, 3]
    path = tmp_path / "basis.json"
    path.write_text(json.dumps(document), encoding="utf-8")
    with pytest.raises(BasisFileError, match="training field must be an object"):
        Basis.read(path)


def test_a_model_with_a_dash_in_its_name_writes_a_c_header(tmp_path, capsys):
    """Item 14: ``--format header`` with ``generalized-schlick`` failed after the work ("a C name must be an
    identifier"); its array is named with ``_`` for the dash, and gcc compiles it."""
    import shutil

    out = tmp_path / "out"
    argv = ["build", "--size", "6", "--model", "generalized-schlick", "--format", "header", "--out", out]
    assert run(argv) == 0
    (header,) = out.glob("*.h")
    assert header.name == "ggx_generalized-schlick_exponent5.h"
    text = header.read_text(encoding="ascii")
    assert "static const float ggx_generalized_schlick_exponent5[" in text
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler here")
    source = tmp_path / "use.c"
    source.write_text(f'#include "{header}"\nint main(void) {{ return (int) ggx_generalized_schlick_exponent5[0]; }}\n')
    compiled = subprocess.run([compiler, "-fsyntax-only", str(source)], capture_output=True, text=True)
    assert compiled.returncode == 0, compiled.stderr
