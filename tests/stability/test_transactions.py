"""Groups of files are one transaction even against a full disk, a second writer and kill -9.

A full disk inside the EXR library (which raises a bare RuntimeError) is one line naming the file, keeps the
previous files and leaves no folder behind; two builds into one folder never leave a mixed set; a process
killed between the renames of a group leaves a journal from which the next reader or writer finishes the
group, and its temporaries are removed.
"""

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

from preintegrate import exr
from preintegrate.exr import read_lut
from preintegrate.lut import AVERAGE_LUT, SHIPPED_LUTS
from tests.conftest import assert_one_line_error, fail_on_call, run

ROOT = Path(__file__).resolve().parents[2]


def _files(folder: Path) -> dict[str, bytes]:
    return {path.name: path.read_bytes() for path in sorted(folder.iterdir())}


def _library_disk_full(image, filename):
    Path(filename).write_bytes(b"v/1\x01partial")
    raise RuntimeError("Error writing EXR file: No space left on device")  # what OpenEXR's bindings raise


def test_disk_full_in_a_new_folder_leaves_no_folder(tmp_path, monkeypatch, capsys):
    out = tmp_path / "a" / "b" / "luts"
    fail_on_call(monkeypatch, exr.OpenEXR.File, "write", 2, _library_disk_full)
    assert run(["build", "--size", "6", "--out", out]) == 2
    error = capsys.readouterr().err
    assert_one_line_error(error)
    assert "ggx_schlick_rgb.exr" in error and "No space left" in error
    assert list(tmp_path.iterdir()) == []


def test_disk_full_keeps_the_previous_files(tmp_path, monkeypatch, capsys):
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    before = _files(out)
    fail_on_call(monkeypatch, exr.OpenEXR.File, "write", 1, _library_disk_full)
    assert run(["build", "--size", "8", "--out", out]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert _files(out) == before


def test_disk_full_during_a_scene_write(tmp_path, monkeypatch, capsys):
    scene = tmp_path / "scene.toml"
    scene.write_text('[[material]]\nname = "m"\nf0 = 0.04\nroughness = 0.5\n', encoding="utf-8")
    fail_on_call(monkeypatch, exr.OpenEXR.File, "write", 2, _library_disk_full)  # call 1 measures the sizes
    assert run(["scene", scene, "--out", tmp_path / "out"]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert not (tmp_path / "out").exists()


_KILLED_BUILD = textwrap.dedent("""
    import os, signal, sys
    from preintegrate import cli
    original, calls = os.replace, []
    def replace(source, target):
        if not str(target).endswith(".tmp"):
            calls.append(target)
            if len(calls) == 2:
                os.kill(os.getpid(), signal.SIGKILL)  # between the group's renames
        return original(source, target)
    os.replace = replace
    cli.main(["build", "--size", "8", "--out", sys.argv[1]])
""")


def test_kill_between_renames_is_finished_by_the_next_reader(tmp_path, capsys):
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    killed = subprocess.run([sys.executable, "-c", _KILLED_BUILD, str(out)], cwd=ROOT, capture_output=True)
    assert killed.returncode == -signal.SIGKILL
    assert (out / ".fresnel-lut-journal.json").exists()  # the group is half renamed
    basis_table, basis_header = read_lut(out / "ggx_basis_rgba.exr")  # the reader finishes the group
    schlick_table, schlick_header = read_lut(out / "ggx_schlick_rgb.exr")
    assert basis_table.shape[:2] == schlick_table.shape[:2] == (8, 8)
    assert read_lut(out / AVERAGE_LUT)[0].shape[:2] == (8, 1)  # the whole group, whichever was renamed
    assert sorted(path.name for path in out.iterdir()) == sorted(SHIPPED_LUTS)


def test_a_stale_temporary_is_removed_by_the_next_write(tmp_path, capsys):
    out = tmp_path / "luts"
    out.mkdir()
    (out / ".ggx_basis_rgba.exr.abc12345.tmp").write_bytes(b"left by a killed build")
    (out / ".my.own.notes.tmp").write_bytes(b"a user's file: not ours to remove")
    assert run(["build", "--size", "6", "--out", out]) == 0
    assert sorted(path.name for path in out.iterdir()) == sorted([".my.own.notes.tmp", *SHIPPED_LUTS])


def test_two_builds_into_one_folder_leave_one_consistent_set(tmp_path):
    out = tmp_path / "luts"
    environment = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    commands = [[sys.executable, "-m", "preintegrate.cli", "build", "--size", str(size), "--out", str(out)] + extra
                for size, extra in ((24, []), (20, ["--half"]))]
    for _ in range(3):
        processes = [subprocess.Popen(command, cwd=ROOT, env=environment, stdout=subprocess.DEVNULL,
                                      stderr=subprocess.DEVNULL) for command in commands]
        assert [process.wait(timeout=120) for process in processes] == [0, 0]
        headers = [read_lut(out / name)[1] for name in ("ggx_basis_rgba.exr", "ggx_schlick_rgb.exr")]
        assert headers[0]["pixel_type"] == headers[1]["pixel_type"] and headers[0]["width"] == headers[1]["width"]
