"""Which path for which material (issue 39): the linear models' exact table against the basis, and the basis against
the linear models, side by side.

1. **The F82-tint family** (Adobe Standard Material, OpenPBR ``specular_color``, MaterialX ``color82``; Hoffman 2023
   eq. 3), one channel: F0 × tint on a grid. For each material, the error of its F̄ over a (μo, r) grid against
   the model's own split sum (float64 integrals of its three fixed functions: the model is linear in them) at texels
   of the shipped grid, of (a) the exact path, the shipped float32 Schlick table's R, G, A
   (``fresnelLinearSplitSum``); (b) the basis projection the include solves per pixel
   (``fresnelCoefficientsF82Tint``, float64 integrals of the basis); (c) Schlick with F0 alone (the tint dropped).
   And the curve error max over θ of (b) and (c).
2. **Physical conductors** (η 0.1–4, κ 1–8, seeded): the curve error max over θ of the basis' four-point
   coefficients and of the best two-parameter linear model engines have for them, Hoffman 2019's F82 with the exact
   F0 and F(arccos 1/7) (equal to the F82 tint that matches F there), and Schlick with the exact F0.
3. **Generalised Adobe with p ≠ 5**: what reading the table's p = 5 columns costs another exponent.
4. **Side by side, each table read as its shader reads it** (bilinear, at random (μo, r), the F82-tint family): this
   project's exact table (``fresnelLinearSplitSum``), its basis table with the include's projection, Babylon.js's
   OpenPBR table (npm ``@babylonjs/core``, 8-bit RGBD decoded to half floats as its ``rgbdDecode`` pass does:
   :mod:`benchmarks.babylon_table`) and Schlick with F0 from this project's table; against the model's own split sum
   in float64 at the same points. ``--no-babylon`` leaves Babylon.js out (no npm).

Run: ``.venv/bin/python -m benchmarks.linear_models [--grid N] [--conductors N] [--points N] [--no-babylon]
[--out FILE]`` (the report: ``--out report/linear_models.md``).
"""

from __future__ import annotations

import argparse

import numpy as np

from basis import coefficients_from_nk, default_basis, fresnel_conductor, reconstruct
from basis.angles import cos_theta
from basis.models import fresnel_model
from basis.models.formulas import F82_MU, hoffman2019_curve, schlick_curve
from benchmarks.output import publish
from handoff.exr import read_lut
from handoff.shaders import coefficients_per_pixel_model, linear_model_curve, linear_weights, shader_constants
from handoff.shipped import BASIS_LUT, SCHLICK_LUT, shipped_lut
from preintegrate.channels import basis_channels, schlick_table_channels
from preintegrate.ggx import roughness_to_alpha
from preintegrate.quadrature import directional_albedo

THETA = np.linspace(0.0, 0.5 * np.pi, 2001)
#: The F82-tint family of sections 1 and 4: F0 0.02–1 × tint 0–1.
F0_RANGE, F0_COUNT, TINT_COUNT = (0.02, 1.0), 50, 21


def _summary(errors: np.ndarray) -> tuple[float, float]:
    """(max, median) over materials of each material's max error."""
    return float(np.max(errors)), float(np.median(errors))


def _family() -> tuple[np.ndarray, np.ndarray]:
    """(F0, tint) of the F82-tint family, flattened."""
    grids = np.meshgrid(np.linspace(*F0_RANGE, F0_COUNT), np.linspace(0.0, 1.0, TINT_COUNT))
    return grids[0].ravel(), grids[1].ravel()


