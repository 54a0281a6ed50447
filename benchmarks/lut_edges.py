"""The tables' edges (issue 26 item 21): lookup error over all of [0, 1]² for three texel placements of one size.

For each placement of :data:`preintegrate.lut.COLUMN_PLACEMENTS` × rows (``centres``: the engines' table and this
project's before 2026-12; ``endpoints``: both ends of both axes on a texel; ``root-endpoints``: the same with the
columns uniform in √μo, the default build), a W × W table of the four basis channels is built and read as a GPU
reads it (bilinear, clamp-to-edge, through the grid's coordinates: :meth:`preintegrate.lut.LutGrid.lookup`) at
seeded random (μo, r) in the interior and on every edge, and compared with the split-sum integral at those very
points (:func:`preintegrate.quadrature.directional_albedo`, the integral the tables hold, itself within 3e-8 of
adaptive cubature: ``tests/fresnel_lut/test_cli.py``). Reported: max and 99th percentile of max_k |Δb̄_k| per region,
and gold's (``luts/materials.json``, ACEScg) max |ΔF̄| over the RGB channels, which weighs the channels as a material
does.

Run: ``.venv/bin/python -m benchmarks.lut_edges [--size W] [--points N] [--out FILE]`` (the report:
``--out report/lut_edges.md``).
"""

from __future__ import annotations

import argparse

import numpy as np

from basis import default_basis, material_coefficients
from benchmarks.output import publish
from preintegrate.channels import basis_channels
from preintegrate.ggx import roughness_to_alpha
from preintegrate.lut import LutGrid, build_table
from preintegrate.quadrature import directional_albedo

PLACEMENTS = {
    "centres (engines; before 2026-12)": {"rows": "centres", "columns": "centres"},
    "endpoints": {"rows": "endpoints", "columns": "endpoints"},
    "root-endpoints (default)": {"rows": "endpoints", "columns": "root-endpoints"},
}


def sample_points(points: int, seed: int = 26) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """(μo, r) per region: the interior and each edge, the issue's grazing view μo = 0.002, and the corners."""
    rng = np.random.default_rng(seed)
    edge = max(points // 8, 8)

    def uniform(count: int) -> np.ndarray:
        return rng.uniform(0.0, 1.0, count)

    return {
        "all of [0, 1]^2": (uniform(points), uniform(points)),
        "mu_o >= 0.1, r >= 0.1": (rng.uniform(0.1, 1.0, points), rng.uniform(0.1, 1.0, points)),
        "mu_o = 0": (np.zeros(edge), uniform(edge)),
        "mu_o = 0.002": (np.full(edge, 0.002), uniform(edge)),
        "mu_o = 1": (np.ones(edge), uniform(edge)),
        "r = 0": (uniform(edge), np.zeros(edge)),
        "r = 1": (uniform(edge), np.ones(edge)),
        "the issue's points": (np.array([0.5, 0.002, 0.002]), np.array([1.0, 0.5, 1.0])),
    }


def edge_errors(size: int = 128, points: int = 4000) -> dict[str, dict[str, tuple[float, float, float]]]:
    """placement → region → (max, 99th percentile of max_k |Δb̄_k|, gold's max |ΔF̄|)."""
    basis = default_basis()
    channels = basis_channels(basis)
    gold = material_coefficients("Gold")  # (3, 4)
    regions = sample_points(points)
    exact = {
        name: directional_albedo(channels.functions, mu_o, roughness_to_alpha(roughness))
        for name, (mu_o, roughness) in regions.items()
    }
    result = {}
    for placement, axes in PLACEMENTS.items():
        grid = LutGrid(size, size, **axes)
        table = build_table(channels, grid)
        rows = {}
        for name, (mu_o, roughness) in regions.items():
            difference = grid.lookup(table, mu_o, roughness) - exact[name]  # (P, 4)
            per_point = np.max(np.abs(difference), axis=-1)
            rows[name] = (
                float(per_point.max()),
                float(np.quantile(per_point, 0.99)),
                float(np.max(np.abs(difference @ gold.T))),
            )
        result[placement] = rows
    return result


def markdown(result: dict, size: int, points: int) -> str:
    placements = list(result)
    lines = [
        f"Lookup error of a {size} x {size} basis table per texel placement (`python -m benchmarks.lut_edges --size "
        f"{size} --points {points}`): max and 99th percentile over the region's seeded points of max_k |b̄_k lookup "
        "- b̄_k integral|, and gold's max |F̄| error (ACEScg, RGB).",
        "",
        "| region | " + " | ".join(placements) + " |",
        "|---|" + "---|" * len(placements),
    ]
    for region in result[placements[0]]:
        cells = ["{:.1e} (p99 {:.1e}; gold {:.1e})".format(*result[placement][region]) for placement in placements]
        lines.append(f"| {region} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=128, help="table width = height (default 128)")
    parser.add_argument("--points", type=int, default=4000, help="seeded points per interior region (default 4000)")
    parser.add_argument("--out", default=None, help="also write the Markdown table here")
    arguments = parser.parse_args(argv)
    text = markdown(edge_errors(arguments.size, arguments.points), arguments.size, arguments.points)
    publish(text, arguments.out)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
