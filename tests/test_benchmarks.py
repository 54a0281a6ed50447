"""Every ``python -m benchmarks.*`` entry runs (issue 22: README's stability table could not be regenerated because
``benchmarks.stability_table`` imported a test module by an old name). Each is run in a fresh process as README says,
with small settings where it has them; ``benchmarks.fuzz`` runs in tests/test_fuzz.py and ``benchmarks.commands``
(minutes: it times every command) is started with ``--help`` only."""

import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests.conftest import gpu_missing

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
        "area_light_set",
        "area_lights",
        "coefficient_table",
        "commands",
        "fuzz",
        "gpu_compiler",
        "gpu_timings",
        "linear_models",
        "lut_edges",
        "materialx_library",
        "quadrature_vs_montecarlo",
        "shader_cost",
        "stability_table",
        "three_package",
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


def test_linear_models_runs_small():
    """The path study at 6² texels, 200 conductors and 300 random points: the exact table holds the F82-tint family
    to float32 at its texels (the basis projection does not: 0.13 at worst), the basis holds physical conductors
    better than the F82 model, and Babylon.js's table, fetched with npm and decoded as its shaders do, holds the
    family to its 8 bits at its texel centres (1.8e-2 measured; a wrong orientation, scale or decode misses by
    more than 0.2) and is further off than this project's exact table between texels."""
    completed = _run("benchmarks.linear_models", "--grid", "6", "--conductors", "200", "--points", "300")
    assert completed.returncode == 0, completed.stderr[-2000:]

    def cells(name):
        row = next(line for line in completed.stdout.splitlines() if line.startswith(f"| {name}"))
        return [float(cell) for cell in row.strip("|").split("|")[1:]]

    assert cells("exact table")[0] <= 1e-6 < 1e-2 <= cells("basis projection, Fbar")[0]
    assert cells("basis, four-point")[0] < cells("F82 (Hoffman 2019)")[0]
    babylon_storage = next(line for line in completed.stdout.splitlines() if "its storage alone" in line)
    assert 1e-3 < float(babylon_storage.strip("|").split("|")[1]) < 0.03, babylon_storage
    assert cells("this project's exact table")[0] < cells("Babylon.js")[0]


def test_coefficient_table_runs_small():
    """The coefficient-table study at 300 random points: on the Gulbrandsen grid the table is never worse than the
    four-point solve and better at the median; the shipped and the four-point tables hold their models within 1e-4."""
    completed = _run("benchmarks.coefficient_table", "--points", "300")
    assert completed.returncode == 0, completed.stderr[-2000:]
    row = next(line for line in completed.stdout.splitlines() if line.startswith("| Gulbrandsen grid"))
    median, worst = (float(value) for value in row.strip("|").split("|")[6].split("/"))
    assert median < 0.8 and worst <= 1.0 and row.strip("|").split("|")[7].strip() == "0", row
    for name in ("| weighted (shipped) |", "| four-point |"):
        table_row = next(line for line in completed.stdout.splitlines() if line.startswith(name))
        assert float(table_row.strip("|").split("|")[1]) <= 1e-4, table_row


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
def test_gpu_timings_run_small(tmp_path):
    """The frame-time benchmark on llvmpipe at 64 × 36, one round, with issue 41's baseline include from a file (as on
    a machine without the history): every shader-cost pass and every area-light pass draws, each ratio to its own
    baseline; a file that is not there is a usage error, not a traceback."""
    from benchmarks.area_light_set import baseline_include, cost_passes
    from benchmarks.shader_cost import ALL_VARIANTS

    include = tmp_path / "baseline.glsl"
    include.write_text(baseline_include(), encoding="utf-8")
    out = tmp_path / "timings.md"
    completed = _run(
        "benchmarks.gpu_timings",
        *("--width", "64", "--height", "36", "--frames", "1", "--rounds", "1"),
        *("--baseline-include", str(include), "--out", str(out)),
    )
    assert completed.returncode == 0, completed.stderr[-2000:]
    text = out.read_text(encoding="utf-8")
    rows = [line for line in text.splitlines() if line.startswith("| ") and "---" not in line]
    area_passes = len(cost_passes("// the baseline")[0])  # the baseline, the forms and the diagnostics: 7
    assert area_passes == 7 and len(rows) == 2 + len(ALL_VARIANTS) + area_passes, rows  # and two headers
    assert "| schlick | " in text and text.count(" | 1.00 |") >= 2, text
    assert "| punctual blend | " in text
    missing = _run("benchmarks.gpu_timings", "--baseline-include", str(tmp_path / "absent.glsl"))
    assert missing.returncode == 2 and "absent.glsl" in missing.stderr and "Traceback" not in missing.stderr


