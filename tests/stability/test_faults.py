"""Bad input and faults at the ``fresnel-lut`` command line: every option fuzzed, corrupt and foreign files,
interrupted and failing writes, determinism.

Extends tests/fresnel_lut/test_cli.py (a dozen error cases, ``build`` interrupts, ``build --size 8`` determinism) to every
option of ``build``, ``basis``, ``coeffs`` and ``report --out``: negative, zero, NaN, inf, huge, strings, empty and
missing values. The contract checked for each: exit status 2; exactly one stderr line, beginning with
"fresnel-lut", that names the option (or its parameter) and, for a value of the right type, the accepted range or
choices; no Traceback; nothing on stdout; nothing written anywhere. References: byte comparison of files and of
folder listings before and after.
"""

from __future__ import annotations

import errno
import json
import os
import sys
from pathlib import Path

import pytest

from benchmarks.fault_cases import (
    BAD_BASIS,
    BASES,
    FLOAT_OPTIONS,
    FUZZ,
    exr_file,
    option_named,
    rehashed,
    valid_triple,
    with_option,
    write_file,
)
from fresnel_lut import cli
from handoff import exr, tables
from handoff.shipped import BASIS_LUT, SHIPPED_LUTS
from tests.conftest import assert_one_line_error, fail_on_call, run, run_subprocess