def f82_tint_family(grid: int = 24) -> dict[str, tuple[float, float]]:
    """method → (max, median) over the family of max |error|, for F̄ on a grid × grid (μo, r) grid and the curve."""
    f0, tint = _family()
    weights = linear_weights("f82-tint", f0=f0, tint=tint)  # (M, 3)
    coefficients = coefficients_per_pixel_model("f82-tint", f0=f0, tint=tint)  # (M, 4): the include's projection
    table = read_lut(shipped_lut(SCHLICK_LUT))[0]
    columns, rows = (np.round(np.linspace(0, n - 1, grid)).astype(int) for n in table.shape[1::-1])
    column, row = (values.ravel() for values in np.meshgrid(columns, rows))
    mu_o, roughness = (column / (table.shape[1] - 1)) ** 2, row / (table.shape[0] - 1)  # texels: no interpolation
    alpha = roughness_to_alpha(roughness)
    linear = directional_albedo(schlick_table_channels().functions, mu_o, alpha)[:, [0, 1, 3]]  # (P, 3) float64
    basis = directional_albedo(basis_channels().functions, mu_o, alpha)  # (P, 4)
    exact = linear @ weights.T  # (P, M): the model's own split sum
    read = table[row, column][:, [0, 1, 3]] @ weights.T
    schlick = linear[:, :1] * f0 + linear[:, 1:2]
    mu = cos_theta(THETA)[:, None]
    curve = linear_model_curve("f82-tint", mu, f0=f0, tint=tint)  # (T, M), unclamped as the table holds it
    inside = np.all((curve >= 0.0) & (curve <= 1.0), axis=0)
    return {
        "materials (of them, curve inside [0, 1])": (float(f0.size), float(np.sum(inside))),
        "exact table, Fbar (the shipped float32 texels)": _summary(np.max(np.abs(read - exact), axis=0)),
        "basis projection, Fbar": _summary(np.max(np.abs(basis @ coefficients.T - exact), axis=0)),
        "Schlick F0 only, Fbar": _summary(np.max(np.abs(schlick - exact), axis=0)),
        "basis projection, F over theta": _summary(np.max(np.abs(reconstruct(coefficients, mu) - curve), axis=0)),
        "Schlick F0 only, F over theta": _summary(np.max(np.abs(schlick_curve(mu, f0) - curve), axis=0)),
    }


def conductors(count: int = 2000, seed: int = 39) -> dict[str, tuple[float, float]]:
    """method → (max, median) over random conductors of max over θ |F_method − F_exact|."""
    rng = np.random.default_rng(seed)
    eta, kappa = rng.uniform(0.1, 4.0, count), rng.uniform(1.0, 8.0, count)
    mu = cos_theta(THETA)[:, None]
    exact = fresnel_conductor(mu, eta, kappa)  # (T, N)
    f0, f82 = fresnel_conductor(1.0, eta, kappa), fresnel_conductor(F82_MU, eta, kappa)
    basis = reconstruct(coefficients_from_nk(eta, kappa, default_basis()), mu)
    return {
        "conductors": (float(count), float(count)),
        "basis, four-point from eta, kappa": _summary(np.max(np.abs(basis - exact), axis=0)),
        "F82 (Hoffman 2019) with the exact F0 and F82": _summary(
            np.max(np.abs(np.clip(hoffman2019_curve(mu, f0, f82), 0, 1) - exact), axis=0)
        ),
        "Schlick with the exact F0": _summary(np.max(np.abs(schlick_curve(mu, f0) - exact), axis=0)),
    }


def side_by_side(points: int = 2000, babylon: bool = True, seed: int = 39) -> dict[str, tuple[float, float]]:
    """path → (max, median) over the F82-tint family of max |error| of the split sum E·F̄ at ``points`` random
    (μo, r) ∈ [0, 1]², each table read bilinearly as its shader reads it."""
    f0, tint = _family()
    rng = np.random.default_rng(seed)
    mu_o, roughness = rng.uniform(0.0, 1.0, points), rng.uniform(0.0, 1.0, points)
    linear = directional_albedo(schlick_table_channels().functions, mu_o, roughness_to_alpha(roughness))
    exact = linear[:, [0, 1, 3]] @ linear_weights("f82-tint", f0=f0, tint=tint).T  # (P, M)
    grid = shader_constants().grid
    ours = grid.lookup(read_lut(shipped_lut(SCHLICK_LUT))[0], mu_o, roughness)  # (P, 4)
    basis_texels = grid.lookup(read_lut(shipped_lut(BASIS_LUT))[0], mu_o, roughness)
    coefficients = coefficients_per_pixel_model("f82-tint", f0=f0, tint=tint)
    extra = {}
    paths = {
        "this project's exact table (fresnelLinearSplitSum)": ours[:, [0, 1, 3]]
        @ linear_weights("f82-tint", f0=f0, tint=tint).T,
        "this project's basis table, projected (fresnelCoefficientsF82Tint)": basis_texels @ coefficients.T,
    }
    if babylon:
        from benchmarks.babylon_table import VERSION, f82_tint_albedo, openpbr_table

        table = openpbr_table()
        paths[f"Babylon.js {VERSION} OpenPBR table (8-bit RGBD, half floats)"] = f82_tint_albedo(
            table, f0, tint, mu_o, roughness
        )
        # its storage alone: at 24² of its texel centres, where bilinear filtering returns a texel
        centres = (np.round(np.linspace(0, 127, 24)) + 0.5) / 128.0
        u, v = (values.ravel() for values in np.meshgrid(centres, centres))
        at_centres = directional_albedo(schlick_table_channels().functions, u, roughness_to_alpha(v))[:, [0, 1, 3]]
        storage = f82_tint_albedo(table, f0, tint, u, v) - at_centres @ linear_weights("f82-tint", f0=f0, tint=tint).T
        extra = {f"Babylon.js {VERSION}, at 24² of its texel centres (its storage alone)": storage}
    paths["Schlick with F0 (tint dropped), this project's table"] = ours[:, :1] * f0 + ours[:, 1:2]
    errors = {name: _summary(np.max(np.abs(values - exact), axis=0)) for name, values in paths.items()}
    return errors | {name: _summary(np.max(np.abs(values), axis=0)) for name, values in extra.items()}


