"""Study 1 of the report: LUT error against generation time, quadrature against the engines' Monte Carlo.

Public objects: ``lut_error_vs_time``, ``plot_lut_error``, ``lut_error_table_markdown``, ``QUICK``.

For one table of the six channels an engine ships (4 basis + 2 Schlick,
``combine(basis_channels(), schlick_channels())``) on the engines' texel grid, :meth:`preintegrate.lut.LutGrid.centred`
(texel centres: their estimate divides by μo and needs α > 0, which the default grid's edge texels are not):

* our deterministic quadrature (:func:`preintegrate.lut.build_table`): the shipped schedule scaled by
  several factors (``method="quadrature-schedule"``, setting = factor, 1 = what ``fresnel-lut build``
  uses) and several uniform orders n (``method="quadrature"``, ``QuadratureOrder.uniform(n)``, 2n² nodes
  per texel);
* the engine practice (:func:`preintegrate.estimators.hammersley_albedo` through ``build_table(method="hammersley")``): N Hammersley points per texel
  with GGX NDF importance sampling (Karis 2013; UE4, Filament, glTF IBL Sampler), and the same points with
  VNDF sampling (Heitz 2018);

each timed with ``time.perf_counter`` in this one run and compared, texel by texel and channel by
channel, against one converged reference (the quadrature at ``reference_order``, computed once). The
"equal-time ratio" divides each Hammersley table's max error by the quadrature's max error at the same
time, interpolated in log-log within each quadrature family, the better family at that time (the issue's
target: ≥ 1000× lower max error at equal wall time).

Run: ``python -m fresnel_lut.report.lut_error [--quick] [--size N] [--png FILE]``.

References
----------
:cite:`Karis2013` B. Karis, "Real Shading in Unreal Engine 4", SIGGRAPH 2013 course notes.
:cite:`Heitz2018` E. Heitz, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), 2018.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from basis.validation import ParameterError, check_positive_int, check_range
from preintegrate.channels import basis_channels, combine, schlick_channels
from preintegrate.lut import LutGrid, build_table
from preintegrate.quadrature import DEFAULT_ORDER, QuadratureOrder

from .figures import pyplot, save_figure

__all__ = ["QUICK", "lut_error_table_markdown", "lut_error_vs_time", "plot_lut_error"]

#: Settings of ``quick=True`` (replacing the arguments): a 32 × 32 table in a few seconds.
QUICK = {"size": 32, "orders": (8, 16, 32), "scales": (0.5, 1.0), "samples": (64, 1024), "reference_order": 64}

METHODS = ("quadrature-schedule", "quadrature", "hammersley-ndf", "hammersley-vndf")
QUADRATURE_METHODS = ("quadrature-schedule", "quadrature")
_SAMPLING = {"hammersley-ndf": "ndf", "hammersley-vndf": "vndf"}


def _settings(name: str, values, high: int) -> tuple[int, ...]:
    if isinstance(values, (str, bytes)) or not isinstance(values, Sequence) or len(values) == 0:
        raise ParameterError(f"{name} must be a non-empty sequence of integers, got {values!r}")
    return tuple(check_positive_int(f"{name}[{k}]", value, low=1, high=high) for k, value in enumerate(values))


def _errors(table: np.ndarray, reference: np.ndarray) -> tuple[float, float]:
    difference = np.abs(table - reference)
    return float(difference.max()), float(np.sqrt(np.mean(difference * difference)))


def _interpolated_error(rows: list[dict], seconds: float) -> float | None:
    """Max error of one quadrature family at ``seconds``, linear in log-log between its bracketing rows."""
    rows = sorted(rows, key=lambda row: row["seconds"])
    log_seconds = np.log([row["seconds"] for row in rows])
    if not rows or np.log(seconds) < log_seconds[0]:
        return None
    if np.log(seconds) > log_seconds[-1]:  # the family's slowest setting is faster still: a lower bound
        return float(min(row["max_abs_error"] for row in rows))
    log_errors = np.log([max(row["max_abs_error"], 1e-300) for row in rows])
    return float(np.exp(np.interp(np.log(seconds), log_seconds, log_errors)))


def _equal_time(rows: list[dict]) -> list[dict]:
    """Each Hammersley row against the quadrature's error at the same time.

    Within each quadrature family the max error is interpolated linearly in log(error) against
    log(seconds) between the settings that bracket the Hammersley time (a single timing of a fast step is
    noisy on shared cores; the interpolated curve is not); the better family at that time is used.
    Past a family's slowest setting its best error is used (more time could only lower it, so the ratio
    is then a lower bound); below every family's fastest setting the ratio is ``None``.
    """
    ratios = []
    for row in rows:
        if row["method"] in QUADRATURE_METHODS:
            continue
        candidates = {
            method: _interpolated_error([q for q in rows if q["method"] == method], row["seconds"])
            for method in QUADRATURE_METHODS
        }
        candidates = {method: error for method, error in candidates.items() if error is not None}
        best = min(candidates, key=candidates.get) if candidates else None
        error = None if best is None else candidates[best]
        ratios.append(
            {
                "method": row["method"],
                "setting": row["setting"],
                "seconds": row["seconds"],
                "max_abs_error": row["max_abs_error"],
                "quadrature_method": best,
                "quadrature_max_abs_error": error,
                "ratio": None if error is None else row["max_abs_error"] / error,
            }
        )
    return ratios


def lut_error_vs_time(
    size: int = 128,
    orders: Sequence[int] = (8, 12, 16, 24, 32, 48),
    scales: Sequence[float] = (0.3, 0.4, 0.5, 0.65, 0.8, 1.0, 1.5),
    samples: Sequence[int] = (64, 256, 1024, 4096),
    reference_order: int = 96,
    quick: bool = False,
    progress: Callable[[int, int], None] | None = None,
    *,
    repeats: int = 1,
) -> dict:
    """Time and error of every table setting against one converged reference.

    Parameters
    ----------
    size : int
        Table width = height, in [2, 8192].
    orders : sequence of int
        Quadrature orders n (``QuadratureOrder.uniform(n)``), each below ``reference_order``.
    scales : sequence of float
        Factors of the shipped schedule (:meth:`QuadratureSchedule.scaled`); 1 is the shipped one.
    samples : sequence of int
        Hammersley points per texel, each in [1, 2^24]; both NDF and VNDF sampling are run.
    reference_order : int
        Order of the reference table, in [2, 4096].
    quick : bool
        Use :data:`QUICK` (size 32, fewer settings) instead of the four arguments above.
    progress : callable, optional
        Called with (tables done, tables total).
    repeats : int
        Build every compared table this many times and keep the shortest time (the ``timeit`` convention:
        on shared cores, other jobs only ever add time). The reference is built once.

    Returns
    -------
    dict
        ``size``, ``channels`` (names), ``reference_order``, ``reference_seconds``, ``rows`` (one dict per
        table: ``method`` in :data:`METHODS`, ``setting`` (order or samples per texel), ``seconds``,
        ``max_abs_error``, ``rms_abs_error``), ``equal_time`` (see the module notes) and
        ``total_seconds`` (the whole study, reference included).
    """
    if quick:
        size, orders, samples, scales = QUICK["size"], QUICK["orders"], QUICK["samples"], QUICK["scales"]
        reference_order = QUICK["reference_order"]
    size = check_positive_int("size", size, low=2, high=8192)
    reference_order = check_positive_int("reference_order", reference_order, low=2, high=4096)
    orders = _settings("orders", orders, reference_order - 1)
    samples = _settings("samples", samples, 1 << 24)
    if isinstance(scales, (str, bytes)) or not isinstance(scales, Sequence) or len(scales) == 0:
        raise ParameterError(f"scales must be a non-empty sequence of numbers, got {scales!r}")
    scales = tuple(float(check_range(f"scales[{k}]", value, 0.05, 4.0)) for k, value in enumerate(scales))
    if progress is not None and not callable(progress):
        raise ParameterError(f"progress must be callable or None, got {type(progress).__name__}")
    repeats = check_positive_int("repeats", repeats, low=1, high=100)

    channels = combine(basis_channels(), schlick_channels())
    # Warm-up: first calls (spline set-up, lazy imports) stay out of the timings.
    build_table(channels, LutGrid.centred(2), order=QuadratureOrder.uniform(2))
    for sampling in _SAMPLING.values():
        build_table(channels, LutGrid.centred(2), method="hammersley", samples=4, sampling=sampling)

    total_tables = 1 + len(scales) + len(orders) + len(_SAMPLING) * len(samples)
    done = 0

    def step():
        nonlocal done
        done += 1
        if progress is not None:
            progress(done, total_tables)

    study_start = time.perf_counter()
    start = time.perf_counter()
    grid = LutGrid.centred(size)
    reference = build_table(channels, grid, order=QuadratureOrder.uniform(reference_order))
    reference_seconds = time.perf_counter() - start
    step()

    def timed(build, *args, **kwargs):
        best = np.inf
        for _ in range(repeats):
            start = time.perf_counter()
            table = build(*args, **kwargs)
            best = min(best, time.perf_counter() - start)
        return table, best

    rows = []
    for scale in scales:
        table, seconds = timed(build_table, channels, grid, order=DEFAULT_ORDER.scaled(scale))
        rows.append(
            {"method": "quadrature-schedule", "setting": scale, "seconds": seconds, **_row_errors(table, reference)}
        )
        step()
    for order in orders:
        table, seconds = timed(build_table, channels, grid, order=QuadratureOrder.uniform(order))
        rows.append({"method": "quadrature", "setting": order, "seconds": seconds, **_row_errors(table, reference)})
        step()
    for method, sampling in _SAMPLING.items():
        for count in samples:
            table, seconds = timed(build_table, channels, grid, method="hammersley", samples=count, sampling=sampling)
            rows.append({"method": method, "setting": count, "seconds": seconds, **_row_errors(table, reference)})
            step()
    return {
        "size": size,
        "channels": list(channels.channel_names),
        "channel_sets": channels.name,
        "reference_order": reference_order,
        "reference_seconds": reference_seconds,
        "repeats": repeats,
        "rows": rows,
        "equal_time": _equal_time(rows),
        "total_seconds": time.perf_counter() - study_start,
    }


def _row_errors(table: np.ndarray, reference: np.ndarray) -> dict:
    max_error, rms_error = _errors(table, reference)
    return {"max_abs_error": max_error, "rms_abs_error": rms_error}


def _title(result: dict) -> str:
    size = result["size"]
    return (
        f"{size}×{size} split-sum LUT, 6 channels (4 basis + 2 Schlick): error vs generation time\n"
        f"reference: quadrature order {result['reference_order']} ({result['reference_seconds']:.1f} s)"
    )


def plot_lut_error(result: dict, path=None) -> Path | bytes:
    """Write a log-log PNG of max (solid) and RMS (dashed) absolute error against seconds, per method.

    The file is written to a temporary name in the same folder and renamed into place; with ``path`` None the PNG
    bytes are returned instead. Needs matplotlib (the ``plot`` extra).
    """
    plt = pyplot()
    if path is not None:
        path = Path(path)
        if path.suffix.lower() != ".png":
            raise ParameterError(f"path must end in .png, got {str(path)!r}")
        if not path.parent.is_dir():
            raise ParameterError(f"path's folder must exist, got {str(path.parent)!r}")
    styles = {
        "quadrature-schedule": ("C1", "D", "quadrature, shipped schedule × factor"),
        "quadrature": ("C0", "o", "quadrature, uniform order n"),
        "hammersley-ndf": ("C3", "s", "Hammersley + GGX NDF sampling (engines)"),
        "hammersley-vndf": ("C2", "^", "Hammersley + VNDF sampling"),
    }
    figure, axes = plt.subplots(figsize=(9.0, 6.0), dpi=150)
    for method in METHODS:
        rows = sorted(
            (row for row in result["rows"] if row["method"] == method),
            key=lambda row: row["seconds"],
        )
        if not rows:
            continue
        colour, marker, label = styles[method]
        seconds = np.array([row["seconds"] for row in rows])
        for key, line, kind in (("max_abs_error", "-", "max"), ("rms_abs_error", "--", "RMS")):
            errors = np.array([row[key] for row in rows])
            shown = errors > 0.0  # log axes: an exact zero cannot be drawn
            axes.plot(
                seconds[shown],
                errors[shown],
                line,
                color=colour,
                marker=marker,
                markersize=5,
                fillstyle="full" if kind == "max" else "none",
                label=f"{label}, {kind}",
            )
        for row in rows:
            if row["max_abs_error"] > 0.0:
                text = {"quadrature": f"n={row['setting']}", "quadrature-schedule": f"×{row['setting']:g}"}.get(
                    method, f"{row['setting']} spp"
                )
                axes.annotate(
                    text,
                    (row["seconds"], row["max_abs_error"]),
                    textcoords="offset points",
                    xytext=(4, 4),
                    fontsize=7,
                    color=colour,
                )
    for row in result["rows"]:
        if row["method"] == "quadrature-schedule" and row["setting"] == 1.0:
            axes.plot(
                [row["seconds"]],
                [row["max_abs_error"]],
                "*",
                color="C1",
                markersize=14,
                label="shipped default (fresnel-lut build)",
            )
    for value, text in ((1.0 / 255.0, "8-bit step 1/255"), (2.0**-11, "half-float step near 1 (2⁻¹¹)")):
        axes.axhline(value, color="0.6", linestyle=":", linewidth=1.0)
        axes.annotate(
            text,
            (0.01, value),
            xycoords=("axes fraction", "data"),
            xytext=(0, 2),
            textcoords="offset points",
            fontsize=7,
            color="0.4",
        )
    axes.set_xscale("log")
    axes.set_yscale("log")
    low, high = axes.get_xlim()
    axes.set_xlim(low, high * 1.5)  # room for the labels of the slowest points
    axes.set_xlabel("generation time (s)")
    axes.set_ylabel("absolute error vs reference (max over texels and channels; RMS)")
    axes.set_title(_title(result), fontsize=10)
    axes.grid(True, which="major", alpha=0.4)
    axes.grid(True, which="minor", alpha=0.15)
    axes.legend(fontsize=7, loc="lower left", framealpha=0.9)
    figure.tight_layout()
    return save_figure(figure, path)


def lut_error_table_markdown(result: dict) -> str:
    """The study's rows as a Markdown table, Hammersley rows with their equal-time ratio."""
    size = result["size"]
    ratios = {(entry["method"], entry["setting"]): entry for entry in result["equal_time"]}
    lines = [
        f"{size} × {size} table, {len(result['channels'])} channels ({result['channel_sets']}); reference: quadrature "
        f"order {result['reference_order']} ({result['reference_seconds']:.2f} s); times: best of "
        f"{result['repeats']} run(s); whole study "
        f"{result['total_seconds']:.1f} s.",
        "",
        "| method | setting | time (s) | max abs error | RMS abs error | equal-time ratio (max error / quadrature's) |",
        "|---|---|---:|---:|---:|---|",
    ]
    for row in result["rows"]:
        if row["method"] == "quadrature":
            setting = f"order {row['setting']}"
        elif row["method"] == "quadrature-schedule":
            setting = f"shipped schedule × {row['setting']:g}" + (" (the default)" if row["setting"] == 1.0 else "")
        else:
            setting = f"{row['setting']} spp"
        ratio = ""
        entry = ratios.get((row["method"], row["setting"]))
        if entry is not None:
            ratio = (
                "no quadrature setting this fast"
                if entry["ratio"] is None
                else f"{entry['ratio']:.3g} (quadrature at {entry['seconds']:.2f} s: {entry['quadrature_max_abs_error']:.1e})"
            )
        lines.append(
            f"| {row['method']} | {setting} | {row['seconds']:.3f} | {row['max_abs_error']:.2e} | "
            f"{row['rms_abs_error']:.2e} | {ratio} |"
        )
    return "\n".join(lines) + "\n"


def main(argv: Sequence[str] | None = None) -> None:
    from ..progress import Progress

    parser = argparse.ArgumentParser(description="LUT error against generation time (report study 1).")
    parser.add_argument("--quick", action="store_true", help="32 x 32 table, fewer settings")
    parser.add_argument("--size", type=int, default=128, help="table size (default 128)")
    parser.add_argument("--png", type=Path, default=None, help="write the log-log plot here")
    parser.add_argument("--repeats", type=int, default=1, help="time each table this many times, keep the best")
    arguments = parser.parse_args(argv)
    progress = Progress("lut error study", unit="tables")
    started = time.perf_counter()
    result = lut_error_vs_time(size=arguments.size, quick=arguments.quick, progress=progress, repeats=arguments.repeats)
    progress.close()
    print(lut_error_table_markdown(result))
    if arguments.png is not None:
        print(f"plot: {plot_lut_error(result, arguments.png)}")
    print(f"study run time (with warm-up): {time.perf_counter() - started:.1f} s")


if __name__ == "__main__":
    main()
