"""Deterministic quadrature against the VNDF Monte-Carlo reference, texel by texel.

Run: ``.venv/bin/python benchmarks/quadrature_vs_montecarlo.py [--samples N]``. Prints, for a grid of
(μo, α) that includes the stiff corners, the largest |quadrature − Monte Carlo| over the six LUT
channels (4 basis + 2 Schlick) and the largest |Δ| / σ, then the self-convergence of the quadrature
(default order against order 64) over a full 128 × 128 table.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from preintegrate.channels import basis_channels, combine, schlick_channels
from preintegrate.estimators import monte_carlo_albedo
from preintegrate.lut import build_table
from preintegrate.quadrature import DEFAULT_ORDER, QuadratureOrder, directional_albedo


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--samples", type=int, default=2_000_000, help="Monte-Carlo samples per texel")
    parser.add_argument("--size", type=int, default=128, help="table size of the convergence check")
    arguments = parser.parse_args()
    combined = combine(basis_channels(), schlick_channels())
    functions = combined.functions

    worst_abs = worst_sigma = 0.0
    started = time.perf_counter()
    for mu_o in (1e-3, 0.01, 0.1, 0.3, 0.6, 0.9, 1.0):
        for alpha in (1e-3, 0.01, 0.05, 0.2, 0.5, 1.0):
            quadrature = directional_albedo(functions, mu_o, alpha)
            mean, error = monte_carlo_albedo(functions, mu_o, alpha, samples=arguments.samples, seed=7)
            delta = np.abs(quadrature - mean)
            worst_abs = max(worst_abs, float(delta.max()))
            # σ floor 1e-9: a channel that is ~0 on every sample (Schlick bias at μo = 1, tiny α) has σ = 0
            worst_sigma = max(worst_sigma, float(np.max(delta / np.maximum(error, 1e-9))))
    print(f"42 texels x 6 channels, {arguments.samples} VNDF samples each ({time.perf_counter() - started:.1f} s):")
    print(f"  max |quadrature - MC| = {worst_abs:.2e}, max |quadrature - MC| / sigma = {worst_sigma:.2f}")

    started = time.perf_counter()
    table = build_table(combined, arguments.size, order=DEFAULT_ORDER)
    seconds = time.perf_counter() - started
    reference = build_table(combined, arguments.size, order=QuadratureOrder.uniform(64))
    print(
        f"{arguments.size}x{arguments.size} table, 6 channels, default order ({DEFAULT_ORDER.describe()}): {seconds:.2f} s"
    )
    print(f"  max |default - order 64| = {np.abs(table - reference).max():.2e}")


if __name__ == "__main__":
    main()