def _snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (recursively, hidden ones included) → its bytes."""
    return {str(path.relative_to(folder)): path.read_bytes() for path in sorted(folder.rglob("*")) if path.is_file()}


def _check_refused(argv, kind, capsys, folder):
    before = _snapshot(folder)
    assert run(argv) == 2
    captured = capsys.readouterr()
    assert_one_line_error(captured.err)
    assert captured.out == ""
    line = captured.err.strip()
    if kind != "usage":
        assert option_named(line, argv), line
    if kind == "range":
        assert "[" in line or "must be one of" in line or "must be auto, talk or notebook" in line, (
            line
        )  # range/choices
    assert _snapshot(folder) == before, "something was written"


@pytest.mark.parametrize("case", sorted(FUZZ))
def test_fuzzed_option_is_refused(case, tmp_path, monkeypatch, capsys):
    """One bad value of one option (the others valid): exit 2, one 'fresnel-lut…' line naming the option and,
    for a value of the right type, its range or choices; no Traceback; no stdout; nothing written (cwd = tmp)."""
    monkeypatch.chdir(tmp_path)
    argv, kind = FUZZ[case]
    _check_refused(argv, kind, capsys, tmp_path)


@pytest.mark.parametrize("option", sorted(FLOAT_OPTIONS))
def test_non_finite_message_states_the_range(option, tmp_path, monkeypatch, capsys):
    """--eta/--kappa/--reflectivity/--edge-tint nan: the one-line refusal states the accepted interval, like 0 or 1e7 do."""
    monkeypatch.chdir(tmp_path)
    base = FLOAT_OPTIONS[option][0]
    triple = valid_triple(option)
    triple[1] = "nan"
    _check_refused(with_option(base, option, triple), "range", capsys, tmp_path)


@pytest.mark.parametrize("seed", ["-1", "-99999999999999999999"])
def test_negative_seed(seed, tmp_path, monkeypatch, capsys):
    """basis --seed −1: refused like every other option (exit 2, one line naming --seed and its range)."""
    monkeypatch.chdir(tmp_path)
    _check_refused(["basis", "--count", "100", "--seed", seed, "--out", "b.json"], "range", capsys, tmp_path)


@pytest.mark.parametrize("edge_tint", ["0", "1"])
def test_reflectivity_next_to_one_names_reflectivity(edge_tint, tmp_path, monkeypatch, capsys):
    """coeffs --reflectivity 0.999999999 0.5 0.5: either coefficients (exit 0) or a refusal naming --reflectivity."""
    monkeypatch.chdir(tmp_path)
    status = run(["coeffs", "--reflectivity", "0.999999999", "0.5", "0.5", "--edge-tint", edge_tint, "0", "0"])
    captured = capsys.readouterr()
    if status != 0:
        assert status == 2 and "reflectivity" in captured.err, captured.err


# ----------------------------------------------------------------------------- output paths
@pytest.mark.parametrize("argv", [["build", "--size", "4", "--out", ""], ["report", "--quick", "--out", ""]])
def test_empty_out_is_refused(argv, tmp_path, monkeypatch, capsys):
    """--out '' (e.g. an unset shell variable): exit 2, one line naming --out, nothing written; report never started."""
    monkeypatch.chdir(tmp_path)
    import fresnel_lut.report

    def no_report(*args, **kwargs):
        raise AssertionError("report started with an empty --out")

    monkeypatch.setattr(fresnel_lut.report, "write_report", no_report)
    _check_refused(argv, "usage", capsys, tmp_path)


@pytest.mark.parametrize("command", ["basis", "build"])
def test_out_naming_an_existing_directory_keeps_it(command, tmp_path, monkeypatch, capsys):
    """basis --out DIR (DIR an existing folder with a file in it), or build --out D where D/ggx_basis_rgba.exr is a
    folder: exit 2, one line, the folder and its content untouched, no hidden temporaries."""
    monkeypatch.chdir(tmp_path)
    if command == "basis":
        folder = tmp_path / "precious"
        argv = ["basis", "--count", "100", "--out", folder]
    else:
        folder = tmp_path / "out" / BASIS_LUT
        argv = ["build", "--size", "4", "--out", tmp_path / "out"]
    folder.mkdir(parents=True)
    (folder / "keep.txt").write_text("keep me")
    before = _snapshot(tmp_path)
    status = run(argv)
    captured = capsys.readouterr()
    assert folder.is_dir() and (folder / "keep.txt").read_text() == "keep me"
    assert _snapshot(tmp_path) == before
    assert status == 2
    assert_one_line_error(captured.err)


@pytest.mark.parametrize("command", ["build", "basis"])
def test_unwritable_out_is_refused_before_the_work(command, tmp_path, monkeypatch, capsys):
    """--out under a regular file (cannot be created): refused before the integration / training starts."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("x")

    def no_work(*args, **kwargs):
        raise AssertionError("the work started before --out was checked")

    monkeypatch.setattr(tables, "build_table", no_work)
    monkeypatch.setattr(cli, "build_basis", no_work)
    argv = (
        ["build", "--size", "4", "--out", "a_file/luts"]
        if command == "build"
        else ["basis", "--count", "100", "--out", "a_file/b.json"]
    )
    _check_refused(argv, "usage", capsys, tmp_path)


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["build", "--size", "4", "--out", "a_file/luts"], "a_file"),
        (["basis", "--count", "100", "--out", "a_file/b.json"], "a_file"),
        (["report", "--out", "a_file"], "a_file"),
        (["report", "--out", "a_file/report"], "a_file"),
        (["build", "--size", "4", "--out", "/proc/no/such/folder"], "/proc/no"),
    ],
)
def test_out_that_cannot_be_created(argv, fragment, tmp_path, monkeypatch, capsys):
    """--out that is, or lies under, a regular file, or under /proc: exit 2, one line naming the path, the file
    untouched, nothing else written."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a_file").write_text("x")
    before = _snapshot(tmp_path)
    assert run(argv) == 2
    captured = capsys.readouterr()
    lines = [line for line in captured.err.splitlines() if line.startswith("fresnel-lut")]
    assert len(lines) == 1 and "Traceback" not in captured.err
    assert fragment in lines[0], lines[0]
    assert _snapshot(tmp_path) == before


# ----------------------------------------------------------------------------- corrupt and foreign --basis
@pytest.mark.parametrize("command", ["build", "coeffs"])
@pytest.mark.parametrize("case", sorted(BAD_BASIS))
def test_bad_basis_file_is_refused(case, command, tmp_path, monkeypatch, capsys):
    """--basis naming an empty, binary, EXR, non-UTF-8, UTF-16, non-object, foreign, truncated, hash-failing, NaN/inf,
    string-valued file, a folder, '' or nothing: exit 2, one line naming the basis file, no Traceback, nothing
    written; never a silent fallback to the shipped basis."""
    monkeypatch.chdir(tmp_path)
    path = BAD_BASIS[case](tmp_path)
    argv = ["build", "--size", "4", "--out", "out"] if command == "build" else list(BASES["coeffs_nk"])
    before = _snapshot(tmp_path)
    assert run(argv + ["--basis", path]) == 2
    captured = capsys.readouterr()
    assert_one_line_error(captured.err)
    assert captured.out == ""
    assert "basis" in captured.err
    assert _snapshot(tmp_path) == before


@pytest.mark.parametrize(
    "edit", ["coinciding fit angles", "nearly coinciding fit angles", "b0 not one", "b2 not zero at 0", "zero curve"]
)
def test_rehashed_degenerate_basis_is_refused(edit, tmp_path, monkeypatch, capsys):
    """A consistent-looking (re-hashed) basis.json violating the format's invariants: coeffs exits 2 with one line
    naming the basis file and what is wrong."""
    monkeypatch.chdir(tmp_path)

    def apply(data):
        if edit == "coinciding fit angles":
            data["fit_angles"][3] = data["fit_angles"][2]
        elif edit == "nearly coinciding fit angles":
            data["fit_angles"][3] = data["fit_angles"][2] - 1e-13
        elif edit == "b0 not one":
            data["curves"][0] = [2.0] * len(data["curves"][0])
        elif edit == "b2 not zero at 0":
            data["curves"][2][0] = 0.1
        else:
            data["curves"][3] = [0.0] * len(data["curves"][3])

    path = write_file(tmp_path, "b.json", rehashed(apply))
    assert run(list(BASES["coeffs_nk"]) + ["--basis", path]) == 2
    captured = capsys.readouterr()
    assert_one_line_error(captured.err)
    assert "basis" in captured.err


# ----------------------------------------------------------------------------- failing and interrupted writes
@pytest.fixture
def previous_build(tmp_path):
    out = tmp_path / "luts"
    assert run(["build", "--size", "6", "--out", out]) == 0
    return out, _snapshot(out)


def test_disk_full_during_exr_write(previous_build, monkeypatch, capsys):
    """OSError ENOSPC inside the 2nd EXR write (after writing part of it): exit 2, one line, both previous LUTs
    byte-identical, no temporaries."""
    out, before = previous_build

    def partial_then_disk_full(image, filename):
        Path(filename).write_bytes(b"v/1\x01partial")
        raise OSError(errno.ENOSPC, "No space left on device", filename)

    fail_on_call(monkeypatch, exr.OpenEXR.File, "write", 2, partial_then_disk_full)
    assert run(["build", "--size", "10", "--out", out]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert _snapshot(out) == before


def test_permission_denied_at_rename(previous_build, monkeypatch, capsys):
    """PermissionError at the 2nd rename of a build: exit 2, one line, both previous LUTs byte-identical (the first
    rename rolled back), no temporaries."""
    out, before = previous_build

    def permission_denied(source, destination):
        raise PermissionError(errno.EACCES, "Permission denied", str(destination))

    # backups are hard links; call 1 renames the first new file, call 2 the second
    fail_on_call(monkeypatch, os, "replace", 2, permission_denied)
    assert run(["build", "--size", "10", "--out", out]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert _snapshot(out) == before


@pytest.fixture
def previous_basis(tmp_path):
    path = tmp_path / "basis.json"
    assert run(["basis", "--count", "100", "--out", path]) == 0
    return path, _snapshot(tmp_path)


def test_basis_interrupted_while_training(previous_basis, monkeypatch, capsys):
    """Ctrl-C during `basis` training: exit 130, 'interrupted' on stderr, no Traceback, the previous basis.json
    byte-identical and nothing else written."""
    path, before = previous_basis

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_basis", interrupted)
    assert run(["basis", "--count", "100", "--out", path]) == 130
    err = capsys.readouterr().err
    assert "interrupted" in err and "Traceback" not in err
    assert _snapshot(path.parent) == before


def test_basis_interrupted_while_writing(previous_basis, monkeypatch, capsys):
    """Ctrl-C after half of the new basis.json is written to its temporary: exit 130, previous file byte-identical,
    the temporary removed."""
    path, before = previous_basis
    original = Path.write_text

    def write_text(self, text, *args, **kwargs):
        if self.name.endswith(".tmp"):
            original(self, text[: len(text) // 2], *args, **kwargs)
            raise KeyboardInterrupt
        return original(self, text, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", write_text)
    assert run(["basis", "--count", "100", "--out", path]) == 130
    capsys.readouterr()
    assert _snapshot(path.parent) == before


def test_basis_disk_full_while_writing(previous_basis, monkeypatch, capsys):
    """ENOSPC while writing the new basis.json: exit 2, one line, previous file byte-identical, temporary removed."""
    path, before = previous_basis
    original = Path.write_text

    def write_text(self, text, *args, **kwargs):
        if self.name.endswith(".tmp"):
            raise OSError(errno.ENOSPC, "No space left on device", str(self))
        return original(self, text, *args, **kwargs)

    monkeypatch.setattr(Path, "write_text", write_text)
    assert run(["basis", "--count", "100", "--out", path]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert _snapshot(path.parent) == before


# ----------------------------------------------------------------------------- determinism
def _set_cores(monkeypatch, count):
    """Both the integrator and the training set use os.cpu_count() threads by default."""
    monkeypatch.setattr(os, "cpu_count", lambda: count)


@pytest.mark.parametrize("half", [False, True])
def test_build_twice_is_bit_identical(half, tmp_path, monkeypatch, capsys):
    """build --size 16 (float32 and --half) twice — the second time with one thread instead of the machine's cores —
    gives byte-identical EXR files."""
    extra = ["--half"] if half else []
    assert run(["build", "--size", "16", "--out", tmp_path / "a", *extra]) == 0
    _set_cores(monkeypatch, 1)
    assert run(["build", "--size", "16", "--out", tmp_path / "b", *extra]) == 0
    capsys.readouterr()
    for name in SHIPPED_LUTS:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


def test_basis_twice_is_bit_identical(tmp_path, monkeypatch, capsys):
    """basis --count 2000 twice (second time on one thread) gives byte-identical basis.json; a different --seed
    gives a different one."""
    assert run(["basis", "--count", "2000", "--out", tmp_path / "a.json"]) == 0
    _set_cores(monkeypatch, 1)
    assert run(["basis", "--count", "2000", "--out", tmp_path / "b.json"]) == 0
    assert run(["basis", "--count", "2000", "--seed", "2", "--out", tmp_path / "c.json"]) == 0
    capsys.readouterr()
    assert (tmp_path / "a.json").read_bytes() == (tmp_path / "b.json").read_bytes()
    assert (tmp_path / "a.json").read_bytes() != (tmp_path / "c.json").read_bytes()


# ----------------------------------------------------------------------------- through a real process
SUBPROCESS_CASES = ["--count=0", "--fit-angles='bogus'", "--order='nan'", "--edge-tint[1]='1.1'", "--eta[0]='0'"]


@pytest.mark.parametrize("case", SUBPROCESS_CASES)
def test_fuzzed_option_via_subprocess(case, tmp_path):
    """A few fuzz cases through `python -m fresnel_lut.cli`: exit status 2, one stderr line, no Traceback, nothing
    written in the working folder."""
    argv, _ = FUZZ[case]
    result = run_subprocess(argv, cwd=tmp_path)
    assert result.returncode == 2
    assert_one_line_error(result.stderr)
    assert result.stdout == "" and list(tmp_path.iterdir()) == []


def test_foreign_basis_via_subprocess(tmp_path):
    """build --basis <an EXR file> through a real process: exit 2, one line naming the basis file, no output folder."""
    path = exr_file(tmp_path)
    result = run_subprocess(["build", "--size", "4", "--out", tmp_path / "out", "--basis", path], cwd=tmp_path)
    assert result.returncode == 2
    assert_one_line_error(result.stderr)
    assert "basis" in result.stderr and not (tmp_path / "out").exists()


def _editable_install() -> bool:
    """True when the package is installed in editable mode (setuptools' finder after the path finder)."""
    return any(
        "Editable" in type(finder).__name__ or "Editable" in getattr(finder, "__name__", "") for finder in sys.meta_path
    )


def test_commands_after_a_default_build_in_the_same_folder(tmp_path):
    """`python -m fresnel_lut.cli build --size 4` (default --out luts) then `coeffs --json` in the same folder:
    both exit 0 and the coefficients are those of the shipped basis (as in-process)."""
    assert run_subprocess(["build", "--size", "4"], cwd=tmp_path).returncode == 0
    assert (tmp_path / "luts" / BASIS_LUT).exists()
    result = run_subprocess(list(BASES["coeffs_nk"]) + ["--json"], cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    from basis import default_basis

    assert json.loads(result.stdout)["basis_hash"] == default_basis().content_hash
