"""Issue 36, items 2-4, 6 and 7: what an output folder holds cannot make a command lose a user's file or hang.

A journal proves each file it acts on (the identity its writer recorded), so a crafted, copied or unpacked journal
moves nothing; a scene's earlier file list names only scene files; a FIFO or a device where a file is expected is
refused unread; a scene's tables are named apart from a build's, and a build keeps the LTC table it does not refit.
"""

from __future__ import annotations

import json
import os
import shutil
import threading
from pathlib import Path

import pytest

from basis.storage import JOURNAL, FolderWarning, read_journal
from handoff.exr import read_lut
from handoff.shipped import BASIS_LUT, SHIPPED_LUTS
from tests.conftest import assert_one_line_error, run, run_subprocess

ROOT = Path(__file__).resolve().parents[2]
GOLD_SCENE = '[[material]]\nname = "g"\npreset = "Gold"\nroughness = [0.3, 0.5]\n'


def _files(folder: Path) -> dict[str, bytes]:
    return {path.name: path.read_bytes() for path in sorted(folder.iterdir()) if path.is_file()}


@pytest.fixture
def built(tmp_path):
    out = tmp_path / "d1"
    assert run(["build", "--size", "6", "--out", out]) == 0
    return out


def _crafted_journals(folder: Path) -> list[dict]:
    """The issue's journal (v2), and v3 journals whose identities are made up or taken from other files."""
    temporary = ".notes.txt.abcdefgh.tmp"
    (folder / temporary).write_text("the attacker's text")
    fake = [1, 2, 3, 4]
    return [
        {
            "format": "fresnel-basis/journal",
            "version": 2,
            "renames": [[temporary, "notes.txt"]],
            "removals": ["basis.json"],
        },
        {
            "format": "fresnel-basis/journal",
            "version": 3,
            "renames": [[temporary, "notes.txt", fake]],
            "removals": [["basis.json", fake], ["materials.json", [0, 0, 0, 0]], [".keep", fake]],
        },
    ]


#: The writers the issue names (render and report write through the same transaction; they are slow, so the
#: quick ones stand for them here).
WRITERS = {
    "build": lambda out: ["build", "--size", "6", "--out", out],
    "scene": lambda out: ["scene", str(out.parent / "gold.toml"), "--out", out],
    "basis": lambda out: ["basis", "--count", "200", "--grid-size", "64", "--out", out / "basis.json"],
    "materials": lambda out: ["materials", "--presets", out / "materials.json"],
}


@pytest.mark.parametrize("writer", sorted(WRITERS))
@pytest.mark.parametrize("which", [0, 1])
def test_a_crafted_journal_renames_and_removes_nothing(built, tmp_path, capsys, writer, which):
    """Item 2: ``notes.txt`` is not replaced, ``basis.json``, ``materials.json`` and ``.keep`` are not removed by
    the next writer, whichever it is (except that ``basis`` and ``materials`` write their own file by name)."""
    (tmp_path / "gold.toml").write_text(GOLD_SCENE, encoding="utf-8")
    user = {"notes.txt": "a user's notes", "basis.json": "{}", "materials.json": "{}", ".keep": ""}
    for name, text in user.items():
        (built / name).write_text(text, encoding="utf-8")
    (built / JOURNAL).write_text(json.dumps(_crafted_journals(built)[which]), encoding="utf-8")
    assert read_journal(built) is None or not read_journal(built).pending()
    before = _files(built)
    for name in SHIPPED_LUTS:
        read_lut(built / name)  # no group: the tables read as they are
    assert _files(built) == before
    assert run(WRITERS[writer](built)) == 0
    written = {"basis": "basis.json", "materials": "materials.json"}.get(writer)
    for name, text in user.items():
        if name != written:
            assert (built / name).read_text(encoding="utf-8") == text, name
    assert not (built / JOURNAL).exists()


_KILLED = """
import os, signal, sys
from fresnel_lut import cli
original, calls = os.replace, []
def replace(source, target):
    if not str(target).endswith(".tmp") and not str(target).endswith("journal.json"):
        calls.append(target)
        if len(calls) == 2:
            os.kill(os.getpid(), signal.SIGKILL)
    return original(source, target)
os.replace = replace
cli.main(["build", "--size", "8", "--out", sys.argv[1]])
"""


def test_a_real_journal_copied_elsewhere_moves_nothing(built, tmp_path):
    """A journal a killed build left is obeyed where it was left (test_transactions), but its copy in another folder
    (an archive unpacked, a folder copied) proves none of its files: the copy's files stay as they are."""
    import subprocess
    import sys

    killed = subprocess.run(
        [sys.executable, "-c", _KILLED, str(built)], cwd=ROOT, env={**os.environ, "PYTHONPATH": str(ROOT)}
    )
    assert killed.returncode < 0 and (built / JOURNAL).exists()
    copy = tmp_path / "copy"
    shutil.copytree(built, copy)
    journal = read_journal(copy)
    assert journal is not None and journal.targets and not journal.pending()
    before = _files(copy)
    assert any(name.endswith(".tmp") for name in before)
    scene = tmp_path / "gold.toml"
    scene.write_text(GOLD_SCENE, encoding="utf-8")
    assert run(["scene", scene, "--out", copy]) == 0  # a writer of another set: the journal is the only actor
    after = _files(copy)
    assert all(after.get(name) == data for name, data in before.items() if name != JOURNAL)  # nothing moved
    assert not (copy / JOURNAL).exists()
    assert read_journal(built).pending()  # the original is still the killed build's, and the next build finishes it


