"""``fresnel-lut report``: error against run time, measured side by side in one run on this machine.

Public objects: ``write_report``, ``environment``, ``read_system_value``.

Writes ``OUT/README.md`` (tables, the machine and versions, which targets were reached) and PNG plots
(with the ``plot`` extra) from three studies and a benchmark of the basis build:

1. LUT error vs generation time (:mod:`fresnel_lut.report.lut_error`);
2. Fresnel models: curve error vs evaluation cost, and 3. preintegrated error
   (:mod:`fresnel_lut.report.model_error`);
4. basis build: time and peak memory, convergence with the training-set size
   (:mod:`fresnel_lut.report.basis_build`).

``quick=True`` shrinks every study (32 × 32 tables, fewer settings and materials, 10^5 training curves)
so the whole report takes well under three minutes; the targets are then marked as not measured.
"""

from __future__ import annotations

import datetime
import importlib.metadata
import os
import platform
import subprocess
import time
from pathlib import Path

from basis.eigenbasis import default_basis
from basis.storage import write_together

from ..progress import Progress
from .approximation_error import approximation_markdown, approximation_table
from .basis_build import basis_build_cost, basis_build_markdown, basis_convergence
from .lut_error import lut_error_table_markdown, lut_error_vs_time, plot_lut_error
from .model_error import EIGHT_BIT_STEP, model_error_markdown, model_error_study, plot_model_error

__all__ = ["environment", "read_system_value", "write_report"]

PACKAGES = ("numpy", "scipy", "openexr", "colour-science", "matplotlib")


def read_system_value(path: str, key: str) -> str:
    """The value of the first ``key: value`` line of a system file (``/proc/cpuinfo``, ``/proc/meminfo``) that
    starts with ``key``; ``unknown`` where there is none."""
    try:
        for line in Path(path).read_text().splitlines():
            if line.startswith(key):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def environment() -> dict:
    """The machine, the versions and the code that produced the report."""
    versions = {}
    for name in PACKAGES:
        try:
            versions[name] = importlib.metadata.version(name)
        except importlib.metadata.PackageNotFoundError:
            versions[name] = "not installed"
    try:
        commit = subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            capture_output=True,
            text=True,
            cwd=Path(__file__).resolve().parent,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        commit = "unknown"
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    return {
        "date (UTC)": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M"),
        "machine": f"{platform.machine()}, {read_system_value('/proc/cpuinfo', 'model name')}",
        "cores": str(os.cpu_count()),
        "memory": read_system_value("/proc/meminfo", "MemTotal"),
        "load average at start (1, 5, 15 min)": ", ".join(f"{value:.2f}" for value in load),
        "system": platform.platform(),
        "python": platform.python_version(),
        **{f"{name}": version for name, version in versions.items()},
        "fresnel-basis commit": commit,
        "basis hash": default_basis().content_hash,
    }


def _targets(lut: dict, models: dict, cost: list[dict], quick: bool) -> list[tuple[str, str, str]]:
    """(target, measured, reached?) rows of the issue's targets."""
    rows = []
    default = next(row for row in lut["rows"] if row["method"] == "quadrature-schedule" and row["setting"] == 1.0)
    if quick:
        rows.append(
            (
                "128×128, 6 channels: max error ≤ 1e-6 in ≤ 2 s",
                f"{lut['size']}×{lut['size']} only (quick)",
                "not measured",
            )
        )
    else:
        reached = default["max_abs_error"] <= 1e-6 and default["seconds"] <= 2.0
        rows.append(
            (
                "128×128, 6 channels: max error ≤ 1e-6 in ≤ 2 s",
                f"{default['max_abs_error']:.1e} in {default['seconds']:.2f} s (best of {lut['repeats']} runs)",
                "yes" if reached else "no",
            )
        )
    ratios = [entry["ratio"] for entry in lut["equal_time"] if entry["ratio"] is not None]
    measured = ", ".join(
        f"{entry['method'].replace('hammersley-', '')} {entry['setting']} spp: {entry['ratio']:.3g}×"
        for entry in lut["equal_time"]
        if entry["ratio"] is not None
    )
    rows.append(
        (
            "≥ 1000× lower max error than Hammersley MC at equal time",
            measured or "no overlap in time",
            ("yes" if min(ratios) >= 1000 else f"no (lowest {min(ratios):.3g}×)") if ratios else "not measured",
        )
    )
    big = [row for row in cost if row["count"] >= 1_000_000]
    if big:
        row = big[0]
        reached = row["build_seconds"] <= 30 and row["peak_rss_mib"] <= 1024
        rows.append(
            (
                "basis: 10^6 curves × 512 angles in ≤ 30 s, ≤ 1 GB",
                f"{row['build_seconds']:.1f} s, {row['peak_rss_mib']} MiB",
                "yes" if reached else "no",
            )
        )
    else:
        rows.append(("basis: 10^6 curves × 512 angles in ≤ 30 s, ≤ 1 GB", "10^5 only (quick)", "not measured"))
    metals = models["preintegrated"]["models"]["basis-4point"]["metals"]
    rows.append(
        (
            "every held-out metal ≤ 1/255 in F̄ with the basis (four-point)",
            f"worst {metals['max_worst']:.2e}, {metals['above_8bit']}/{metals['count']} above 1/255",
            "yes" if metals["max_worst"] <= EIGHT_BIT_STEP else "no",
        )
    )
    return rows


