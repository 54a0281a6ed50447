"""Held-out materials on which the basis, its training domain and its fit angles are judged.

Public objects: ``holdout_materials``, ``validation_groups``, ``VALIDATION_SEED``, ``FIGURE_2``.

None of these is drawn from the training sampler (different seeds and, for the grids, deterministic
lattices). :func:`holdout_materials` is what the build chooses fit angles on: real dielectrics
(η 1.2–2.9), metals (η 0.1–4, κ 1–8), the Gulbrandsen artist space (r up to 0.95, g in [0, 1]) and stiff
corners (κ up to 100, η up to 50, r up to 0.999). :func:`validation_groups` is what the basis is *judged*
on (issue 14, the report's basis-fidelity section): fresh draws, never used to build or choose anything.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..fresnel import fresnel_kernel
from ..gulbrandsen import gulbrandsen_to_nk

__all__ = ["FIGURE_2", "VALIDATION_SEED", "holdout_materials", "validation_groups"]

#: Seed of the validation draws (its own: neither the training sets' nor the held-out materials').
VALIDATION_SEED = 14_2020

#: The material of Belcour et al. 2020, Figure 2: Gulbrandsen r = 0.44, g = (0, 1, 0) (and GGX α = 0.08).
FIGURE_2 = {"reflectivity": (0.44, 0.44, 0.44), "edge_tint": (0.0, 1.0, 0.0), "alpha": 0.08}

Curves = Callable[[np.ndarray], np.ndarray]


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
            np.concatenate(
                [np.geomspace(0.05, 50.0, 12), np.full(6, 1.0), gulbrandsen_to_nk(stiff_r, stiff_g)[0].ravel()]
            ),
            np.concatenate(
                [np.zeros(12), np.geomspace(10.0, 100.0, 6), gulbrandsen_to_nk(stiff_r, stiff_g)[1].ravel()]
            ),
        ),
    }


def _exact(eta: np.ndarray, kappa: np.ndarray) -> Curves:
    return lambda mu: fresnel_kernel(np.asarray(mu, dtype=np.float64)[..., None, :], eta[:, None], kappa[:, None])


def _measured_metals(space: str) -> Curves:
    from ..spectral import rgb_fresnel, spectral_iors  # colour science, only when judged

    metals = [material for material in spectral_iors().values() if material.kind == "metal"]

    def curves(mu):
        mu = np.asarray(mu, dtype=np.float64)
        return np.concatenate([np.moveaxis(rgb_fresnel(material, mu, space), -1, -2) for material in metals], axis=-2)

    return curves


def validation_groups(seed: int = VALIDATION_SEED, space: str = "ACEScg") -> dict[str, Curves]:
    """The groups a basis is judged on, each a function μ (M,) → curves F (N, M), one row per curve.

    ``dielectrics``: 200 η uniform in [1.2, 2.9]; ``metals``: 400 with η log-uniform in [0.1, 4], κ uniform in
    [1, 8]; ``measured metals``: every channel of the RGB curves (in ``space``) of the metals of
    ``luts/spectral_ior.json`` by Hoffman's spectral procedure; ``gulbrandsen``: 300 with r uniform in
    [0, 0.9] and g in [0, 1]; ``figure 2``: the three channels of :data:`FIGURE_2`.
    """
    rng = np.random.default_rng(seed)
    dielectric = rng.uniform(1.2, 2.9, 200)
    metal_eta, metal_kappa = np.exp(rng.uniform(np.log(0.1), np.log(4.0), 400)), rng.uniform(1.0, 8.0, 400)
    artist = gulbrandsen_to_nk(rng.uniform(0.0, 0.9, 300), rng.uniform(0.0, 1.0, 300))
    figure = gulbrandsen_to_nk(np.array(FIGURE_2["reflectivity"]), np.array(FIGURE_2["edge_tint"]))
    return {
        "dielectrics": _exact(dielectric, np.zeros_like(dielectric)),
        "metals": _exact(metal_eta, metal_kappa),
        "measured metals": _measured_metals(space),
        "gulbrandsen": _exact(*artist),
        "figure 2": _exact(*figure),
    }
