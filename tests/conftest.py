"""Shared test helpers: running the CLI in-process or as a subprocess, checking its one-line errors, and
making the n-th call of a function fail. Test modules import them from here (``tests.conftest``) and never
from one another; the deliberately independent references are ``tests.references``."""

from __future__ import annotations

import subprocess
import sys

from fresnel_lut import cli


def run(argv):
    """cli.main in-process; argparse errors raise SystemExit, converted to its status."""
    try:
        return cli.main([str(a) for a in argv])
    except SystemExit as exit_:
        return exit_.code


def run_subprocess(argv, cwd):
    return subprocess.run(
        [sys.executable, "-m", "fresnel_lut.cli", *map(str, argv)], capture_output=True, text=True, cwd=cwd, timeout=120
    )


def assert_one_line_error(stderr):
    lines = stderr.splitlines()
    assert len(lines) == 1, stderr
    assert lines[0].startswith("fresnel-lut"), stderr
    assert "error" in lines[0]
    assert "Traceback" not in stderr


def fail_on_call(monkeypatch, owner, name, call, failure):
    """Patch ``owner.name`` so that its ``call``-th call runs ``failure(*arguments)`` (which raises) instead."""
    original, calls = getattr(owner, name), []

    def patched(*arguments):
        calls.append(arguments)
        if len(calls) == call:
            failure(*arguments)
        return original(*arguments)

    monkeypatch.setattr(owner, name, patched)
