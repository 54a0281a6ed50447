"""Data and security (issue 26, items 1-5): a LUT folder from someone else cannot make a reader or a writer touch
anything outside it; a build owns the set it writes; shipped data is replaced only when named; every shipped or
written document carries what lets a reader refuse it when damaged or edited.
"""

from __future__ import annotations

import json

import numpy as np
import OpenEXR
import pytest

from basis.eigenbasis import Basis, BasisFileError, shipped_basis_path
from basis.presets import PresetFileError, content_hash, material_presets, shipped_presets_path
from basis.storage import JOURNAL, read_journal
from handoff.exr import LutFileError, read_lut
from handoff.formats import payload_hash
from handoff.shipped import SHIPPED_LUTS
from handoff.tables import DEFAULT_BUILD_FILES
from tests.conftest import assert_one_line_error, run
from tests.references.ktx2 import read_ktx2


def _tree(folder):
    return {str(path.relative_to(folder)): path.read_bytes() for path in sorted(folder.rglob("*")) if path.is_file()}


@pytest.fixture
def built(tmp_path):
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    return out


@pytest.mark.parametrize(
    "journal",
    [
        [["../precious/keep.txt", "ggx_basis_rgba.exr"]],  # the old layout, a path outside
        {"format": "fresnel-basis/journal", "version": 2, "renames": [["../precious/keep.txt", "ggx_basis_rgba.exr"]]},
        {
            "format": "fresnel-basis/journal",
            "version": 2,
            "renames": [[".ggx_basis_rgba.exr.abcdefgh.tmp", "../precious/keep.txt"]],
        },
        {
            "format": "fresnel-basis/journal",
            "version": 2,
            "renames": [["notes.txt", "ggx_basis_rgba.exr"]],
        },  # not a temporary
        {"format": "fresnel-basis/journal", "version": 2, "renames": [], "removals": ["../precious/keep.txt"]},
        {"format": "fresnel-basis/journal", "version": 2, "renames": [], "removals": ["/tmp"]},
    ],
)
def test_a_crafted_journal_moves_nothing(built, tmp_path, capsys, journal):
    """Item 1: a reader of a folder with a crafted journal changes nothing anywhere; a writer into it finishes only
    its own temporaries (names it makes, inside the folder), so the file the journal names outside stays."""
    precious = tmp_path / "precious"
    precious.mkdir()
    (precious / "keep.txt").write_text("not a LUT")
    (built / ".ggx_basis_rgba.exr.abcdefgh.tmp").symlink_to(precious / "keep.txt")
    (built / "notes.txt").write_text("a user's notes")
    (built / JOURNAL).write_text(json.dumps(journal))
    before = _tree(tmp_path)
    for name in SHIPPED_LUTS:
        read_lut(built / name)  # a foreign journal is no group: the tables read as they are
    assert _tree(tmp_path) == before
    assert read_journal(built) is None  # none of these is a journal of this project's
    assert run(["build", "--size", "6", "--out", built]) == 0
    assert (precious / "keep.txt").read_text() == "not a LUT" and (built / "notes.txt").read_text() == "a user's notes"
    assert not (built / JOURNAL).exists()


def test_a_smaller_basis_build_removes_the_second_table_of_a_larger_one(built, tmp_path, capsys):
    """Item 3: an 8-term build writes ggx_basis_rgba_2; a 4-term build into the same folder owns the set and
    removes it (else fresnelBasisSplitSum8 would combine two bases), in every format."""
    eight = tmp_path / "eight.json"
    assert run(["basis", "--count", "2000", "--terms", "8", "--out", eight]) == 0
    assert run(["build", "--size", "6", "--basis", eight, "--format", "exr,ktx2", "--out", built]) == 0
    assert (built / "ggx_basis_rgba_2.exr").exists() and (built / "ggx_basis_rgba_2.ktx2").exists()
    (built / ".ggx_schlick_rgba.png.abc12345.tmp").write_bytes(b"left by a killed png16 build")
    (built / "ggx_basis_rgba_2.exr.notes").write_text("not a table of the set")
    assert run(["build", "--size", "6", "--out", built]) == 0
    assert sorted(path.name for path in built.iterdir()) == sorted([*DEFAULT_BUILD_FILES, "ggx_basis_rgba_2.exr.notes"])


