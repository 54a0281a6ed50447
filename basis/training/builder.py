"""Build a :class:`~basis.eigenbasis.Basis`: training set → iterative SVD → fit angles.

Public objects: ``build_basis``, ``holdout_fit_errors``, ``choose_fit_angles``, ``TALK_ANGLES``,
``NOTEBOOK_ANGLES``.

The fit angles θ2, θ3 are chosen on the held-out materials (dielectrics and metals, see
:mod:`basis.training`) by minimising the worst max |ΔF| over θ of the four-point fit, in a window
around the talk's θ2 ≈ 1.45, θ3 ≈ 1.31. The errors at the talk's and at the authors' notebook angles
are stored beside the choice so the effect is on record.

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, "Coefficients".
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..angles import angle_grid, cos_theta
from ..eigenbasis import Basis
from ..fresnel import fresnel_kernel
from ..parallel import one_blas_thread
from ..validation import check_positive_int
from .domain import DEFAULT_DOMAIN, TrainingDomain
from .holdout import holdout_materials
from .svd import build_curves

__all__ = ["NOTEBOOK_ANGLES", "TALK_ANGLES", "build_basis", "choose_fit_angles", "holdout_fit_errors"]

#: θ2, θ3 as printed in the talk.
TALK_ANGLES = (1.45, 1.31)
#: θ2, θ3 of the authors' public notebook: cos θ = 0.128 and 0.432.
NOTEBOOK_ANGLES = (float(np.arccos(0.128)), float(np.arccos(0.432)))
#: Groups of :func:`basis.training.holdout_materials` the choice of angles minimises over.
SELECTION_GROUPS = ("dielectrics", "metals")


def holdout_fit_errors(basis: Basis, angles=None, samples: int = 1001) -> dict[str, float]:
    """Worst max |ΔF| over θ of the four-point fit, per held-out group, at ``angles`` = (θ2, θ3, …)."""
    fit_angles = basis.fit_angles if angles is None else np.array([0.0, 0.5 * np.pi, *angles])
    inverse = np.linalg.inv(basis.evaluate(fit_angles)).T
    theta = np.linspace(0.0, 0.5 * np.pi, samples)
    curves = basis.evaluate(theta)
    errors = {}
    for name, (eta, kappa) in holdout_materials().items():
        coefficients = fresnel_kernel(cos_theta(fit_angles), eta[:, None], kappa[:, None]) @ inverse
        exact = fresnel_kernel(cos_theta(theta), eta[:, None], kappa[:, None])
        errors[name] = float(np.max(np.abs(coefficients @ curves.T - exact)))
    return errors


def choose_fit_angles(basis: Basis, theta2=(1.30, 1.56, 27), theta3=(1.0, 1.5, 26)) -> tuple[float, float]:
    """Grid search of (θ2 > θ3) minimising the worst held-out error over ``SELECTION_GROUPS``.

    The exact curves of the held-out materials, at the candidate angles and on the error grid, are
    computed once; each candidate pair is then a 4 × 4 solve and a matrix product.
    """
    candidates2, candidates3 = np.linspace(*theta2), np.linspace(*theta3)
    angles = np.concatenate([[0.0, 0.5 * np.pi], candidates2, candidates3])
    theta = np.linspace(0.0, 0.5 * np.pi, 257)
    eta, kappa = (np.concatenate(parts) for parts in zip(*(holdout_materials()[group] for group in SELECTION_GROUPS)))
    exact_at = fresnel_kernel(cos_theta(angles), eta[:, None], kappa[:, None])
    exact = fresnel_kernel(cos_theta(theta), eta[:, None], kappa[:, None])
    basis_at, curves = basis.evaluate(angles), basis.evaluate(theta)
    best = (np.inf, TALK_ANGLES)
    for i, angle2 in enumerate(candidates2, start=2):
        for j, angle3 in enumerate(candidates3, start=2 + candidates2.size):
            if angle3 > angle2 - 0.02:
                continue
            rows = [0, 1, i, j]
            coefficients = np.linalg.solve(basis_at[rows], exact_at[:, rows].T).T
            score = float(np.max(np.abs(coefficients @ curves.T - exact)))
            if score < best[0]:
                best = (score, (float(round(angle2, 4)), float(round(angle3, 4))))
    return best[1]


def build_basis(
    count: int = 200_000,
    seed: int = 1,
    domain: TrainingDomain = DEFAULT_DOMAIN,
    grid_size: int = 512,
    grid_kind: str = "theta",
    n_terms: int = 4,
    fit_angles: str | tuple = "auto",
    progress: Callable[[int], None] | None = None,
) -> Basis:
    """Build the eigen-basis from ``count`` training curves.

    Parameters
    ----------
    count, seed : int
        Training-set size and random seed (the set is a pure function of both and ``domain``).
    grid_size, grid_kind : int, str
        θ samples (≥ 16) and their spacing (see :func:`basis.training.angle_grid`).
    n_terms : int
        K; fit angles beyond θ3 are not chosen automatically, so ``"auto"``/``"talk"`` need K = 4.
    fit_angles : {"auto", "talk", "notebook"} or tuple of float
        θ2, θ3 (, …): searched on the held-out set, the talk's, the notebook's, or given.
    """
    count = check_positive_int("count", count, low=100)
    with one_blas_thread():  # basis.json's bytes, statistics included, must not depend on BLAS threads
        return _build(count, seed, domain, grid_size, grid_kind, n_terms, fit_angles, progress)


def _build(count, seed, domain, grid_size, grid_kind, n_terms, fit_angles, progress) -> Basis:
    theta = angle_grid(grid_size, grid_kind)
    curves, stats = build_curves(theta, domain.curves(theta, count, seed), n_terms, progress)
    provisional = Basis(theta, curves, np.array([0.0, 0.5 * np.pi, *TALK_ANGLES][:n_terms]))
    named = {"talk": TALK_ANGLES, "notebook": NOTEBOOK_ANGLES}
    if isinstance(fit_angles, str):
        if fit_angles not in ("auto", *named):
            raise ValueError(f"fit_angles must be 'auto', 'talk', 'notebook' or a tuple, got {fit_angles!r}")
        chosen = choose_fit_angles(provisional) if fit_angles == "auto" else named[fit_angles]
    else:
        chosen = tuple(float(angle) for angle in fit_angles)
    errors = {name: holdout_fit_errors(provisional, angles) for name, angles in {**named, "chosen": chosen}.items()}
    training = {
        "domain": domain.describe(),
        "count": count,
        "seed": seed,
        "grid": {"kind": grid_kind, "size": grid_size},
        "fit_angle_choice": fit_angles if isinstance(fit_angles, str) else "given",
        "holdout_max_abs_error": {name: {"angles": list(named.get(name, chosen)), **errs} for name, errs in errors.items()},
        **stats,
    }
    return Basis(theta, curves, np.array([0.0, 0.5 * np.pi, *chosen]), training)