def write_report(out="build/report", quick: bool = False) -> dict:
    """Run every study and write ``out/README.md`` and the PNGs (the folder is made only then, with the files: an
    interrupted or failed run leaves no folder behind). Returns paths and run times."""
    out = Path(out)
    started = time.perf_counter()
    env = environment()
    timings = {}

    progress = Progress("study 1: LUT error vs time", "tables")
    begin = time.perf_counter()
    # the speed target reads the best of three runs per table: one wall-clock run flips under load (issue 26 item 22)
    lut = lut_error_vs_time(quick=quick, progress=progress, repeats=1 if quick else 3)
    progress.close()
    timings["study 1"] = time.perf_counter() - begin

    print("studies 2 and 3: Fresnel models ...", flush=True)
    begin = time.perf_counter()
    models = model_error_study(quick=quick)
    timings["studies 2 and 3"] = time.perf_counter() - begin

    print("basis build benchmark ...", flush=True)
    begin = time.perf_counter()
    cost = basis_build_cost((100_000,) if quick else (100_000, 1_000_000))
    convergence = basis_convergence(start=12_500 if quick else 25_000, doublings=2 if quick else 4)
    timings["basis build"] = time.perf_counter() - begin

    print("models of the references on the basis ...", flush=True)
    begin = time.perf_counter()
    approximations = approximation_table(size=16 if quick else 32)
    timings["reference models"] = time.perf_counter() - begin

    figures = {}
    try:
        figures[out / "lut_error_vs_time.png"] = plot_lut_error(lut)
        figures[out / "fresnel_models.png"] = plot_model_error(models)
        plots_note = ""
    except ValueError as error:  # matplotlib missing
        plots_note = f"\n_Plots skipped: {error}_\n"

    targets = _targets(lut, models, cost, quick)
    lines = [
        "# fresnel-basis: error against run time",
        "",
        f"Generated by `fresnel-lut report{' --quick' if quick else ''}` in one run; every number below comes from "
        "that run on this machine (2 shared cores: timings move with other jobs, ratios measured side by side "
        "are the figures to compare).",
        "",
        "## Machine and versions",
        "",
        "| | |",
        "|---|---|",
        *[f"| {key} | {value} |" for key, value in env.items()],
        "",
        "## Targets",
        "",
        "| target | measured | reached |",
        "|---|---|---|",
        *[f"| {target} | {measured} | {reached} |" for target, measured, reached in targets],
        "",
        "## 1. Preintegration: LUT error against generation time",
        "",
        "![LUT error vs time](lut_error_vs_time.png)" if not plots_note else "",
        "",
        lut_error_table_markdown(lut),
        "## 2 and 3. Fresnel models: curve error, cost, preintegrated error",
        "",
        "![Fresnel models](fresnel_models.png)" if not plots_note else "",
        "",
        model_error_markdown(models),
        "## 4. Basis build: cost and convergence with the training-set size",
        "",
        "Build measured in a child process (`fresnel-lut basis --count N`, its own peak RSS; the time includes "
        "the fit-angle search). Convergence: max over θ of the change of each element when the training set "
        "doubles (same domain and seed), and the held-out four-point error of each basis.",
        "",
        basis_build_markdown(cost, convergence),
        plots_note,
        "",
        "## 5. Every Fresnel model of the references, projected onto the basis",
        "",
        approximation_markdown(approximations),
        "## 6. Measured materials in colour",
        "",
        "RMS ΔE2000 of Schlick, F82, Gulbrandsen and the basis against the spectral ground truth of Hoffman's "
        "metals and dielectrics, his blending and gamut tests, and what closes the gap to his 0.08: "
        "[materials.md](materials.md), written by `fresnel-lut materials` (about 6 minutes; it also writes "
        "`luts/materials.json`).",
        "",
        "Run times: "
        + ", ".join(f"{name} {seconds:.1f} s" for name, seconds in timings.items())
        + f"; whole report {time.perf_counter() - started:.1f} s.",
        "",
    ]
    readme, text = out / "README.md", "\n".join(lines)
    # the README and its plots are one transaction: a full disk or Ctrl-C leaves the folder as it was
    write_together(
        [
            (readme, lambda temporary: temporary.write_text(text, encoding="utf-8")),
            *[(path, lambda temporary, data=data: temporary.write_bytes(data)) for path, data in figures.items()],
        ]
    )
    return {"readme": readme, "pngs": list(figures), "seconds": time.perf_counter() - started, "targets": targets}