def test_a_model_build_keeps_the_default_set_and_names_its_shape(built, capsys):
    """Item 9: two exponents of one model are two files; a model build leaves the default set alone."""
    for exponent in ("5", "6"):
        assert (
            run(["build", "--size", "6", "--model", "generalized-schlick", "--exponent", exponent, "--out", built]) == 0
        )
    names = sorted(path.name for path in built.iterdir())
    assert names == sorted(
        [*DEFAULT_BUILD_FILES, "ggx_generalized-schlick_exponent5.exr", "ggx_generalized-schlick_exponent6.exr"]
    )
    assert (
        run(["build", "--size", "6", "--model", "generalized-schlick", "--out", built]) == 0
    )  # the default exponent is 5
    assert sorted(path.name for path in built.iterdir()) == names


def test_basis_replaces_the_shipped_file_only_when_named(capsys):
    """Item 4: ``fresnel-lut basis`` without ``--out`` is refused (it used to overwrite luts/basis.json)."""
    before = shipped_basis_path().read_bytes()
    assert run(["basis", "--count", "100"]) == 2
    assert "--out" in capsys.readouterr().err
    assert run(["materials"]) == 2
    assert "--presets" in capsys.readouterr().err
    assert shipped_basis_path().read_bytes() == before


def _edited_presets(tmp_path, edit, rehash=True):
    document = json.loads(shipped_presets_path().read_text(encoding="utf-8"))
    edit(document["materials"]["Gold"]["ACEScg"])
    if rehash:
        document["content_hash"] = content_hash(document)
    path = tmp_path / "materials.json"
    path.write_text(json.dumps(document), encoding="utf-8")
    return path


@pytest.mark.parametrize(
    "edit, fragment",
    [
        (lambda entry: entry["coefficients"][0].__setitem__(1, 1e6), r"coefficients must lie in \[-10, 10\]"),
        (lambda entry: entry["f0"].__setitem__(0, 5.0), r"f0 must lie in \[-0.25, 1.25\]"),
        (lambda entry: entry["rms_delta_e2000"].__setitem__("basis", -0.1), r"basis must lie in \[0, 100\]"),
    ],
)
def test_presets_out_of_range_are_refused(tmp_path, edit, fragment):
    with pytest.raises(PresetFileError, match=fragment):
        material_presets(_edited_presets(tmp_path, edit))


def test_presets_edited_without_their_hash_are_refused(tmp_path):
    path = _edited_presets(tmp_path, lambda entry: entry["coefficients"][0].__setitem__(1, 0.5), rehash=False)
    with pytest.raises(PresetFileError, match="content hash"):
        material_presets(path)
    assert material_presets()["content_hash"] == content_hash(material_presets())  # the shipped file is sealed


@pytest.mark.parametrize(
    "edit, fragment",
    [
        (lambda document: document.__setitem__("n_terms", 5), "n_terms 5 does not match the 4 curves"),
        (lambda document: document["hemispherical_averages"].__setitem__(2, 0.2), "hemispherical_averages"),
        (lambda document: document.__setitem__("hemispherical_averages", [1, 0]), "hemispherical_averages"),
        (lambda document: document.__setitem__("n_terms", True), "n_terms"),
    ],
)
def test_basis_fields_outside_the_hash_are_checked(tmp_path, edit, fragment):
    """Item 5: engines read the averages from basis.json (shader comments say so): they are checked on read."""
    document = json.loads(shipped_basis_path().read_text(encoding="utf-8"))
    edit(document)
    path = tmp_path / "basis.json"
    path.write_text(json.dumps(document), encoding="utf-8")
    with pytest.raises(BasisFileError, match=fragment):
        Basis.read(path)


def test_ktx2_png_and_header_carry_pixel_type_and_content_hash(tmp_path, capsys):
    """Item 5: every format states its pixel type and the hash of its attributes and stored texels; a flipped bit
    in the texels changes the hash a reader recomputes."""
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--half", "--format", "ktx2,header", "--out", out]) == 0
    data = bytearray((out / "ggx_basis_rgba.ktx2").read_bytes())
    ktx = read_ktx2(bytes(data))
    attributes = {
        key[len("fresnel:") :]: value for key, value in ktx["key_values"].items() if key.startswith("fresnel:")
    }
    texel_bytes = ktx["texels"].astype("<f2").tobytes()
    assert attributes["pixel_type"] == "half"
    assert attributes["content_hash"] == payload_hash(attributes, texel_bytes)
    flipped = bytearray(texel_bytes)
    flipped[7] ^= 0x10
    assert payload_hash(attributes, bytes(flipped)) != attributes["content_hash"]
    header = (out / "ggx_basis_rgba.h").read_text(encoding="utf-8")
    assert " * pixel_type: float32" in header and " * content_hash: " in header


