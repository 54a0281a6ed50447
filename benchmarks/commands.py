"""Wall time and peak memory of every interactive command, side by side with ``python -c "import numpy"``.

Run from the repository root: ``.venv/bin/python -m benchmarks.commands [--repeats N] [--full] [--out FILE]
[--tree DIR]``; ``--tree`` runs the commands of another checkout (``python -m fresnel_lut.cli`` in DIR, e.g. a
``git worktree`` of an older commit) for a before/after table on the same machine.
Each command runs in a fresh process (``os.wait4`` gives that process's own peak resident memory); fast
commands are repeated and the median is reported, with the spread. The machine is shared: the ratio to
the ``import numpy`` baseline measured in the same run is the comparable figure, and the targets of
issue 16 stand beside each row. ``--full`` adds the long ones (full render, ``make test``). The table is
written to ``report/benchmarks.md`` (or ``--out``); README's times are this table's.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.output import machine

ROOT = Path(__file__).resolve().parents[1]
BIN = Path(sys.executable).parent
COEFFICIENTS_1E6 = (
    "import numpy as np; from basis import coefficients_from_nk; rng = np.random.default_rng(0); "
    "eta, kappa = rng.uniform(0.1, 4, 10**6), rng.uniform(0, 8, 10**6); coefficients_from_nk(eta[:1], kappa[:1]); "
    "import time; t = time.perf_counter(); coefficients_from_nk(eta, kappa); print(time.perf_counter() - t)"
)


def _jobs(folder: Path, full: bool, tree: Path | None) -> list[tuple[str, list[str], str]]:
    """(label, argv, target) of every measured command."""
    lut = [str(BIN / "fresnel-lut")] if tree is None else [sys.executable, "-m", "fresnel_lut.cli"]
    jobs = [
        ("python -c 'import numpy' (baseline)", [sys.executable, "-c", "import numpy"], ""),
        ("import basis", [sys.executable, "-c", "import basis"], "<= 0.3 s"),
        ("fresnel-lut --help", lut + ["--help"], ""),
        ("fresnel-lut coeffs --material Gold", lut + ["coeffs", "--material", "Gold"], "<= 0.5 s"),
        ("fresnel-lut build", lut + ["build", "--out", str(folder / "build")], "<= 1.3 s"),
        ("coefficients_from_nk, 10^6 materials (in-process time)", [sys.executable, "-c", COEFFICIENTS_1E6], "0.30 s"),
    ]
    # the showcase trains its scene basis up to seven terms (issue 14); the others stop at four
    jobs += [
        (
            f"fresnel-lut scene examples/{scene.name}",
            lut + ["scene", str(scene), "--out", str(folder / scene.stem)],
            "<= 8 s" if scene.stem == "showcase" else "<= 3 s",
        )
        for scene in sorted((ROOT / "examples").glob("*.toml"))
    ]
    jobs += [
        ("fresnel-lut materials", lut + ["materials", "--presets", str(folder / "materials.json")], "<= 30 s"),
        (
            "fresnel-lut basis --count 1000000",
            lut + ["basis", "--count", "1000000", "--out", str(folder / "b.json")],
            "<= 20 s",
        ),
        ("fresnel-lut render --quick", lut + ["render", "--quick", "--out", str(folder / "render")], "<= 8 s"),
    ]
    if full:
        jobs += [
            ("fresnel-lut render", lut + ["render", "--out", str(folder / "render-full")], "<= 90 s"),
            ("make test", ["make", "-s", "test"], "<= 100 s"),
        ]
    return jobs


def _measure(argv: list[str], cwd: Path) -> tuple[float, float, str]:
    """(seconds, peak RSS in MiB, stdout) of one run in a fresh process."""
    started = time.perf_counter()
    process = subprocess.Popen(argv, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    output = process.stdout.read()
    _, status, usage = os.wait4(process.pid, 0)
    seconds = time.perf_counter() - started
    process.returncode = os.waitstatus_to_exitcode(status)
    if process.returncode != 0:
        raise RuntimeError(f"{' '.join(argv)} failed with status {process.returncode}")
    return seconds, usage.ru_maxrss / 1024.0, output


def benchmark(repeats: int = 5, full: bool = False, tree: Path | None = None) -> list[dict]:
    rows = []
    with tempfile.TemporaryDirectory() as folder:
        for label, argv, target in _jobs(Path(folder), full, tree):
            count = (
                repeats
                if not label.startswith(("fresnel-lut basis", "fresnel-lut materials", "fresnel-lut render", "make"))
                else 1
            )
            runs = [_measure(argv, ROOT if tree is None else tree) for _ in range(count)]
            seconds = [run[0] for run in runs]
            if label.startswith("coefficients_from_nk"):
                seconds = [float(run[2].strip().splitlines()[-1]) for run in runs]
            rows.append(
                {
                    "job": label,
                    "seconds": statistics.median(seconds),
                    "low": min(seconds),
                    "high": max(seconds),
                    "runs": count,
                    "peak_mib": max(run[1] for run in runs),
                    "target": target,
                }
            )
            print(f"{label}: {rows[-1]['seconds']:.2f} s, {rows[-1]['peak_mib']:.0f} MiB", file=sys.stderr, flush=True)
    return rows


def markdown(rows: list[dict]) -> str:
    baseline = rows[0]["seconds"]
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    lines = [
        "# Command benchmark",
        "",
        f"`python -m benchmarks.commands`, {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC, "
        f"{machine()}, Python {platform.python_version()}, load average after the run "
        f"{load[0]:.2f}. Wall time of a fresh process (median of the runs, range in brackets), peak resident memory, "
        "and the time as a multiple of `python -c 'import numpy'` measured in the same run.",
        "",
        "| job | wall time | × import numpy | peak memory | target |",
        "|---|---:|---:|---:|---|",
    ]
    for row in rows:
        spread = f" [{row['low']:.2f}–{row['high']:.2f}]" if row["runs"] > 1 else ""
        lines.append(
            f"| {row['job']} | {row['seconds']:.2f} s{spread} | {row['seconds'] / baseline:.1f} | "
            f"{row['peak_mib']:.0f} MiB | {row['target']} |"
        )
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs of each fast command (default 5)")
    parser.add_argument("--full", action="store_true", help="also the full render and make test")
    parser.add_argument("--out", type=Path, default=ROOT / "report" / "benchmarks.md", help="Markdown table")
    parser.add_argument("--tree", type=Path, default=None, help="measure another checkout's commands (before/after)")
    arguments = parser.parse_args(argv)
    if shutil.which("make") is None and arguments.full:
        parser.error("--full needs make")
    text = markdown(benchmark(arguments.repeats, arguments.full, arguments.tree))
    from basis.storage import write_text

    write_text(arguments.out, text)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