def test_smooth_map_interpolates_its_grid():
    """The smooth material map holds its 9 × 9 random values at the grid's points (every 255/8 texels) and is linear
    between them along each axis (bilinear inside a cell: its second differences vanish within a cell's rows)."""
    from benchmarks.shader_cost import smooth_map

    grid = np.random.default_rng(4).uniform(0.05, 0.95, (9, 9, 4))
    values = smooth_map(np.random.default_rng(4), size=257, cells=8)
    assert values.shape == (257, 257, 4)
    np.testing.assert_allclose(values[::32, ::32], grid, atol=1e-12)
    inside = values[1:31, 33:63]  # within one cell: linear along each axis
    np.testing.assert_allclose(np.diff(inside, 2, axis=0), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.diff(inside, 2, axis=1), 0.0, atol=1e-12)


def test_shader_cost_runs_small():
    """The shader-cost benchmark on llvmpipe at 64 × 36, one round: every variant compiles and draws."""
    completed = _run("benchmarks.shader_cost", "--width", "64", "--height", "36", "--frames", "1", "--rounds", "1")
    assert completed.returncode == 0, completed.stderr[-2000:]
    # five parametrisations (two through the per-pixel tables), then the tables' pass alone and in one atlas
    assert completed.stdout.count("| basis per pixel") == 7
    assert completed.stdout.count("tables in one atlas (one sampler)") == 1
    assert completed.stdout.count("direct light from a 512-texel table") == 1
    assert completed.stdout.count("coefficients from three textures (solved offline)") == 1
    assert "GPU compiler: ACO (Mesa's AMD compiler) on RADV NAVI21" in completed.stdout


def _gpu_compiler_tools():
    """glslangValidator, RADV and the Python Vulkan binding, or skip (fail under CI=true) naming the missing one."""
    import importlib.util
    import shutil

    if shutil.which("glslangValidator") is None:
        gpu_missing("glslangValidator (Debian glslang-tools)")
    from benchmarks.gpu_compiler import radv_manifest

    try:
        radv_manifest()
    except RuntimeError as missing:
        gpu_missing(str(missing))
    if importlib.util.find_spec("vulkan") is None:
        gpu_missing("the Python Vulkan binding (the 'gpu' extra)")


def test_the_gpu_compiler_counts_the_arithmetic_it_is_given():
    """ACO's estimates follow the shader's arithmetic: sixteen dependent multiply-adds on a texel add at least sixteen
    instructions and raise the inverse throughput; the same shader twice gives the same statistics (a static model:
    no noise)."""
    from benchmarks.gpu_compiler import STATISTICS, compiler_estimates

    _gpu_compiler_tools()
    head = "#version 450\nuniform sampler2D map;\nuniform float k;\nout vec4 colour;\n"
    plain = head + "void main() { vec4 x = texture(map, gl_FragCoord.xy); colour = x; }\n"
    chain = "".join("    x = x * x * k + 0.5;\n" for _ in range(4))  # 4 x 4 components: 16 multiply-adds
    busy = head + "void main() {\n    vec4 x = texture(map, gl_FragCoord.xy);\n" + chain + "    colour = x;\n}\n"
    estimates, compiler = compiler_estimates({"plain": plain, "busy": busy, "plain again": plain})
    assert compiler.startswith("RADV NAVI21, Mesa ")
    assert set(estimates["plain"]) == set(STATISTICS)
    assert estimates["busy"]["Instructions"] >= estimates["plain"]["Instructions"] + 16
    assert estimates["busy"]["Inverse Throughput"] > estimates["plain"]["Inverse Throughput"]
    assert estimates["plain again"] == estimates["plain"]