def _rewritten_exr(source, target, **changes):
    """The EXR ``source`` with header attributes changed and its content hash recomputed (a consistent edit)."""
    from handoff.exr import content_hash as exr_hash

    image = OpenEXR.File(str(source), separate_channels=True)
    header = dict(image.header())
    channels = {name: channel.pixels for name, channel in image.channels().items()}
    attributes = {key[len("fresnel:") :]: str(value) for key, value in header.items() if key.startswith("fresnel:")}
    attributes.update(changes)
    attributes["content_hash"] = exr_hash(attributes, channels)
    header.update({f"fresnel:{key}": value for key, value in attributes.items()})
    OpenEXR.File(header, channels).write(str(target))
    return target


@pytest.mark.parametrize(
    "changes, fragment",
    [
        ({"width": "7"}, "header width '7' does not match the pixels"),
        ({"height": "5"}, "header height '5' does not match the pixels"),
        ({"pixel_type": "half"}, "header pixel_type 'half' does not match the pixels"),
        ({"pixel_type": "uint8"}, "pixel_type 'uint8'"),
    ],
)
def test_read_lut_compares_the_header_with_the_pixels(built, tmp_path, changes, fragment):
    path = _rewritten_exr(built / "ggx_basis_rgba.exr", tmp_path / "edited.exr", **changes)
    with pytest.raises(LutFileError, match=fragment):
        read_lut(path)


def test_one_line_for_basis_without_out(capsys):
    assert run(["basis"]) == 2
    assert_one_line_error(capsys.readouterr().err)


@pytest.mark.parametrize("kind", ["basis", "presets", "scene json", "scene toml"])
def test_deeply_nested_files_are_one_line(tmp_path, capsys, kind):
    """Issue 26 item 13: a deeply nested JSON or TOML file was a RecursionError traceback; now one line."""
    deep = "[" * 100_000 + "]" * 100_000
    if kind == "basis":
        path = tmp_path / "basis.json"
        path.write_text(deep)
        argv = ["build", "--size", "4", "--basis", path, "--out", tmp_path / "out"]
    elif kind == "presets":
        path = tmp_path / "materials.json"
        path.write_text('{"a": ' + "[" * 40 + "]" * 40 + "}")  # parses, but deeper than any file of the project
        with pytest.raises(PresetFileError, match="nested deeper than 32"):
            material_presets(path)
        return
    else:
        path = tmp_path / ("scene.json" if kind == "scene json" else "scene.toml")
        path.write_text(deep if kind == "scene json" else "a = " + deep)
        argv = ["scene", path, "--out", tmp_path / "out"]
    assert run(argv) == 2
    error = capsys.readouterr().err
    assert_one_line_error(error)
    assert "nested" in error and not (tmp_path / "out").exists()


