"""Study: cost of building the basis and its convergence with the size of the training set.

Public objects: ``basis_build_cost``, ``basis_convergence``, ``basis_build_markdown``.

The build cost is measured in a child process that calls :func:`basis.training.build_basis` (what
``fresnel-lut basis`` runs) and reports its time and peak resident memory as JSON, so the memory is its
own and not that of the report. Convergence: bases from N, 2N, 4N, … curves (same domain and θ grid);
for each doubling, max over θ of |b_k(2N) − b_k(N)| for every element, and the held-out four-point
error of each basis.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from basis.angles import angle_grid
from basis.eigenbasis import Basis
from basis.training import DEFAULT_DOMAIN, build_curves, holdout_fit_errors

__all__ = ["basis_build_cost", "basis_build_markdown", "basis_convergence"]


#: The child of :func:`basis_build_cost`: build and write a basis, print the time and the peak memory.
_CHILD = """
import json, sys, time
from basis.training import build_basis
from fresnel_lut.progress import peak_rss_mib
started = time.perf_counter()
build_basis(count=int(sys.argv[1])).write(sys.argv[2])
print(json.dumps({"seconds": time.perf_counter() - started, "peak_rss_mib": peak_rss_mib()}))
"""


def basis_build_cost(counts=(100_000, 1_000_000)) -> list[dict]:
    """Wall time and peak RSS of a basis build from N curves in a fresh process, per N."""
    rows = []
    for count in counts:
        with tempfile.TemporaryDirectory() as folder:
            started = time.perf_counter()
            completed = subprocess.run(
                [sys.executable, "-c", _CHILD, str(count), str(Path(folder) / "b.json")],
                capture_output=True,
                text=True,
                check=True,
            )
            wall = time.perf_counter() - started
        measured = json.loads(completed.stdout)
        rows.append(
            {
                "count": count,
                "angles": 512,
                "build_seconds": measured["seconds"],
                "process_seconds": wall,
                "peak_rss_mib": round(measured["peak_rss_mib"]),
            }
        )
    return rows


def basis_convergence(start: int = 25_000, doublings: int = 4, seed: int = 1) -> list[dict]:
    """Change of each b_k when the training set doubles, and the held-out error of each basis."""
    theta = angle_grid(512)
    previous, rows = None, []
    for step in range(doublings + 1):
        count = start * 2**step
        curves, _ = build_curves(theta, DEFAULT_DOMAIN.curves(theta, count, seed), 4)
        basis = Basis(theta, curves, np.array([0.0, 0.5 * np.pi, 1.5, 1.26]))
        row = {"count": count, **{f"holdout_{name}": error for name, error in holdout_fit_errors(basis).items()}}
        if previous is not None:
            for k in range(1, curves.shape[0]):
                row[f"change_b{k}"] = float(np.max(np.abs(curves[k] - previous[k])))
        rows.append(row)
        previous = curves
    return rows


def basis_build_markdown(cost: list[dict], convergence: list[dict]) -> str:
    """Two Markdown tables."""
    lines = ["| training curves × angles | build time (s) | peak RSS (MiB) |", "|---|---|---|"]
    lines += [
        f"| {row['count']:,} × {row['angles']} | {row['build_seconds']:.1f} | {row['peak_rss_mib']} |" for row in cost
    ]
    lines += [
        "",
        "| curves N | max Δb1 vs N/2 | max Δb2 | max Δb3 | held-out metals, max ΔF | held-out dielectrics, max ΔF |",
        "|---|---|---|---|---|---|",
    ]
    for row in convergence:
        changes = " | ".join(f"{row[f'change_b{k}']:.1e}" if f"change_b{k}" in row else "–" for k in (1, 2, 3))
        lines.append(
            f"| {row['count']:,} | {changes} | {row['holdout_metals']:.4f} | {row['holdout_dielectrics']:.4f} |"
        )
    return "\n".join(lines)