def test_the_gpu_compiler_names_a_shader_that_does_not_compile(tmp_path):
    _gpu_compiler_tools()
    shader = tmp_path / "broken.frag"
    shader.write_text("#version 450\nout vec4 colour;\nvoid main() { colour = vec4(undeclared); }\n", encoding="utf-8")
    completed = _run("benchmarks.gpu_compiler", str(shader))
    assert completed.returncode == 1 and "'undeclared' : undeclared identifier" in completed.stderr, completed.stderr


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


@pytest.mark.slow
def test_three_package_runs_small():
    """The three.js comparison with one measured metal, gold and Figure 2 (three.js from npm in headless Chromium):
    the package's error below stock three.js's for each."""
    completed = _run("benchmarks.three_package", "--materials", "1", timeout=600)
    if completed.returncode != 0 and "is missing" in completed.stderr:
        gpu_missing(completed.stderr.strip().splitlines()[-1])
    assert completed.returncode == 0, completed.stderr[-2000:]
    rows = [line for line in completed.stdout.splitlines() if line.startswith("| ") and "---" not in line][1:]
    assert len(rows) == 4, completed.stdout
    for row in rows:
        assert float(row.split("|")[6]) > 5, row  # stock max over the package's max


@pytest.mark.slow
def test_materialx_library_runs_small():
    """MaterialX's documents with and without the basis branch, one material each, 64 FIS samples."""
    completed = _run("benchmarks.materialx_library", "--materials", "1", "--samples", "64", timeout=600)
    if completed.returncode != 0 and "is missing" in completed.stderr:
        gpu_missing(completed.stderr.strip().splitlines()[-1])
    assert completed.returncode == 0, completed.stderr[-2000:]
    rows = {line.split("|")[1].strip(): line.split("|")[2:6] for line in completed.stdout.splitlines() if "| `" in line}
    assert set(rows) == {"`conductor_bsdf`", "`standard_surface`", "`open_pbr_surface`"}
    for cells in rows.values():
        stock, branch = (float(cell.split("/")[0]) for cell in cells[:2])
        assert branch < stock, cells