def other_exponents(exponents=(3.0, 4.0, 4.5, 5.5, 6.0, 7.0), steps: int = 11) -> dict[str, tuple[float, float]]:
    """exponent p → (max, median) over r0, r90, tint on a grid of max over θ |F_p − F_5|: what reading the p = 5
    columns of the table costs a generalised Adobe material of another exponent."""
    model = fresnel_model("generalized-adobe")
    mu = cos_theta(THETA)[:, None]
    r0, r90, tint = (values.ravel() for values in np.meshgrid(*[np.linspace(0.0, 1.0, steps)] * 3))
    five = model.evaluate(mu, r0=r0, r90=r90, tint=tint, exponent=5.0)
    return {
        f"p = {p:g}": _summary(np.max(np.abs(model.evaluate(mu, r0=r0, r90=r90, tint=tint, exponent=p) - five), axis=0))
        for p in exponents
    }


def markdown(family: dict, metals: dict, exponents: dict, grid: int, shared: dict, points: int) -> str:
    lines = [
        f"`python -m benchmarks.linear_models --grid {grid}`: max and median over the materials of each one's max "
        f"|error| (F̄ at {grid}² texels of the shipped 128² grid, both ends of both axes among them; F over 2001 θ). "
        "Between texels every table adds the same bilinear error (`report/lut_edges.md`).",
        "",
        "**The F82-tint family** (F0 0.02–1 × tint 0–1, one channel), against the model's own split sum:",
        "",
        "| path | max | median |",
        "|---|---:|---:|",
    ]
    count, inside = family.pop("materials (of them, curve inside [0, 1])")
    lines += [f"| {name} | {high:.2e} | {middle:.2e} |" for name, (high, middle) in family.items()]
    lines += [
        "",
        f"({int(count)} materials, {int(inside)} of them with a curve inside [0, 1], where the linear form is the model.)",
        "",
        "**Physical conductors** (η 0.1–4, κ 1–8), curve error against the exact Fresnel equations:",
        "",
        "| path | max | median |",
        "|---|---:|---:|",
    ]
    metals.pop("conductors")
    lines += [f"| {name} | {high:.2e} | {middle:.2e} |" for name, (high, middle) in metals.items()]
    lines += [
        "",
        "**Generalised Adobe with p ≠ 5** (Hoffman 2023 eq. 6; r0, r90, tint on an 11³ grid): the table's columns are",
        "p = 5's, so another exponent read from them misses its curve by max over θ |F_p − F_5| (its exact split sum",
        "is its own table, `fresnel-lut build --model generalized-adobe --exponent P`):",
        "",
        "| exponent | max | median |",
        "|---|---:|---:|",
    ]
    lines += [f"| {name} | {high:.2e} | {middle:.2e} |" for name, (high, middle) in exponents.items()]
    lines += [
        "",
        f"**Side by side, each table read as its shader reads it** (the F82-tint family above, E·F̄ at {points} random",
        "(μo, r) ∈ [0, 1]², bilinear with clamp at each table's own coordinates; against the model's split sum in",
        "float64 at the same points, so each row holds its table's storage and its interpolation):",
        "",
        "| path | max | median |",
        "|---|---:|---:|",
    ]
    lines += [f"| {name} | {high:.2e} | {middle:.2e} |" for name, (high, middle) in shared.items()]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grid", type=int, default=24, help="(mu_o, r) points a side for Fbar (default 24)")
    parser.add_argument("--conductors", type=int, default=2000, help="random conductors (default 2000)")
    parser.add_argument("--points", type=int, default=2000, help="random (mu_o, r) of the side by side (default 2000)")
    parser.add_argument("--no-babylon", action="store_true", help="leave Babylon.js's table out (fetched with npm)")
    parser.add_argument("--out", default=None, help="also write the Markdown here")
    arguments = parser.parse_args(argv)
    text = markdown(
        f82_tint_family(arguments.grid),
        conductors(arguments.conductors),
        other_exponents(),
        arguments.grid,
        side_by_side(arguments.points, babylon=not arguments.no_babylon),
        arguments.points,
    )
    publish(text, arguments.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
