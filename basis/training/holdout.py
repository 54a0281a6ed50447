"""Held-out materials on which the basis, its training domain and its fit angles are judged.

Public objects: ``holdout_materials``.

None of these is drawn from the training sampler (different seeds and, for the grids, deterministic
lattices). Groups follow the design notes: real dielectrics (η 1.2–2.9), metals (η 0.1–4, κ 1–8),
the Gulbrandsen artist space (r up to 0.95, g in [0, 1]) and stiff corners (κ up to 100, η up to 50,
r up to 0.999).
"""

from __future__ import annotations

import numpy as np

from ..gulbrandsen import gulbrandsen_to_nk

__all__ = ["holdout_materials"]


def holdout_materials(seed: int = 20200817) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Named groups of (η, κ) arrays."""
    rng = np.random.default_rng(seed)
    r_grid, g_grid = np.meshgrid(np.linspace(0.0, 0.95, 20), np.linspace(0.0, 1.0, 11))
    stiff_r, stiff_g = np.meshgrid([0.98, 0.99, 0.995, 0.999], np.linspace(0.0, 1.0, 5))
    return {
        "dielectrics": (np.linspace(1.2, 2.9, 35), np.zeros(35)),
        "metals": (np.exp(rng.uniform(np.log(0.1), np.log(4.0), 400)), rng.uniform(1.0, 8.0, 400)),
        "gulbrandsen": gulbrandsen_to_nk(r_grid.ravel(), g_grid.ravel()),
        "stiff": (
            np.concatenate([np.geomspace(0.05, 50.0, 12), np.full(6, 1.0), gulbrandsen_to_nk(stiff_r, stiff_g)[0].ravel()]),
            np.concatenate([np.zeros(12), np.geomspace(10.0, 100.0, 6), gulbrandsen_to_nk(stiff_r, stiff_g)[1].ravel()]),
        ),
    }