@pytest.mark.slow
def test_the_lobe_study_takes_the_shipped_table_toward_the_lobes_punctual_limit():
    """The lobe study (F = 1) on the shipped LTC table with a coarse reference (1e-3): the punctual-limit, two-lobe
    and radiance-fit rows are there and, as in the report, the punctual limit (unbounded, lowering only, and as
    shipped) is lower at the median than the table alone, by a fifth at least, the two lobes lower too (measured:
    3.13 %, 3.58 % and 2.36 % for the limit, 4.65 % for the two lobes, against 4.73 %), and what ships is lower at the
    p90 than the lowering-only form, the bound of 2 for any light and the weight √I that shipped before (17.6 % against
    35.8 %, 28.7 % and 23.9 %), lower at the median and the p90 than the weight I^p without the light's spread
    (2.36 % / 17.6 % against 3.13 % / 19.2 %), and lower at the median than without the LTC's share above the horizon
    at no higher p90 (2.48 % / 17.6 %); the ratio over 8 × 8 points of the light lower than over the one at L*, by a
    fifth at the p90 (2.02 % / 13.3 %; a quarter before the spread term, all at the report's tolerance)."""
    from basis.storage import shipped_path
    from benchmarks.area_light_set import (
        LOBE_LIMIT,
        LOBE_LIMIT_HALF,
        LOBE_LIMIT_LOWER,
        LOBE_LIMIT_NO_SPREAD,
        LOBE_LIMIT_NO_UPPER,
        LOBE_LIMIT_PREVIOUS,
        LOBE_LIMIT_ROWS,
        LOBE_LIMIT_SHIPPED,
        RADIANCE_FIT,
        RADIANCE_FIT_LIMIT,
        SPREAD_POINTS,
        TWO_LOBES,
        lobe_study,
        spread_ratio_row,
    )
    from handoff.exr import read_lut
    from handoff.shipped import LTC_LUT

    lines = lobe_study(1e-3, {"shipped": read_lut(shipped_path(LTC_LUT))[0]})
    rows = [line.split("|") for line in lines if line.count("%") > 3]
    assert len(rows) == 28, lines  # fourteen by placement, then fourteen by width
    medians = {row[1].strip(): float(row[2].split("%")[0]) for row in rows[:14]}
    p90 = {row[1].strip(): float(row[2].split("/")[1].split("%")[0]) for row in rows[:14]}
    spread = {spread_ratio_row(points) for points in SPREAD_POINTS}
    assert set(medians) == {"shipped", TWO_LOBES, RADIANCE_FIT, RADIANCE_FIT_LIMIT, *LOBE_LIMIT_ROWS} | spread, lines
    # the ratio over 8 × 8 points of the light: the frontier more evaluations of the lobe reach, below the one point
    # (measured 2.02 % / 13.3 % against 2.38 % / 15.4 %)
    assert (
        medians[spread_ratio_row(8)] < medians[LOBE_LIMIT_SHIPPED]
        and p90[spread_ratio_row(8)] < 0.9 * p90[LOBE_LIMIT_SHIPPED]
    ), (medians, p90)
    assert p90[LOBE_LIMIT_SHIPPED] < min(p90[LOBE_LIMIT_PREVIOUS], p90[LOBE_LIMIT_LOWER], p90[LOBE_LIMIT_HALF]), p90
    # the light's spread: lower at the median and the p90 than the weight I^p alone
    assert medians[LOBE_LIMIT_SHIPPED] < medians[LOBE_LIMIT_NO_SPREAD], medians
    assert p90[LOBE_LIMIT_SHIPPED] < p90[LOBE_LIMIT_NO_SPREAD], p90
    # the LTC's share above the horizon: lower at the median, no higher at the p90
    assert medians[LOBE_LIMIT_SHIPPED] < medians[LOBE_LIMIT_NO_UPPER], medians
    assert p90[LOBE_LIMIT_SHIPPED] <= p90[LOBE_LIMIT_NO_UPPER], p90
    for name in (LOBE_LIMIT, LOBE_LIMIT_LOWER, LOBE_LIMIT_SHIPPED):
        assert medians[name] < 0.8 * medians["shipped"], (name, medians)
    assert medians[TWO_LOBES] < medians["shipped"], medians


def test_the_ratio_bound_is_the_criterions_choice():
    """The shipped weight and bound of the lobe's ratio, (p, R₀, K, S), are the ones the benchmark's criterion picks on
    the training lights (the report's reference tolerance), and the report's tables say so."""
    from benchmarks.area_light_set import (
        REFERENCE_TOLERANCE,
        SHIPPED_BOUND,
        chosen_bound,
        ratio_bound,
        ratio_bound_errors,
    )

    assert chosen_bound(ratio_bound_errors(REFERENCE_TOLERANCE)) == SHIPPED_BOUND
    lines = ratio_bound(REFERENCE_TOLERANCE)
    assert not any("now picks" in line for line in lines), lines
    assert sum("(chosen) (shipped)" in line for line in lines) == 2, lines  # the row of p, the cell of the bound


@pytest.mark.slow
def test_the_spread_is_the_criterions_choice():
    """The shipped power k, share c and ratio ρ of the lobe's spread term are the ones the benchmark's criterion picks
    on the spread's training lights (the report's reference tolerance), where the term lowers the p90 below that of
    the term shipped before (only where the ratio exceeds 1) and that without it (measured 8.99 % against 9.53 % and
    14.1 %), at a p90 over the hemisphere's training lights no higher than the one shipped before (27.0 %), and the
    report's table says so."""
    from benchmarks.area_light_set import (
        REFERENCE_TOLERANCE,
        SPREAD_BEFORE,
        chosen_spread,
        spread_errors,
        spread_study,
    )
    from preintegrate.ltc import LOBE_SPREAD_POWER, LOBE_SPREAD_RATIO, LOBE_SPREAD_SHARE

    errors = spread_errors(REFERENCE_TOLERANCE)
    shipped = (LOBE_SPREAD_POWER, LOBE_SPREAD_SHARE, LOBE_SPREAD_RATIO)
    assert chosen_spread(errors) == shipped

    def p90(key, lights):
        return np.percentile(errors[key][lights], 90)

    assert p90(shipped, 0) < p90(SPREAD_BEFORE, 0) < p90(None, 0) and p90(shipped, 1) <= p90(SPREAD_BEFORE, 1)
    lines = spread_study(REFERENCE_TOLERANCE, errors)
    assert not any("now picks" in line for line in lines) and sum("(chosen) (shipped)" in line for line in lines) == 1


