"""Absolute frame times of the shader passes on whatever GPU the EGL context finds (the one measurement ACO's static
estimate and llvmpipe cannot give).

The passes are the shader-cost benchmark's (:data:`benchmarks.shader_cost.ALL_VARIANTS`: Schlick, the basis with
uniform coefficients, the per-pixel solves and tables, the atlas) and the area-light benchmark's
(:func:`benchmarks.area_light_set.cost_passes`, with issue 41's baseline: the split sum as the include of
:data:`benchmarks.area_light_set.BASELINE_REVISION` had it, and the shipped form's diagnostics), each a full-screen
pass timed by :func:`benchmarks.shader_cost.frame_times` (variants alternated round by round, the median per frame).
Each table gives
milliseconds per frame and the ratio to its own baseline (Schlick's pass; issue 41's baseline pass), each column from
one run; the shader-cost passes with four uploads (32-bit textures and noise maps, as that benchmark's; 8-bit maps,
noise and smooth, with 32-bit tables, as an engine ships them; half floats, a diagnostic).

The baseline include comes from git (:func:`benchmarks.area_light_set.baseline_include`) or, on a machine with the
working tree but not its history, from ``--baseline-include FILE`` (the same text, written beforehand with
``git show ce2dc28:luts/fresnel_basis.glsl``).

Run: ``.venv/bin/python -m benchmarks.gpu_timings [--width W --height H --frames N --rounds R]
[--baseline-include FILE] [--out FILE]`` (the report, on a GPU: ``--out report/gpu_timings.md``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from benchmarks.area_light_set import BASELINE, baseline_include, cost_passes
from benchmarks.output import machine, publish
from benchmarks.shader_cost import frame_times


def gl_version() -> str:
    """The EGL context's ``GL_VERSION`` (the driver's version, on NVIDIA's)."""
    import moderngl

    context = moderngl.create_standalone_context(backend="egl")
    try:
        return context.info["GL_VERSION"]
    finally:
        context.release()


def timings(width: int, height: int, frames: int, rounds: int, baseline: str) -> list[str]:
    """Markdown lines: the two tables (shader-cost passes against Schlick's, with 32-bit textures, with 8-bit material
    maps, noise and smooth, and with half floats; area-light passes against issue 41's baseline), ``baseline`` the
    baseline include's text."""
    shading, renderer = frame_times(width, height, frames, rounds)
    painted, _ = frame_times(width, height, frames, rounds, maps="f1")
    smooth, _ = frame_times(width, height, frames, rounds, maps="f1", smooth=True)
    half, _ = frame_times(width, height, frames, rounds, texel="f2")
    columns = (shading, painted, smooth, half)
    area, _ = frame_times(width, height, frames, rounds, *cost_passes(baseline))
    lines = [
        f"Renderer: {renderer}, OpenGL {gl_version()}, on {machine()}; {width} x {height}, the median of {rounds} "
        f"rounds of {frames} frames, variants alternated; milliseconds per frame and the ratio to the table's first "
        "row, each table from one run. The shader-cost passes four times: every table and material map in 32-bit "
        "floats, each map texel an independent random value (as benchmarks.shader_cost uploads them: neighbouring "
        "texels are different materials, so the per-pixel tables are read incoherently); the material maps in 8 bits "
        "(as an engine ships painted maps), the tables in 32-bit floats (as the include asks); the same with smooth "
        "maps (random values on a 9 × 9 grid interpolated linearly: regions that blend, as painted maps mostly are); "
        "and everything in 16-bit floats with the noise maps (which the tables' accuracy does not allow: README), to "
        "see what filtering 32-bit texels costs. Command: `python -m benchmarks.gpu_timings`.",
        "",
        "| shader-cost pass (benchmarks.shader_cost) | 32-bit: ms | × Schlick | 8-bit maps: ms | × Schlick "
        "| 8-bit smooth maps: ms | × Schlick | half floats: ms | × Schlick |",
        "|---|---|---|---|---|---|---|---|---|",
        *(
            f"| {name} | "
            + " | ".join(f"{1e3 * times[name]:.3f} | {times[name] / times['schlick']:.2f}" for times in columns)
            + " |"
            for name in shading
        ),
        "",
        "| area-light pass (benchmarks.area_light_set) | ms per frame | × issue 41's baseline |",
        "|---|---|---|",
        *(f"| {name} | {1e3 * time:.3f} | {time / area[BASELINE]:.2f} |" for name, time in area.items()),
    ]
    return lines


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--width", type=int, default=3840)
    parser.add_argument("--height", type=int, default=2160)
    parser.add_argument("--frames", type=int, default=16, help="frames per variant per round (default 16)")
    parser.add_argument("--rounds", type=int, default=9, help="rounds alternating the variants (default 9)")
    parser.add_argument(
        "--baseline-include", type=Path, default=None, help="issue 41's baseline include (default: from git)"
    )
    parser.add_argument("--out", default=None, help="Markdown file (default: print)")
    arguments = parser.parse_args(argv)
    for name in ("width", "height", "frames", "rounds"):
        if getattr(arguments, name) < 1:
            parser.error(f"--{name} must be at least 1")
    if arguments.baseline_include is not None:
        try:
            baseline = arguments.baseline_include.read_text(encoding="utf-8")
        except OSError as error:
            parser.error(f"--baseline-include: {error}")
    else:
        try:
            baseline = baseline_include()
        except RuntimeError as error:
            parser.error(f"{error}; pass --baseline-include FILE")
    lines = timings(arguments.width, arguments.height, arguments.frames, arguments.rounds, baseline)
    publish("\n".join(["# Frame times on a GPU", "", *lines]) + "\n", arguments.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