def test_options_are_never_ignored_without_a_word(capsys, tmp_path):
    """Issue 26 item 12: --list-materials --json prints JSON; report --materials with --quick or --fidelity is refused."""
    assert run(["coeffs", "--list-materials", "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["space"] == "ACEScg" and "Gold" in document["materials"]
    for extra in (["--quick"], ["--fidelity"]):
        assert run(["report", "--materials", *extra, "--out", tmp_path / "r"]) == 2
        assert_one_line_error(capsys.readouterr().err)
    assert not (tmp_path / "r").exists()


def test_messages_carry_no_python_error_numbers(tmp_path, capsys):
    """Issue 26 item 16: a dangling symbolic link as --out is named as one; OS errors read without "[Errno N]"."""
    (tmp_path / "link").symlink_to(tmp_path / "nowhere")
    assert run(["build", "--size", "4", "--out", tmp_path / "link"]) == 2
    error = capsys.readouterr().err
    assert_one_line_error(error)
    assert "dangling" in error and "Errno" not in error


def test_a_closed_pipe_ends_the_listing_quietly(tmp_path):
    """Issue 26 item 16: `fresnel-lut coeffs --list-materials | head -1` printed "[Errno 32] Broken pipe" with status 2."""
    import subprocess
    import sys
    from pathlib import Path

    command = Path(sys.executable).parent / "fresnel-lut"
    completed = subprocess.run(
        f"'{command}' coeffs --list-materials | head -1", shell=True, capture_output=True, text=True, timeout=60
    )
    assert completed.stdout.startswith("measured materials") and completed.stderr == ""


def test_one_supported_range_of_terms_end_to_end(tmp_path, capsys):
    """Issue 26 item 11: basis --terms took 2-16, build 1-8; --count 200 --terms 14 raised TypeError; a two-term
    basis broke coeffs --material. Now 2 to 8 everywhere, and a two-term basis serves every command."""
    for terms in ("9", "14", "1"):
        assert run(["basis", "--count", "200", "--terms", terms, "--out", tmp_path / "b.json"]) == 2
        assert_one_line_error(capsys.readouterr().err)
    two = tmp_path / "two.json"
    assert run(["basis", "--count", "2000", "--terms", "2", "--out", two]) == 0
    capsys.readouterr()
    assert run(["coeffs", "--material", "Gold", "--basis", two, "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert len(document["coefficients"][0]) == 2 and document["material"]["rms_delta_e2000"]["basis"] > 0
    assert run(["build", "--size", "4", "--basis", two, "--out", tmp_path / "luts"]) == 0


@pytest.mark.parametrize(
    "call",
    [
        lambda: __import__("preintegrate.lut", fromlist=["lut_lookup"]).lut_lookup(np.zeros((4, 4, 2)), np.nan, 0.5),
        lambda: __import__("preintegrate.lut", fromlist=["lut_lookup"]).lut_lookup(np.zeros((4, 4, 2)), "0.5", 0.5),
        lambda: __import__("preintegrate.lut", fromlist=["lut_lookup"]).lut_lookup(np.zeros((4, 4, 2)), True, 0.5),
        lambda: __import__("preintegrate.lut", fromlist=["lut_lookup"]).lut_lookup(np.zeros((1, 4, 2)), 0.5, 0.5),
        lambda: __import__("handoff.formats", fromlist=["png16_encoding"]).png16_encoding([1.0, 2.0]),
        lambda: read_lut(3),
        lambda: read_lut(b"ggx_basis_rgba.exr"),
        lambda: __import__("preintegrate.multiple_scattering", fromlist=["basis_albedo"]).basis_albedo(
            np.zeros(4), 0.5, 0.5, __import__("handoff.shipped", fromlist=["shipped_tables"]).shipped_tables()
        ),
    ],
    ids=[
        "lookup nan",
        "lookup text",
        "lookup bool",
        "lookup one row",
        "png16 encoding of a list",
        "read_lut int",
        "read_lut bytes",
        "basis_albedo (4,)",
    ],
)
def test_api_helpers_refuse_bad_input_with_parameter_error(call):
    """Issue 26 item 15: these raised IndexError, AttributeError, TypeError or AxisError."""
    from basis.validation import ParameterError

    with pytest.raises(ParameterError):
        call()


def test_resource_caps_refuse_before_the_work(tmp_path, capsys):
    """Issue 26 item 17: `build --size 8192 --format header` ran > 300 s and left a 6 GB temporary; a scene of 3,000
    materials took 192 s and 880 MiB. Both are refused at once, in one line."""
    assert run(["build", "--size", "8192", "--format", "header", "--out", tmp_path / "big"]) == 2
    assert "use ktx2 or exr" in capsys.readouterr().err and not (tmp_path / "big").exists()
    scene = tmp_path / "many.toml"
    scene.write_text("".join(f'[[material]]\nname = "m{k}"\nf0 = 0.04\nroughness = 0.5\n' for k in range(300)))
    assert run(["scene", scene, "--out", tmp_path / "out"]) == 2
    error = capsys.readouterr().err
    assert_one_line_error(error)
    assert "at most 256" in error and not (tmp_path / "out").exists()


def test_coeffs_for_another_basis_state_that_basis_error(tmp_path, capsys):
    """Issue 26 item 8: coeffs --basis OTHER --material NAME printed the shipped basis' RMS ΔE2000 (0.073 for gold)
    beside coefficients refitted for OTHER. A three-term basis fits gold worse: its own RMS is stated, above the
    shipped four-term one, and recomputing the shipped basis' error gives the preset's figure back."""
    three = tmp_path / "three.json"
    assert run(["basis", "--count", "2000", "--terms", "3", "--out", three]) == 0
    capsys.readouterr()
    assert run(["coeffs", "--material", "Gold", "--json"]) == 0
    shipped = json.loads(capsys.readouterr().out)["material"]["rms_delta_e2000"]["basis"]
    assert run(["coeffs", "--material", "Gold", "--basis", three, "--json"]) == 0
    other = json.loads(capsys.readouterr().out)["material"]["rms_delta_e2000"]["basis"]
    assert other > 1.5 * shipped
    assert run(["coeffs", "--material", "Gold", "--basis", shipped_basis_path(), "--json"]) == 0
    again = json.loads(capsys.readouterr().out)["material"]["rms_delta_e2000"]["basis"]
    assert again == pytest.approx(shipped, rel=1e-6)
