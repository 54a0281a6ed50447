"""Build a :class:`~basis.eigenbasis.Basis`: training set → iterative SVD → fit angles.

Public objects: ``build_basis``, ``holdout_fit_errors``, ``holdout_lines``, ``choose_fit_angles``, ``TALK_ANGLES``,
``NOTEBOOK_ANGLES``, ``FIT_ANGLE_CHOICES``.

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

from ..angles import angle_grid, cos_theta, theta_spline
from ..eigenbasis import TERMS_RANGE, Basis
from ..fresnel import fresnel_kernel
from ..parallel import one_blas_thread
from ..validation import ParameterError, check_choice, check_positive_int
from .domain import DEFAULT_DOMAIN, TrainingDomain
from .holdout import holdout_materials
from .svd import build_curves

__all__ = [
    "FIT_ANGLE_CHOICES",
    "NOTEBOOK_ANGLES",
    "TALK_ANGLES",
    "build_basis",
    "choose_fit_angles",
    "holdout_fit_errors",
    "holdout_lines",
]

#: θ2, θ3 as printed in the talk.
TALK_ANGLES = (1.45, 1.31)
#: θ2, θ3 of the authors' public notebook: cos θ = 0.128 and 0.432.
NOTEBOOK_ANGLES = (float(np.arccos(0.128)), float(np.arccos(0.432)))
#: The named fit-angle choices of :func:`build_basis` (``fresnel-lut basis --fit-angles``): searched on the
#: held-out set, the talk's, the notebook's.
FIT_ANGLE_CHOICES = ("auto", "talk", "notebook")
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


#: Largest θ grid: the SVD holds a few M × M matrices (M = 4096: about 0.7 GB).
MAX_GRID = 4096


def greedy_fit_angles(theta: np.ndarray, curves: np.ndarray, candidates=(0.2, 1.56, 137)) -> tuple[float, ...]:
    """Fit angles for K ≠ 4 terms, one per term after b1: the curves come in SVD order, so the k-th angle is
    the candidate that minimises the worst held-out error (``SELECTION_GROUPS``) of the (k + 1)-term fit
    with the angles already chosen (a square system at every step)."""
    spline = theta_spline(theta, curves.T, axis=0)
    grid = np.linspace(*candidates)
    dense = np.linspace(0.0, 0.5 * np.pi, 257)
    eta, kappa = (np.concatenate(parts) for parts in zip(*(holdout_materials()[group] for group in SELECTION_GROUPS)))
    angles = [0.0, 0.5 * np.pi]
    exact_dense = fresnel_kernel(cos_theta(dense), eta[:, None], kappa[:, None])
    curves_dense = spline(dense)
    for terms in range(3, curves.shape[0] + 1):
        best = (np.inf, None)
        for angle in grid:
            if min(abs(angle - chosen) for chosen in angles) < 0.02:
                continue
            rows = np.array([*angles, angle])
            system = spline(rows)[:, :terms]
            if np.linalg.cond(system) > 1e6:
                continue
            coefficients = np.linalg.solve(system, fresnel_kernel(cos_theta(rows), eta[:, None], kappa[:, None]).T).T
            score = float(np.max(np.abs(coefficients @ curves_dense[:, :terms].T - exact_dense)))
            if score < best[0]:
                best = (score, float(round(angle, 4)))
        if best[1] is None:
            raise ParameterError(
                f"no fit angle keeps the {terms}-term system solvable: the training curves hold too "
                f"few distinct shapes for {curves.shape[0]} terms (use fewer terms or more curves)"
            )
        angles.append(best[1])
    return tuple(angles[2:])


def build_basis(
    count: int = 200_000,
    seed: int = 1,
    domain: TrainingDomain = DEFAULT_DOMAIN,
    grid_size: int = 512,
    grid_kind: str = "theta",
    n_terms: int = 4,
    fit_angles: str | tuple = "auto",
    progress: Callable[[int], None] | None = None,
    weighting: str = "normalised",
) -> Basis:
    """Build the eigen-basis from ``count`` training curves.

    Parameters
    ----------
    count, seed : int
        Training-set size and random seed (the set is a pure function of both and ``domain``).
    grid_size, grid_kind : int, str
        θ samples (≥ 16) and their spacing (see :func:`basis.angles.angle_grid`).
    n_terms : int
        K in :data:`basis.eigenbasis.TERMS_RANGE` (2 to 8: what the tables and shaders hold); for K ≠ 4, ``"auto"`` chooses one angle per term after b1 (:func:`greedy_fit_angles`).
    fit_angles : {"auto", "talk", "notebook"} or tuple of float
        θ2, θ3 (, …): searched on the held-out set, the talk's, the notebook's, or given.
    weighting : {"normalised", "span"}
        How a curve counts in the SVD (:func:`.svd.build_curves`); "span" is recorded in ``training``.
    """
    count = check_positive_int("count", count, low=100)
    n_terms = check_positive_int("n_terms", n_terms, low=TERMS_RANGE[0], high=TERMS_RANGE[1])
    grid_size = check_positive_int("grid_size", grid_size, low=16, high=MAX_GRID)
    if isinstance(fit_angles, str):
        check_choice("fit_angles", fit_angles, FIT_ANGLE_CHOICES)
        if fit_angles != "auto" and n_terms != 4:
            raise ParameterError(
                f"fit_angles {fit_angles!r} are two angles, for 4 terms; with {n_terms} terms use 'auto' "
                f"or give {n_terms - 2} angles"
            )
    elif len(tuple(fit_angles)) != n_terms - 2:
        raise ParameterError(
            f"{n_terms} terms need {n_terms - 2} fit angles besides 0 and pi/2, got {len(tuple(fit_angles))}"
        )
    with one_blas_thread():  # basis.json's bytes, statistics included, must not depend on BLAS threads
        return _build(count, seed, domain, grid_size, grid_kind, n_terms, fit_angles, progress, weighting)


def _build(count, seed, domain, grid_size, grid_kind, n_terms, fit_angles, progress, weighting) -> Basis:
    theta = angle_grid(grid_size, grid_kind)
    curves, stats = build_curves(theta, domain.curves(theta, count, seed), n_terms, progress, weighting)
    training = {
        "domain": domain.describe(),
        "count": count,
        "seed": seed,
        "grid": {"kind": grid_kind, "size": grid_size},
        "fit_angle_choice": fit_angles if isinstance(fit_angles, str) else "given",
    }
    if weighting != "normalised":  # the shipped basis' description (and bytes) stay as they were
        training["weighting"] = weighting
    if n_terms != 4:  # the talk's and the notebook's angles are for four terms: choose one angle per extra term
        chosen = greedy_fit_angles(theta, curves) if fit_angles == "auto" else tuple(float(a) for a in fit_angles)
        basis = Basis(theta, curves, np.array([0.0, 0.5 * np.pi, *chosen]))
        errors = {"chosen": {"angles": list(chosen), **holdout_fit_errors(basis)}}
        return Basis(theta, curves, basis.fit_angles, {**training, "holdout_max_abs_error": errors, **stats})
    provisional = Basis(theta, curves, np.array([0.0, 0.5 * np.pi, *TALK_ANGLES][:n_terms]))
    named = {"talk": TALK_ANGLES, "notebook": NOTEBOOK_ANGLES}  # FIT_ANGLE_CHOICES beside "auto"
    if isinstance(fit_angles, str):
        chosen = choose_fit_angles(provisional) if fit_angles == "auto" else named[fit_angles]
    else:
        chosen = tuple(float(angle) for angle in fit_angles)
    errors = {name: holdout_fit_errors(provisional, angles) for name, angles in {**named, "chosen": chosen}.items()}
    training = {
        **training,
        "holdout_max_abs_error": {
            name: {"angles": list(named.get(name, chosen)), **errs} for name, errs in errors.items()
        },
        **stats,
    }
    return Basis(theta, curves, np.array([0.0, 0.5 * np.pi, *chosen]), training)


def holdout_lines(basis: Basis) -> list[str]:
    """A built basis' fit angles and its held-out errors (max |ΔF| over θ of the four-point fit at the chosen, the
    talk's and the notebook's angles, per group) as a table a person reads."""
    errors = basis.training["holdout_max_abs_error"]
    groups = [key for key in next(iter(errors.values())) if key != "angles"]
    lines = [
        f"fit angles: {', '.join(f'{angle:.4f}' for angle in basis.fit_angles)} rad",
        "held-out max |dF| over theta of the four-point fit:",
        f"  {'angles':28s}" + "".join(f"{group:>13s}" for group in groups),
    ]
    for name, row in errors.items():
        label = f"{name} ({', '.join(f'{angle:.4f}' for angle in row['angles'])})"
        lines.append(f"  {label:28s}" + "".join(f"{row[group]:13.4f}" for group in groups))
    return lines
