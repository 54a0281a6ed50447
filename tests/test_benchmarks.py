"""Every ``python -m benchmarks.*`` entry runs (issue 22: README's stability table could not be regenerated because
``benchmarks.stability_table`` imported a test module by an old name). Each is run in a fresh process as README says,
with small settings where it has them; ``benchmarks.fuzz`` runs in tests/test_fuzz.py and ``benchmarks.commands``
(minutes: it times every command) is started with ``--help`` only."""

import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
#: The entries: modules of benchmarks/ that run as a program (helpers such as ``benchmarks.output`` do not).
ENTRIES = sorted(
    path.stem
    for path in (ROOT / "benchmarks").glob("*.py")
    if 'if __name__ == "__main__":' in path.read_text(encoding="utf-8")
)


def _run(*argv, timeout=300):
    return subprocess.run([sys.executable, "-m", *argv], cwd=ROOT, capture_output=True, text=True, timeout=timeout)


def test_every_benchmark_is_listed_here():
    assert ENTRIES == [
        "area_lights",
        "commands",
        "fuzz",
        "lut_edges",
        "quadrature_vs_montecarlo",
        "shader_cost",
        "stability_table",
        "view_page",
    ]


@pytest.mark.parametrize("entry", ENTRIES)
def test_every_benchmark_starts(entry):
    completed = _run(f"benchmarks.{entry}", "--help")
    assert completed.returncode == 0 and "usage" in completed.stdout, completed.stderr


@pytest.mark.slow
def test_the_stability_table_regenerates():
    completed = _run("benchmarks.stability_table")
    assert completed.returncode == 0, completed.stderr[-2000:]
    assert "## Extreme regimes, API fuzz, CLI fuzz" in completed.stdout and "| FAIL |" not in completed.stdout


@pytest.mark.slow
def test_lut_edges_runs_small():
    """The edge study at 32 x 32: the default placement beats texel centres on every edge and at the issue's points."""
    completed = _run("benchmarks.lut_edges", "--size", "32", "--points", "200")
    assert completed.returncode == 0, completed.stderr[-2000:]
    for region in ("mu_o = 0 ", "mu_o = 1 ", "r = 1 ", "the issue's points"):
        row = next(line for line in completed.stdout.splitlines() if line.startswith(f"| {region}"))
        centres, _, default = (float(cell.split()[0]) for cell in row.strip("|").split("|")[1:])
        assert default < centres, row


@pytest.mark.slow
def test_quadrature_against_monte_carlo_runs_small():
    completed = _run("benchmarks.quadrature_vs_montecarlo", "--samples", "2000", "--size", "8")
    assert completed.returncode == 0, completed.stderr[-2000:]


@pytest.mark.slow
def test_shader_cost_runs_small():
    """The shader-cost benchmark on llvmpipe at 64 × 36, one round: every variant compiles and draws."""
    completed = _run("benchmarks.shader_cost", "--width", "64", "--height", "36", "--frames", "1", "--rounds", "1")
    assert completed.returncode == 0, completed.stderr[-2000:]
    assert completed.stdout.count("| basis per pixel") == 3
    assert completed.stdout.count("direct light from a 512-texel table") == 1


@pytest.mark.slow
def test_area_lights_runs_small():
    """The area-light report at 8 x 8 with a 6 x 6 fit and no peers (npm is the benchmark's, not the suite's)."""
    completed = _run(
        "benchmarks.area_lights", "--size", "8", "--nodes", "8", "--ltc-size", "6", "--three", "none", timeout=600
    )
    assert completed.returncode == 0, completed.stderr[-2000:]
    assert completed.stdout.count("| Gold |") == 1 and "three.js not measured: not asked for" in completed.stdout


@pytest.mark.slow
def test_the_look_development_page_benchmark_writes_its_screenshot(tmp_path):
    """README's screenshot of the page is this benchmark's (``--out report``); small, into a temporary folder."""
    completed = _run(
        "benchmarks.view_page", "--size", "48", "--samples", "32", "--repeats", "2", "--out", str(tmp_path)
    )
    assert completed.returncode == 0, completed.stderr[-2000:]
    assert (tmp_path / "view.png").read_bytes().startswith(b"\x89PNG") and "Console errors: 0" in completed.stdout
    assert "| basis split sum |" in (tmp_path / "view.md").read_text(encoding="utf-8")
