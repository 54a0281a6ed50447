"""Reading luts/materials.json (basis/presets.py): every field is checked, and every corrupted variant is
refused with one line naming the file, the material and the key, by the API and by the CLI."""

import json

import numpy as np
import pytest

import basis.presets as presets
from basis.presets import PresetFileError, material_coefficients, material_preset, material_presets
from tests.conftest import assert_one_line_error, run

SHIPPED = json.loads(presets.shipped_presets_path().read_text(encoding="utf-8"))


def _gold(document):
    return document["materials"]["Gold"]["ACEScg"]


#: name → (edit of the document, words the error must contain)
CORRUPTIONS = {
    "nan coefficient": (lambda d: _gold(d)["coefficients"][0].__setitem__(1, float("nan")), "finite"),
    "inf f0": (lambda d: _gold(d)["f0"].__setitem__(0, float("inf")), "finite"),
    "text coefficient": (lambda d: _gold(d)["coefficients"][1].__setitem__(0, "0.5"), "numbers"),
    "boolean f82": (lambda d: _gold(d)["f82"].__setitem__(2, True), "numbers"),
    "one row of coefficients": (lambda d: _gold(d).__setitem__("coefficients", _gold(d)["coefficients"][:1]), "shape"),
    "flat coefficients": (lambda d: _gold(d).__setitem__("coefficients", sum(_gold(d)["coefficients"], [])), "shape"),
    "two f0": (lambda d: _gold(d).__setitem__("f0", _gold(d)["f0"][:2]), "shape"),
    "no coefficients": (lambda d: _gold(d).pop("coefficients"), "lacks coefficients"),
    "no ACEScg": (lambda d: d["materials"]["Gold"].pop("ACEScg"), "lacks the ACEScg"),
    "material a list": (lambda d: d["materials"].__setitem__("Gold", [1, 2]), "must be a table"),
    "no kind": (lambda d: d["materials"]["Gold"].pop("kind"), "kind"),
    "errors a number": (lambda d: _gold(d).__setitem__("rms_delta_e2000", 0.1), "rms_delta_e2000"),
    "error text": (lambda d: _gold(d)["rms_delta_e2000"].__setitem__("basis", "small"), "numbers"),
    "no materials": (lambda d: d.pop("materials"), "materials"),
    "materials a list": (lambda d: d.__setitem__("materials", []), "materials"),
    "hash a number": (lambda d: d.__setitem__("basis_hash", 7), "basis_hash"),
    "other format": (lambda d: d.__setitem__("format", "something/else"), "is not a"),
    "other version": (lambda d: d.__setitem__("version", 2), "is not a"),
}


def _write(tmp_path, edit) -> str:
    document = json.loads(json.dumps(SHIPPED))
    edit(document)
    path = tmp_path / "materials.json"
    path.write_text(json.dumps(document), encoding="utf-8")  # json writes NaN and Infinity tokens as given
    return path


@pytest.mark.parametrize("case", sorted(CORRUPTIONS))
def test_corrupted_presets_are_refused_by_the_api(case, tmp_path, monkeypatch):
    edit, words = CORRUPTIONS[case]
    path = _write(tmp_path, edit)
    monkeypatch.setattr(presets, "shipped_presets_path", lambda: path)
    with pytest.raises(PresetFileError, match=words) as info:
        material_coefficients("Gold")
    assert len(str(info.value).splitlines()) == 1 and str(path) in str(info.value)


@pytest.mark.parametrize("case", sorted(CORRUPTIONS))
def test_corrupted_presets_are_one_line_in_the_cli(case, tmp_path, monkeypatch, capsys):
    edit, _ = CORRUPTIONS[case]
    path = _write(tmp_path, edit)
    monkeypatch.setattr(presets, "shipped_presets_path", lambda: path)
    assert run(["coeffs", "--material", "Gold", "--json"]) == 2
    captured = capsys.readouterr()
    assert_one_line_error(captured.err)
    assert captured.out == ""


@pytest.mark.parametrize("content", [b"\x00\xff\xfe binary", b"", b"{", b"[1, 2]", b'"text"'])
def test_unreadable_presets_are_refused(content, tmp_path):
    path = tmp_path / "materials.json"
    path.write_bytes(content)
    with pytest.raises(PresetFileError, match="material presets"):
        material_presets(path)


def test_shipped_presets_pass_the_checks_and_names_are_text():
    assert material_preset("gold")["name"] == "Gold"
    np.testing.assert_array_equal(material_coefficients("Gold"), np.array(_gold(SHIPPED)["coefficients"]))
    with pytest.raises(presets.ParameterError, match="must be a name"):
        material_coefficients(["Gold"])
    with pytest.raises(presets.ParameterError, match="must be a name"):
        material_preset(None)