@pytest.mark.slow
def test_the_blend_and_the_upper_share_are_the_criterions_choice():
    """The shipped Fresnel blend's weight a I + (1 − a) I^n, the power m of the LTC's share above the horizon, k of the
    lobe whose Fresnel average stands for the light's (r' = min(r, k √Ω_L)) and the spread c of the light's directions
    (0: V·H* of L*'s own half vector, as the shaders take it) are the (m, a, n, c, k) the benchmark's criterion picks on
    its training lights (the report's reference tolerance): the worse kind's median / 3 % + p90 / 20 % lowest, where
    the median falls below 0.7 × that of what shipped before the share, w = I², no share and F(V·H*) (measured 2.50 %
    against 3.87 %), at a p90 no higher (18.6 % against 21.4 %), below the best without the share and below the same
    (m, a, n, c) with F(V·H*) (k = 0: 2.88 %), and below it on each set of lights apart; the report's tables say so."""
    from benchmarks.area_light_set import (
        BLEND_BEFORE,
        BLEND_LIGHT_SETS,
        REFERENCE_TOLERANCE,
        SHIPPED_BLEND,
        _to_targets,
        _worse,
        blend_errors,
        blend_study,
        blend_values,
        chosen_blend,
    )

    values = blend_values(REFERENCE_TOLERANCE)
    errors = blend_errors(values)
    shipped = SHIPPED_BLEND
    assert chosen_blend(errors) == shipped
    assert _worse(errors[shipped], 50) < 0.7 * _worse(errors[BLEND_BEFORE], 50)
    assert _worse(errors[shipped], 90) <= _worse(errors[BLEND_BEFORE], 90)
    without_share = chosen_blend(errors, [key for key in errors if key[0] is None])
    assert _to_targets(errors[shipped]) < _to_targets(errors[without_share]), without_share
    point = (*shipped[:4], 0.0)
    assert shipped[3] == 0.0 and shipped[4] > 0.0
    assert _worse(errors[shipped], 50) < _worse(errors[point], 50) and _to_targets(errors[shipped]) < _to_targets(
        errors[point]
    )
    # each set of lights apart: the two sets hold every value, and F̃ lowers the dielectrics' median on each
    by_set = [blend_errors(values, index) for index in range(len(BLEND_LIGHT_SETS))]
    assert sum(np.sum(values["lights"] == index) for index in range(len(BLEND_LIGHT_SETS))) == len(values["exact"])
    for each in by_set:
        assert each[shipped]["dielectric"][0] < each[point]["dielectric"][0], (each[shipped], each[point])
    lines = blend_study(REFERENCE_TOLERANCE, values)
    assert not any("now picks" in line for line in lines), lines
    # the row of m, the cell of (a, n) and the cell of (k, c)
    assert sum("(chosen) (shipped)" in line for line in lines) == 3, lines
    assert sum(line.startswith(f"| {name} |") for name in BLEND_LIGHT_SETS for line in lines) == 2, lines


def test_the_cost_diagnostics_change_one_call_of_the_shipped_include():
    """Each diagnostic pass of the area-light cost differs from the shipped include in the one line that makes it."""
    from benchmarks.area_light_set import ATAN_EDGES, BASELINE, POLYNOMIAL_PUNCTUAL, WITHOUT_LOBE_LIMIT, cost_passes
    from handoff.shaders import shader_includes

    variants, includes = cost_passes("// the baseline")
    shipped = dict(shader_includes())["fresnel_basis.glsl"].splitlines()
    assert includes[BASELINE] == "// the baseline" and set(includes) <= set(variants)
    for name, now in (
        (POLYNOMIAL_PUNCTUAL, "fresnelBasisDirect(VdotH"),
        (WITHOUT_LOBE_LIMIT, "corners, r, 0.0)"),
        (ATAN_EDGES, "atan(length(c), d)"),
    ):
        changed = [b for a, b in zip(shipped, includes[name].splitlines()) if a != b]
        assert len(changed) == 1 and now in changed[0], (name, changed)


