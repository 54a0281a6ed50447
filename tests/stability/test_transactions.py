"""Groups of files are one transaction even against a full disk, a second writer and kill -9.

A full disk inside the EXR library (which raises a bare RuntimeError) is one line naming the file, keeps the
previous files and leaves no folder behind; two builds into one folder never leave a mixed set; a process
killed between the renames of a group leaves a journal from which the next writer finishes the group (a
reader refuses the half-renamed set and changes nothing), and its temporaries are removed.
"""

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from basis.storage import recover_folder
from handoff import exr
from handoff.exr import read_lut
from handoff.shipped import AVERAGE_LUT, BASIS_LUT, SCHLICK_LUT, SHIPPED_LUTS
from handoff.tables import DEFAULT_BUILD_FILES
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
    assert "ggx_schlick_rgba.exr" in error and "No space left" in error
    assert list(tmp_path.iterdir()) == []


def test_a_folder_another_writer_creates_meanwhile_is_used_and_left(tmp_path, monkeypatch):
    """Two builds into a new folder race to create it (a fresh clone's run of
    test_two_builds_into_one_folder_leave_one_consistent_set lost one build, status 2): the folder another writer
    makes between this one's check and its mkdir is used as it is, and a failure afterwards leaves it (it is not
    this writer's to remove)."""
    from basis import storage

    out = tmp_path / "a" / "luts"
    real_mkdir = Path.mkdir

    def other_writer_first(path, *args, **kwargs):
        if path == out:
            real_mkdir(path)  # the other build's mkdir, just before this one's
        return real_mkdir(path, *args, **kwargs)

    monkeypatch.setattr(Path, "mkdir", other_writer_first)
    written = storage.write_together([(out / "one.txt", lambda temporary: temporary.write_text("1"))])
    assert [path.read_text() for path in written] == ["1"]

    (out / "one.txt").unlink()
    out.rmdir()
    (tmp_path / "a").rmdir()

    def failing(temporary):
        raise OSError(28, "No space left on device")

    with pytest.raises(OSError, match="No space left"):
        storage.write_together([(out / "two.txt", failing)])
    assert out.is_dir() and list(out.iterdir()) == []  # the other writer's folder stays
    monkeypatch.undo()
    assert sorted(path.name for path in tmp_path.iterdir()) == ["a"]


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
    from fresnel_lut import cli
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


def _kill_a_build_between_renames(out: Path, cwd: Path = ROOT) -> None:
    killed = subprocess.run(
        [sys.executable, "-c", _KILLED_BUILD, str(out)],
        cwd=cwd,
        capture_output=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )
    assert killed.returncode == -signal.SIGKILL, killed.stderr
    assert (cwd / out / ".fresnel-lut-journal.json").exists()  # the group is half renamed


def test_a_reader_refuses_a_half_renamed_set_and_changes_nothing(tmp_path):
    """Issue 26 item 1: a reader never renames, removes or writes; it refuses the tables of a half-renamed group
    (one of which may be of the new build, another of the old) with one line naming the folder."""
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    _kill_a_build_between_renames(out)
    before = _files(out)
    for name in SHIPPED_LUTS:
        with pytest.raises(exr.LutFileError, match="half-renamed") as refused:
            read_lut(out / name)
        assert str(out) in str(refused.value) and "\n" not in str(refused.value)
    assert _files(out) == before


def test_the_next_build_finishes_a_half_renamed_set(tmp_path, capsys):
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    _kill_a_build_between_renames(out)
    assert run(["build", "--size", "10", "--out", out]) == 0
    shapes = {read_lut(out / name)[0].shape[:2] for name in (BASIS_LUT, SCHLICK_LUT)}
    assert shapes == {(10, 10)} and read_lut(out / AVERAGE_LUT)[0].shape[:2] == (10, 1)
    assert sorted(path.name for path in out.iterdir()) == sorted(DEFAULT_BUILD_FILES)


