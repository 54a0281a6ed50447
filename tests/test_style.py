"""The tree keeps the one layout and lint configuration of pyproject.toml (``[tool.ruff]``: 120 columns, the
formatter owns the layout of code, imports sorted): ``ruff format --check`` and ``ruff check`` pass."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.parametrize("command", [["format", "--check"], ["check"]], ids=["format", "lint"])
def test_ruff(command):
    completed = subprocess.run([sys.executable, "-m", "ruff", *command, "."], cwd=ROOT, capture_output=True, text=True)
    assert completed.returncode == 0, completed.stdout[-3000:] + completed.stderr[-1000:]