@pytest.mark.parametrize(
    ("option", "message"),
    [
        *((f"--tolerance={value}", "--tolerance must be in (0, 1)") for value in ("0", "-1e-6", "nan", "1")),
        *((f"--roughness={value}", "--roughness must be in (0, 1]") for value in ("0", "-0.5", "nan", "1.5")),
        *((f"--widths={value}", "--widths must be in (0, 100]") for value in ("0", "-1", "nan", "inf", "101")),
    ],
)
def test_area_light_set_refuses_a_tolerance_roughness_or_width_out_of_range(option, message, capsys):
    from benchmarks.area_light_set import main

    with pytest.raises(SystemExit) as exited:
        main([option, "--three", "none", "--no-cost", "--no-fits"])
    assert exited.value.code == 2 and message in capsys.readouterr().err


def test_area_light_set_reports_a_class_without_values():
    """At r = 0.85 alone no small light gives a dielectric value above the floor (1e-3): the report says "–" for that
    class and runs to its end rather than failing on an empty percentile."""
    completed = _run(
        "benchmarks.area_light_set",
        *("--tolerance", "1e-3", "--three", "none", "--no-cost", "--no-fits", "--roughness", "0.85"),
        timeout=600,
    )
    assert completed.returncode == 0, completed.stderr[-2000:]
    small = [line for line in completed.stdout.splitlines() if line.startswith("| small (≤ 0.2) | punctual blend |")]
    assert len(small) == 1 and small[0].rstrip().endswith("| – |"), completed.stdout
    assert "| width 0.02 | –; – |" in completed.stdout


