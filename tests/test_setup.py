"""Issue 26 item 22: the set-up. Read from ``make -n -B`` (every command the target would run, none run): ``make luts``
installs no system package (building needs neither Mesa nor glslang), the test set-up waits for the dpkg lock rather
than failing on it, README names the extras the Makefile installs, and ``make report`` writes its timings and dates
outside the committed snapshot."""

import re
import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
pytestmark = pytest.mark.skipif(shutil.which("make") is None, reason="no make on this machine")


def _dry_run(target: str) -> str:
    completed = subprocess.run(
        ["make", "-n", "-B", target], cwd=ROOT, capture_output=True, text=True, timeout=60, check=True
    )
    return completed.stdout


def test_building_installs_no_system_package():
    commands = _dry_run("luts")
    assert "fresnel-lut build" in commands
    assert "apt-get" not in commands and "glslang" not in commands and "mesa" not in commands


def test_the_test_set_up_waits_for_the_dpkg_lock():
    commands = _dry_run("test")
    installs = [line for line in commands.splitlines() if re.search(r"apt-get (-o \S+ )*(update|install)\b", line)]
    assert installs and all("DPkg::Lock::Timeout=" in line for line in installs)


def test_readme_names_the_extras_the_makefile_installs():
    extras = re.search(r"pip install --quiet -e '\.\[([\w,]+)\]'", _dry_run("test")).group(1)
    assert f"`.[{extras}]`" in (ROOT / "README.md").read_text(encoding="utf-8")


def test_make_report_leaves_the_committed_snapshot_alone():
    commands = _dry_run("report")
    assert "fresnel-lut report --out build/report" in commands
    assert not re.search(r"--out report(\s|$)", commands)