def test_a_crafted_scene_list_removes_no_build_table(built, tmp_path, capsys):
    """Item 3: a ``scene_coefficients.json`` listing the build's tables and a user's file as a scene's earlier
    tables: the scene removes none of them."""
    (built / "notes.png").write_bytes(b"a user's picture")
    (built / "scene_coefficients.json").write_text(
        json.dumps(
            {
                "materials": {
                    "m": {"lut": "ggx_basis_rgba.exr", "second_lut": "ggx_schlick_rgba.exr"},
                    "n": {"lut": "notes.png", "second_lut": "ggx_ltc.exr"},
                },
                "scene_basis": {"file": "fresnel_basis.glsl"},
                "shader_includes": ["ggx_albedo_average.exr", "../d1/ggx_basis_rgba.exr"],
            }
        ),
        encoding="utf-8",
    )
    before = _files(built)
    scene = tmp_path / "gold.toml"
    scene.write_text(GOLD_SCENE, encoding="utf-8")
    assert run(["scene", scene, "--out", built]) == 0
    after = _files(built)
    for name, data in before.items():
        if name != "scene_coefficients.json":
            assert after[name] == data, name


def test_a_scene_into_a_build_folder_replaces_no_build_table(built, tmp_path, capsys):
    """Item 6: a sRGB Gold scene whose plan uses the generic four-term basis writes ``scene_ggx_basis_rgba.exr``,
    never the build's ``ggx_basis_rgba.exr`` (which the build's includes address at 6 rows)."""
    scene = tmp_path / "gold.toml"
    scene.write_text('space = "sRGB"\n' + GOLD_SCENE.replace("[0.3, 0.5]", "[0.2, 0.9]"), encoding="utf-8")
    before = _files(built)
    assert run(["scene", scene, "--out", built]) == 0
    after = _files(built)
    assert all(after[name] == data for name, data in before.items())
    scene_tables = sorted(name for name in after if name.startswith("scene_ggx_"))
    assert scene_tables and all(name not in before for name in scene_tables)
    assert read_lut(built / BASIS_LUT)[0].shape[:2] == (6, 6)


def _finishes_within(seconds: float, call) -> object:
    """``call()``'s result, failing (not hanging the suite) if it takes longer than ``seconds``."""
    result: dict = {}

    def target():
        try:
            result["value"] = call()
        except BaseException as error:  # handed to the test
            result["error"] = error

    worker = threading.Thread(target=target, daemon=True)
    worker.start()
    worker.join(seconds)
    assert not worker.is_alive(), f"still running after {seconds} s"
    if "error" in result:
        raise result["error"]
    return result.get("value")


@pytest.mark.parametrize("kind", ["fifo", "zero", "folder"])
def test_a_journal_that_is_no_regular_file_is_ignored_with_a_warning(built, kind, capsys):
    """Item 4: a FIFO or a link to /dev/zero named as the journal neither hangs a reader nor fills the memory; the
    next writer warns in one line and replaces the name (never writing through it)."""
    journal = built / JOURNAL
    if kind == "fifo":
        os.mkfifo(journal)
    elif kind == "zero":
        journal.symlink_to("/dev/zero")
    else:
        journal.mkdir()
    table, _ = _finishes_within(10, lambda: read_lut(built / BASIS_LUT))
    assert table.shape[:2] == (6, 6)
    if kind == "folder":  # a folder of that name is not ours to remove: the writer stops with one line
        assert _finishes_within(60, lambda: run(["build", "--size", "6", "--out", built])) == 2
        assert_one_line_error(capsys.readouterr().err)
        return
    with pytest.warns(FolderWarning, match="not a regular file"):
        read_journal(built)
    assert _finishes_within(60, lambda: run(["build", "--size", "6", "--out", built])) == 0
    warning = capsys.readouterr().err
    assert warning.count("\n") == 1 and warning.startswith("fresnel-lut: warning: journal") and "ignored" in warning
    assert not os.path.lexists(journal)


@pytest.mark.parametrize(
    "argv",
    [
        lambda fifo: ["build", "--size", "6", "--basis", fifo, "--out", fifo.parent / "o"],
        lambda fifo: ["scene", fifo, "--out", fifo.parent / "o"],
        lambda fifo: ["coeffs", "--eta", "1.5", "1.5", "1.5", "--kappa", "0", "0", "0", "--basis", "/dev/zero"],
        lambda fifo: ["build", "--size", "6", "--basis", "/dev/zero", "--out", fifo.parent / "o"],
    ],
    ids=["basis-fifo", "scene-fifo", "basis-zero", "build-basis-zero"],
)
def test_fifos_and_devices_as_inputs_are_refused_at_once(tmp_path, argv):
    """Item 4: a FIFO (whose open waits for a writer) or /dev/zero (which never ends) as a basis, scene or preset file
    is one line, at once, in a fresh process (a hang fails the test at its time-out instead of the suite's)."""
    fifo = tmp_path / "input.json"
    os.mkfifo(fifo)
    arguments = [str(item) for item in argv(fifo)]
    finished = run_subprocess(arguments, cwd=ROOT, timeout=60)
    assert finished.returncode == 2, finished.stderr
    assert_one_line_error(finished.stderr)
    assert "not a regular file" in finished.stderr


@pytest.mark.parametrize("source", ["fifo", "/dev/zero"])
def test_a_preset_file_that_is_no_regular_file_is_refused_at_once(tmp_path, source):
    """Item 4: the presets reader (the one of ``materials.json``) likewise."""
    from basis.presets import PresetFileError, material_presets

    path = tmp_path / "materials.json"
    if source == "fifo":
        os.mkfifo(path)
    else:
        path = Path(source)
    with pytest.raises(PresetFileError, match="not a regular file"):
        _finishes_within(10, lambda: material_presets(path))
