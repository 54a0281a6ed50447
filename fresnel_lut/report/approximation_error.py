"""Every Fresnel model of the references projected onto the basis: how well the basis LUT renders it.

Public objects: ``approximation_table``, ``approximation_markdown``.

For each model of :data:`basis.models.FRESNEL_MODELS` and each point of its documented
parameter sweep (``model.sweep``), the curve is projected onto the basis by the four-point scheme and
by least squares (c0, c1 exact), and the projection error is measured as

* max |ΔF| over θ on the basis grid (512 samples), and
* max |ΔF̄| of the GGX split sum over a ``size`` × ``size`` LUT grid (μo, r; α = r²), by the texel
  weights of :func:`preintegrate.lut.lut_texel_weights` (the split sum is linear in F).

A row gives the worst sweep point and whether the model has exact split-sum channels of its own
(``fresnel-lut build --model NAME``): yes for the models linear in fixed functions of cos θ, as long
as their clamp to [0, 1] stays inactive (the row says on how many sweep points it does not).

Run: ``python -m fresnel_lut.report.approximation_error [--size N]`` (part of ``fresnel-lut report``).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from basis.angles import cos_theta
from basis.coefficients import (
    coefficients_from_samples,
    coefficients_least_squares_from_table,
)
from basis.eigenbasis import Basis, resolve_basis
from basis.models import FRESNEL_MODELS
from preintegrate.lut import LutGrid, lut_texel_weights

__all__ = ["approximation_markdown", "approximation_table"]


def _describe(parameters: dict) -> str:
    return ", ".join(f"{name} {value:g}" for name, value in parameters.items())


def _sweep_description(sweep: tuple[dict, ...]) -> str:
    names = list(sweep[0])
    values = {name: sorted({point[name] for point in sweep}) for name in names}
    if np.prod([len(v) for v in values.values()]) == len(sweep):  # a full grid
        return "; ".join(f"{name} ∈ {{{', '.join(f'{v:g}' for v in values[name])}}}" for name in names)
    first, rest = names[0], names[1:]
    pairs = sorted({tuple(point[name] for name in rest) for point in sweep})
    return (
        f"{first} ∈ {{{', '.join(f'{v:g}' for v in values[first])}}}; ({', '.join(rest)}) ∈ "
        + "{"
        + ", ".join("(" + ", ".join(f"{v:g}" for v in pair) + ")" for pair in pairs)
        + "}"
    )


def approximation_table(basis: Basis | None = None, size: int = 32, names=None) -> dict:
    """Rows (one per model) of the projection error on the model's sweep; see the module docstring."""
    basis = resolve_basis(basis)
    started = time.perf_counter()
    weights = lut_texel_weights(basis.theta, LutGrid.centred(size))
    mu_grid, mu_fit = cos_theta(basis.theta), cos_theta(basis.fit_angles)
    curves = basis.curves  # (K, M) on basis.theta
    rows = []
    for name, model in FRESNEL_MODELS.items():
        if names is not None and name not in names:
            continue
        targets = np.stack([model.evaluate(mu_grid, **point) for point in model.sweep])  # (S, M)
        at_angles = np.stack([model.evaluate(mu_fit, **point) for point in model.sweep])  # (S, K)
        fits = {
            "four-point": coefficients_from_samples(at_angles, basis),
            "least-squares": coefficients_least_squares_from_table(basis.theta, targets, basis),
        }
        row = {
            "model": name,
            "reference": model.reference,
            "formula": model.formula,
            "sweep": _sweep_description(model.sweep),
            "points": len(model.sweep),
        }
        for fit, coefficients in fits.items():
            difference = targets - coefficients @ curves
            curve_error = np.max(np.abs(difference), axis=1)
            albedo_error = np.max(np.abs(difference @ weights.T), axis=1)
            worst = int(np.argmax(albedo_error))
            row[fit] = {
                "curve": float(curve_error.max()),
                "albedo": float(albedo_error.max()),
                "albedo_median": float(np.median(albedo_error)),
                "worst": _describe(model.sweep[worst]),
                "over_1_255": int(np.sum(albedo_error > 1 / 255)),
            }
        if model.linear:
            inactive = sum(bool(np.all(model.clamp_is_inactive(**point))) for point in model.sweep)
            channels = model.channel_functions(**model.sweep[0])(np.array([0.5])).shape[-1]
            row["channels"] = channels
            row["clamped_points"] = len(model.sweep) - inactive
        else:
            row["channels"] = None
            row["clamped_points"] = 0
        rows.append(row)
    return {"rows": rows, "size": size, "basis_hash": basis.content_hash, "seconds": time.perf_counter() - started}


def approximation_markdown(result: dict) -> str:
    """One row per model: parameters, own split-sum channels, basis projection error."""
    lines = [
        (
            f"Projection onto the basis (hash {result['basis_hash']}): max |ΔF| over θ and max |ΔF̄| over a "
            f"{result['size']} × {result['size']} LUT grid: worst and median over each model's sweep [points with "
            "|ΔF̄| > 1/255 / points]. 'Own channels': LUT channels of the model's exact split sum "
            "(`fresnel-lut build --model NAME`)."
        ),
        "",
        (
            "| model | parameters swept | own channels | four-point: worst max abs dF | worst max abs dFbar "
            "| median max abs dFbar | least squares: worst max abs dF | worst max abs dFbar | median max abs dFbar "
            "| worst point (four-point) |"
        ),
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for row in result["rows"]:
        if row["channels"] is None:
            channels = "no (not linear)"
        else:
            channels = f"{row['channels']}"
            if row["clamped_points"]:
                channels += f" (exact unless clamped: {row['clamped_points']} of {row['points']} clamp)"
        four, least = row["four-point"], row["least-squares"]
        lines.append(
            f"| `{row['model']}` | {row['sweep']} | {channels} | {four['curve']:.4f} "
            f"| {four['albedo']:.4f} [{four['over_1_255']}/{row['points']}] | {four['albedo_median']:.4f} "
            f"| {least['curve']:.4f} | {least['albedo']:.4f} [{least['over_1_255']}/{row['points']}] "
            f"| {least['albedo_median']:.4f} | {four['worst']} |"
        )
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=32, help="LUT grid for the preintegrated error (default 32)")
    arguments = parser.parse_args(argv)
    result = approximation_table(size=arguments.size)
    print(approximation_markdown(result))
    print(f"{result['seconds']:.1f} s")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
