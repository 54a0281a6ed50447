"""Ctrl-C ends any command with exit status 130 and one line, never a traceback: while the modules load and
in the middle of a long build (whose queued batches are cancelled instead of run), leaving nothing written.
Run through the installed console command, as a user does."""

import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

COMMAND = str(Path(sys.executable).parent / "fresnel-lut")


def _interrupted(argv, delay):
    process = subprocess.Popen(
        [COMMAND, *argv],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )
    time.sleep(delay)
    process.send_signal(signal.SIGINT)
    _, error = process.communicate(timeout=60)
    return process.returncode, error


@pytest.mark.parametrize("delay", [0.03, 0.06, 0.1, 0.2, 0.3])
def test_ctrl_c_while_starting(delay, tmp_path):
    status, error = _interrupted(["build", "--size", "32", "--out", tmp_path / "out"], delay)
    if status == 0:  # the command finished first: nothing to interrupt
        return
    if "init_import_site" in error:  # CPython's own start-up (its site module, ~15 ms) runs before any of ours
        return
    frames = set(re.findall(r'File "([^"]+)"', error))
    if frames and all(frame == COMMAND or frame.startswith("<frozen ") for frame in frames):
        return  # still in pip's wrapper script or CPython's import machinery (compiling entry.py): no line of ours ran
    assert status == 130 and "Traceback" not in error, error
    assert error.strip().splitlines()[-1].startswith("fresnel-lut: interrupted")
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_ctrl_c_during_a_long_build(tmp_path):
    status, error = _interrupted(["build", "--size", "768", "--out", tmp_path / "out"], 1.5)
    assert status == 130 and "Traceback" not in error, error
    assert not (tmp_path / "out").exists()


def test_ctrl_c_inside_a_lazily_loaded_c_extension(monkeypatch, capsys):
    """scipy loads on first use, after the start-up window; Ctrl-C inside its pybind11 module initialisation
    surfaces as ``ImportError: initialization failed`` caused by KeyboardInterrupt (seen once in a fresh
    clone's run of test_ctrl_c_while_starting). It ends the command like any Ctrl-C; another ImportError
    still propagates."""
    from fresnel_lut import cli, entry

    def interrupted_import():
        try:
            raise KeyboardInterrupt
        except KeyboardInterrupt as interrupt:
            raise ImportError("initialization failed") from interrupt

    monkeypatch.setattr(cli, "main", interrupted_import)
    assert entry.main() == 130
    assert capsys.readouterr().err.strip().startswith("fresnel-lut: interrupted")

    def missing_module():
        raise ImportError("No module named 'nothing'")

    monkeypatch.setattr(cli, "main", missing_module)
    with pytest.raises(ImportError, match="nothing"):
        entry.main()