def test_a_journal_left_by_a_relative_out_is_finished_from_another_folder(tmp_path, monkeypatch):
    """Issue 26 item 2: a build killed with the default relative ``--out luts`` is finished from another working
    folder that has a ``luts`` of its own: the journal names files relative to its folder, so the killed build's
    whole set (8 x 8) lands where it was going and the other ``luts`` is not touched."""
    work, elsewhere = tmp_path / "work", tmp_path / "elsewhere"
    (elsewhere / "luts").mkdir(parents=True)
    (elsewhere / "luts" / "keep.txt").write_text("an unrelated folder of the same relative name")
    work.mkdir()
    assert run(["build", "--size", "6", "--out", work / "luts"]) == 0
    _kill_a_build_between_renames(Path("luts"), cwd=work)
    monkeypatch.chdir(elsewhere)
    recover_folder(work / "luts")
    shapes = {read_lut(work / "luts" / name)[0].shape[:2] for name in (BASIS_LUT, SCHLICK_LUT)}
    assert shapes == {(8, 8)} and read_lut(work / "luts" / AVERAGE_LUT)[0].shape[:2] == (8, 1)
    assert sorted(path.name for path in (work / "luts").iterdir()) == sorted(DEFAULT_BUILD_FILES)
    assert sorted(path.name for path in (elsewhere / "luts").iterdir()) == ["keep.txt"]


def test_a_stale_temporary_is_removed_by_the_next_write(tmp_path, capsys):
    out = tmp_path / "luts"
    out.mkdir()
    (out / ".ggx_basis_rgba.exr.abc12345.tmp").write_bytes(b"left by a killed build")
    (out / ".my.own.notes.tmp").write_bytes(b"a user's file: not ours to remove")
    assert run(["build", "--size", "6", "--out", out]) == 0
    assert sorted(path.name for path in out.iterdir()) == sorted([".my.own.notes.tmp", *DEFAULT_BUILD_FILES])


def test_two_builds_into_one_folder_leave_one_consistent_set(tmp_path):
    out = tmp_path / "luts"
    environment = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    commands = [
        [sys.executable, "-m", "fresnel_lut.cli", "build", "--size", str(size), "--out", str(out)] + extra
        for size, extra in ((24, []), (20, ["--half"]))
    ]
    for _ in range(3):
        processes = [
            subprocess.Popen(command, cwd=ROOT, env=environment, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            for command in commands
        ]
        assert [process.wait(timeout=120) for process in processes] == [0, 0]
        headers = [read_lut(out / name)[1] for name in ("ggx_basis_rgba.exr", "ggx_schlick_rgba.exr")]
        assert headers[0]["pixel_type"] == headers[1]["pixel_type"] and headers[0]["width"] == headers[1]["width"]


def test_an_interrupted_removal_is_finished_by_the_next_build(tmp_path, monkeypatch, capsys):
    """The renames of a build are done but Ctrl-C stops it while it removes a stale file of its set (the second table
    of an earlier eight-term build): the journal stays, a reader refuses the half-finished set, the next build
    finishes it."""
    from basis import storage

    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    (out / "ggx_basis_rgba_2.exr").write_bytes((out / BASIS_LUT).read_bytes())  # a stale second table

    def interrupted(path):
        raise KeyboardInterrupt

    monkeypatch.setattr(storage, "_remove_file", interrupted)
    assert run(["build", "--size", "8", "--out", out]) == 130
    assert (out / ".fresnel-lut-journal.json").exists() and (out / "ggx_basis_rgba_2.exr").exists()
    with pytest.raises(exr.LutFileError, match="half-renamed"):
        read_lut(out / "ggx_basis_rgba_2.exr")
    monkeypatch.undo()
    assert run(["build", "--size", "8", "--out", out]) == 0
    assert sorted(path.name for path in out.iterdir()) == sorted(DEFAULT_BUILD_FILES)


_BUILDS = """
import sys
from fresnel_lut import cli
for size in [6, 7] * 15:
    assert cli.main(["build", "--size", str(size), "--out", sys.argv[1]]) == 0
"""


def test_a_reader_racing_healthy_builds_reads_the_old_set_or_the_new(tmp_path):
    """Issue 36 item 14: readers racing a healthy build were told a write was killed (631 of 519,000 reads): a
    writer holds the folder while it renames its set, and a reader waits for it, so every read finds a whole set."""
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    writer = subprocess.Popen(
        [sys.executable, "-c", _BUILDS, str(out)],
        cwd=ROOT,
        env={**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"},
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    reads, refused = 0, []
    while writer.poll() is None:
        for name in (BASIS_LUT, SCHLICK_LUT):
            try:
                table, header = read_lut(out / name)
                assert table.shape[:2] in ((6, 6), (7, 7)) and header["width"] == str(table.shape[1])
            except exr.LutFileError as error:
                refused.append(str(error))
            reads += 1
    assert writer.returncode == 0, writer.stderr.read()
    assert reads > 100 and refused == [], f"{len(refused)} of {reads} reads refused: {refused[:2]}"