def test_area_light_set_runs_small(tmp_path):
    """The area-light set with a coarse reference, without peers or cost, at two roughnesses (one glossy) and three
    widths given out of order: every approach, the factorisation and the figure's values by view and by each width
    (sorted), the classes by width named by the widths in them, the roughnesses, widths and the command in the report,
    and with ``--out`` the report beside its figure (a PNG it links to); the forms of F̃ not shipped, alone and in the
    total."""
    from benchmarks.area_light_set import FACTOR_VARIANTS

    out = tmp_path / "set.md"
    completed = _run(
        "benchmarks.area_light_set",
        *("--tolerance", "1e-3", "--three", "none", "--no-cost", "--no-fits", "--roughness", "0.5", "0.15"),
        *("--widths", "10", "0.02", "0.5", "--out", str(out)),
        timeout=600,
    )
    assert completed.returncode == 0, completed.stderr[-2000:]
    lines = completed.stdout.splitlines()
    for row in (
        *("| split sum, this project |", "| punctual blend, this project |", "| F at the light's mean V·H |"),
        *("| N·V 0.08 |", "| N·V 0.95 |", "| width 0.02 |", "| width 0.5 |", "| width 10 |"),  # the figure's values
        *("| small (≤ 0.2) | punctual blend |", "| medium (0.5) | punctual blend |", "| large (10) | split sum |"),
    ):
        assert sum(line.startswith(row) for line in lines) == 1, (row, completed.stdout)
    for form in FACTOR_VARIANTS:  # the forms not shipped, alone and in the total
        assert sum(line.startswith(f"| {form} |") for line in lines) == 2, (form, completed.stdout)
    assert "| form | conductors: total | dielectrics: total |" in lines
    widths = [line.split(" |")[0] for line in lines if re.match(r"\| width \d", line)]
    assert widths == ["| width 0.02", "| width 0.5", "| width 10"], widths
    assert "roughness [0.5, 0.15]" in completed.stdout and "--roughness 0.5 0.15" in completed.stdout
    assert "width [0.02, 0.5, 10.0]" in completed.stdout and "--widths 10 0.02 0.5" in completed.stdout
    assert out.read_text(encoding="utf-8") == completed.stdout[:-1]  # print's own newline
    assert "](set.png)" in completed.stdout
    assert (tmp_path / "set.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_the_grazing_profile_names_the_fit_each_texel_took():
    """_texel_fits names, for the four texels a lookup reads, the fit whose float32 value each holds ("?" for none),
    the nearer row first; grazing_profile gives one row per roughness with those names and each table's statistics,
    the clamped cosine (M = I, no fit) far off the lobe where the shipped table is not."""
    from basis.storage import shipped_path
    from benchmarks.area_light_set import PROFILE_ROUGHNESS, REFERENCE_TOLERANCE, VIEWS, _texel_fits, grazing_profile
    from handoff.exr import read_lut
    from handoff.shipped import LTC_LUT
    from preintegrate.ltc import ltc_grid

    grid = ltc_grid(64)
    mean, free = np.ones((64, 64, 4)), np.full((64, 64, 4), 2.0)
    mu_o, roughness = VIEWS[-1], 0.4
    row = float(grid.view_position(mu_o, np.sqrt(1.0 - mu_o * mu_o)))
    column = float(grid.roughness_position(roughness))
    near, far = int(np.floor(row)), int(np.floor(row)) + 1
    if row - near > far - row:
        near, far = far, near
    low = int(np.floor(column))
    table = mean.copy()
    table[near, low + 1] = free[near, low + 1]
    table[far, low] = 7.0
    assert _texel_fits(table, {"mean": mean, "free": free}, mu_o, roughness) == "mean/free, ?/mean"
    shipped = read_lut(shipped_path(LTC_LUT))[0]
    cosine = np.broadcast_to(np.array([1.0, 0.0, 0.0, 1.0], dtype=np.float32), shipped.shape)
    lines = grazing_profile(1e-3, {"shipped table": shipped, "cosine": cosine}, {"shipped": shipped})
    assert REFERENCE_TOLERANCE < 1e-3 and len(lines) == 2 + len(PROFILE_ROUGHNESS), lines
    assert lines[0].split("|")[1:-1] == [
        " r ",
        " texels read ",
        " shipped table, toward the limit ",
        " shipped table ",
        " cosine ",
    ]
    for line, r in zip(lines[2:], PROFILE_ROUGHNESS):
        cells = [cell.strip() for cell in line.split("|")[1:-1]]
        assert cells[0] == f"{r:g}" and cells[1] == "shipped/shipped, shipped/shipped", cells
        medians = [float(cell.split(" %")[0]) for cell in cells[2:]]
        assert medians[2] > 2.0 * max(medians[0], 5.0), cells


def test_the_radiance_fits_lights_lie_where_the_lobe_reflects():
    """lobe_lights: seeded, in the widths asked for, centred where the lobe reflects: for a sharp lobe (α = 0.05) at
    N·V = 0.5 at least 85 % within 17° of the mirror direction and the median within 8° (tan² θh = α² u / (1 − u):
    u = 0.9 gives θh = 8.5°, so the light 17° off), and for
    α = 1 spread over the hemisphere; bad input refused."""
    from basis.validation import ParameterError
    from benchmarks.area_light_set import lobe_lights

    lights = lobe_lights(0.5, 0.05, 64, (0.1, 2.0))
    np.testing.assert_array_equal(lights, lobe_lights(0.5, 0.05, 64, (0.1, 2.0)))
    assert lights.shape == (64, 4, 3)
    widths = np.linalg.norm(lights[:, 1] - lights[:, 0], axis=-1)
    assert np.all((widths >= 0.1 - 1e-12) & (widths <= 2.0 + 1e-12)), widths
    centres = lights.mean(axis=1)
    directions = centres / np.linalg.norm(centres, axis=-1, keepdims=True)
    mirror = np.array([-np.sqrt(0.75), 0.0, 0.5])
    angles = np.degrees(np.arccos(np.clip(directions @ mirror, -1.0, 1.0)))
    assert np.mean(angles < 17.0) >= 0.85 and np.median(angles) < 8.0, np.sort(angles)
    rough = lobe_lights(0.5, 1.0, 64).mean(axis=1)
    rough /= np.linalg.norm(rough, axis=-1, keepdims=True)
    assert np.median(np.degrees(np.arccos(rough @ mirror))) > 30.0
    assert np.all(rough[:, 2] >= -0.15 - 1e-12)
    for bad in ((0.0, 0.3), (0.5, 0.0), (0.5, 1.5)):
        with pytest.raises(ParameterError):
            lobe_lights(*bad, 4)


def test_area_light_cost_baseline_is_issue_41s_include():
    """The cost section's baseline is the include of the commit issue 41's budget refers to, read from the history:
    the split sum with the LTC clipped in the cosine's space only (no shading-horizon clip)."""
    import subprocess

    from benchmarks.area_light_set import ROOT, baseline_include

    shallow = subprocess.run(["git", "rev-parse", "--is-shallow-repository"], cwd=ROOT, capture_output=True, text=True)
    if shallow.returncode != 0 or shallow.stdout.strip() == "true":
        pytest.skip("not a full git checkout: the baseline commit is not in its history")
    include = baseline_include()
    assert "float fresnelLtcRect(" in include and "fresnelLtcClippedVector" not in include


def test_lobe_and_factor_takes_the_total_apart_and_finds_each_lights_best_weight():
    """lobe_and_factor on values made from a known weight per light and an exact lobe (I E = the lobe): the lobe row is
    0, the include's total is its factor's error, and the best weight of each light (one of ORACLE_WEIGHTS, the same
    for every material under it) takes both to 0; an I of 0 is left out of the factor rows only."""
    from benchmarks.area_light_set import ORACLE_WEIGHTS, lobe_and_factor

    parts = []
    for light, (integral, best) in enumerate(((0.3, ORACLE_WEIGHTS[40]), (0.8, ORACLE_WEIGHTS[150]))):
        albedo = 0.9
        for kind, split, punctual in (("conductor", 0.8, 0.75), ("dielectric", 0.05, 0.2), ("dielectric", 0.03, 0.1)):
            exact = integral * (best * split + (1.0 - best) * punctual)
            parts.append((("view", light), kind, exact, integral * albedo, integral, albedo, split, punctual))
    parts.append((("view", 2), "dielectric", 0.01, 0.01, 0.0, 0.9, 0.05, 0.2))
    lines = lobe_and_factor(parts)
    assert len(lines) == 7, lines
    cells = [[cell.strip() for cell in line.split("|")[2:-1]] for line in lines[2:]]
    total, lobe, factor, best_factor, best_total = cells
    zero = "0.00 % / 0.0 % / 0 %"
    assert lobe == [zero, "0.00 % / 60.0 % / 100 %"], lobe  # four exact dielectric values and the one with I = 0
    assert best_factor == [zero, zero] and best_total[0] == zero, cells
    assert best_total[1] == lobe[1] and total[1].endswith("/ 100 %"), cells
    # the shipped weight at I = 0.3 and 0.8 is not the one the values were made with: its factor misses there
    assert all(float(cell.split(" %")[0]) > 1.0 for cell in (factor[1], total[1])), cells
    # by light: the first three rows per group, in the order the groups first come; the I = 0 light's only
    # value is out of its factor cells and all of its lobe's (I E = 0 against a lobe of 0.01)
    grouped = lobe_and_factor(parts, lambda key: f"light {key[1]}", "light")
    assert grouped[: len(lines)] == lines and grouped[len(lines) : len(lines) + 2] == [
        "",
        "The first three rows by light:",
    ]
    head, _, *rows = grouped[len(lines) + 3 :]
    assert head.split("|")[1].strip() == "light" and [row.split("|")[1].strip() for row in rows] == [
        f"light {number}" for number in range(3)
    ], grouped
    by_light = [[cell.strip() for cell in row.split("|")[2:-1]] for row in rows]
    assert all(row[1] == zero and row[4] == zero for row in by_light[:2]), by_light  # both kinds' lobe, exact there
    assert by_light[2][:3] == ["–"] * 3 and by_light[2][3:] == [
        "100.00 % / 100.0 % / 100 %",
        "100.00 % / 100.0 % / 100 %",
        "–",
    ]
    assert by_light[0][0] == by_light[0][2] and by_light[1][3] == by_light[1][5], (
        by_light
    )  # total = factor where I E is
