"""Plan a scene build: which tables, which layout per material, how many roughness rows.

Public objects: ``ScenePlan``, ``plan_scene``.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable

import numpy as np

from basis.eigenbasis import Basis, resolve_basis

from ..lut import interpolation_weights, texel_centres
from ..quadrature import texel_weights
from .files import Scene, SceneError
from .layout import SCHLICK, Layout, basis_layout, own_layout, scene_basis_layouts, training_operators

__all__ = ["ACCURACY_GOAL", "ScenePlan", "plan_scene"]

#: What a scene build holds a material to before it saves bytes, where some layout can: one 10-bit step.
#: The tolerance is the most a build may give away; a material whose best layout reaches this goal keeps it.
ACCURACY_GOAL = 1.0 / 1023.0

#: Roughness samples of the error grid: 2 × 17 − 1 over the scene's range.
_EVAL_ROUGHNESS = 17
#: The scene bases' training set: every 4th view cosine of the error grid (and layout.TRAINING_ROUGHNESSES).
_TRAINING_STRIDE = 4


@dataclasses.dataclass
class ScenePlan:
    """What :func:`plan_scene` decided, with every material's achieved error."""

    scene: Scene
    tables: tuple[str, ...]  # names of ``candidates``: "schlick", "basis-K", "scene-basis-K", "model:…"
    roughness_range: tuple[float, float]
    rows: int
    layouts: dict[str, str]
    coefficients: dict[str, np.ndarray]
    errors: dict[str, float]
    full_errors: dict[str, dict[str, float]]
    default_build_errors: dict[str, float]
    candidates: dict[str, Layout]
    table_values: dict[str, np.ndarray]  # the tables to write: (rows, columns, channels) per name of ``tables``
    aims: dict[str, float]  # per material: the error the build held it to (ACCURACY_GOAL where reachable)


def plan_scene(scene: Scene, basis: Basis | None = None, progress: Callable[[str], None] | None = None) -> ScenePlan:
    """Choose tables, layouts and rows (module docstring); raises :class:`SceneError` if a material cannot
    meet the tolerance with any layout, naming it and the smallest tolerance that would do. ``progress``
    receives a line per trained scene basis."""
    basis = resolve_basis(basis)
    theta = basis.theta
    low = min(m.roughness[0] for m in scene.materials)
    high = max(m.roughness[1] for m in scene.materials)
    # view cosines: the texel centres and the midpoints between them, μo ∈ [0.5/W, 1 − 0.5/W]; below the
    # first centre every engine reads the edge texel (clamped NdotV), as the default build does
    mu_eval = (np.arange(2 * scene.size - 1) + 1.0) / (2 * scene.size)
    mu_columns = texel_centres(scene.size)
    grid = np.linspace(low, high, 2 * _EVAL_ROUGHNESS - 1)
    r_eval = {m.name: np.unique(np.concatenate([grid[(grid >= m.roughness[0]) & (grid <= m.roughness[1])], m.roughness]))
              for m in scene.materials}
    all_r = np.unique(np.concatenate(list(r_eval.values())))
    # rows of the densest candidate, nested: H = 2^k + 1 endpoint-inclusive rows over [low, high]
    levels = 1 if high == low else max(1, math.ceil(math.log2(max(1.0, scene.size * (high - low)))))
    max_rows = 1 if high == low else 2**levels + 1
    r_rows = np.linspace(low, high, max_rows)
    interp_mu = interpolation_weights(mu_eval, mu_columns)  # (P, W)
    # Every split sum is a linear functional of the curve: the texel weights (…, M) are computed once per
    # texel set and contracted at once with what they act on, so no (…, M) array outlives this block.
    w_eval = texel_weights(theta, mu_eval[None, :], (all_r**2)[:, None])  # (R, P, M)
    exact_of = {m.name: w_eval[np.searchsorted(all_r, r_eval[m.name])] @ m.curve for m in scene.materials}  # (r, P, 3)
    # the scene bases are trained on a coarser set of the same functionals (every 4th view cosine, 5 roughnesses
    # per material): 1/25 of the work, and the plan below measures them on the full set like every layout
    operators = training_operators(scene, basis, mu_eval[::_TRAINING_STRIDE])
    scene_bases = scene_basis_layouts(scene, basis, operators, ACCURACY_GOAL, progress)
    del w_eval, operators
    own_layouts = {layout.name: layout for layout in map(own_layout, scene.materials) if layout is not None}
    candidates = {SCHLICK.name: SCHLICK, **{basis_layout(k).name: basis_layout(k) for k in (2, 3, 4)},
                  **{layout.name: layout for layout in scene_bases},
                  **{name: own_layouts[name] for name in sorted(own_layouts)}}
    own = sorted(own_layouts)
    functions = {name: layout.values(basis) for name, layout in candidates.items()}  # (M, n) on the θ grid

    w_rows = texel_weights(theta, mu_columns[None, :], (r_rows**2)[:, None])  # (H, W, M)
    table_rows = {name: w_rows @ values for name, values in functions.items()}  # the candidate tables (H, W, n)
    del w_rows
    rows_mu = {name: np.einsum("pw,hwn->hpn", interp_mu, table) for name, table in table_rows.items()}

    # each material's weights per layout, once: the error loops below reuse them for every row count
    weights_of = {(m.name, name): layout.coefficients(m, basis) for m in scene.materials for name, layout in candidates.items()}

    def errors_for(layout: str, rows: np.ndarray, projected=None, positions=None) -> dict[str, float]:
        result = {}
        table_mu = rows_mu[layout][rows] if projected is None else projected  # (H', P, n): texels read along μo
        positions = r_rows[rows] if positions is None else positions
        for material in scene.materials:
            coefficients = weights_of[material.name, layout]
            if coefficients is None:
                result[material.name] = np.inf
                continue
            interp_r = interpolation_weights(r_eval[material.name], positions)  # (r, H')
            approx = np.einsum("rh,hpn,cn->rpc", interp_r, table_mu, coefficients)
            result[material.name] = float(np.max(np.abs(approx - exact_of[material.name])))
        return result

    # the full default build (basis RGBA + Schlick RG, rows at (j + 0.5)/size over 0–1), for comparison
    default_r = texel_centres(scene.size)
    near = np.flatnonzero((default_r >= low - 1.0 / scene.size) & (default_r <= high + 1.0 / scene.size))
    w_default = texel_weights(theta, mu_columns[None, :], (default_r[near] ** 2)[:, None])
    default_errors = {layout: errors_for(layout, near, np.einsum("pw,hwn->hpn", interp_mu, w_default @ functions[layout]),
                                         default_r[near]) for layout in ("schlick", "basis-4")}
    del w_default
    default_best = {m.name: min(default_errors[layout][m.name] for layout in default_errors) for m in scene.materials}

    full = np.arange(max_rows)
    full_errors = {layout: errors_for(layout, full) for layout in functions}
    tolerance = scene.tolerance
    best = {m.name: min(full_errors[layout][m.name] for layout in functions) for m in scene.materials}
    failing = [name for name, value in best.items() if value > tolerance]
    if failing:
        worst = max(failing, key=best.get)
        raise SceneError(
            f"material {worst!r} cannot meet tolerance {tolerance:.3g} on Fbar: the best layout reaches "
            f"{best[worst]:.3g}; use tolerance >= {best[worst] * 1.01:.3g} (or another model for it)"
            + (f"; also failing: {sorted(set(failing) - {worst})}" if len(failing) > 1 else "")
        )
    # accuracy first: a material that some layout holds to ACCURACY_GOAL is held to it, the rest to the tolerance
    aims = {name: min(tolerance, ACCURACY_GOAL) if value <= ACCURACY_GOAL else tolerance for name, value in best.items()}
    channels = {name: functions[name].shape[-1] for name in functions}
    # every combination of at most one basis table (generic or the scene's), the Schlick table and the models' own
    options = [tuple(x for x in (schlick, basis_table, *extra) if x)
               for schlick in ("", "schlick")
               for basis_table in ("", "basis-2", "basis-3", "basis-4", *(layout.name for layout in scene_bases))
               for count in range(len(own) + 1) for extra in itertools.combinations(own, count)]
    options = [option for option in options if option]

    def assign(tables, errors) -> dict[str, str] | None:
        layouts = {}
        for material in scene.materials:
            fitting = [t for t in tables if errors[t][material.name] <= aims[material.name]]
            if not fitting:
                return None
            layouts[material.name] = min(fitting, key=lambda t: errors[t][material.name])
        return layouts

    def worst_share(tables) -> float:
        layouts = assign(tables, full_errors)
        return max(full_errors[layouts[m.name]][m.name] / aims[m.name] for m in scene.materials)

    feasible = [tables for tables in options if assign(tables, full_errors) is not None]
    # fewest channels, then fewest tables, then the more accurate (e.g. the scene basis over the generic one)
    tables = min(feasible, key=lambda t: (sum(channels[x] for x in t), len(t), worst_share(t)))
    # fewest nested rows that still meet the tolerance
    chosen_rows, chosen_errors = full, full_errors
    for level in range(levels + 1):
        count = 2**level + 1 if max_rows > 1 else 1
        if count > max_rows:
            break
        subset = np.round(np.linspace(0, max_rows - 1, count)).astype(int)
        errors = {layout: errors_for(layout, subset) for layout in tables}
        if assign(tables, errors) is not None:
            chosen_rows, chosen_errors = subset, errors
            break
    layouts = assign(tables, chosen_errors)
    return ScenePlan(
        scene=scene, tables=tables, roughness_range=(low, high), rows=len(chosen_rows), layouts=layouts,
        coefficients={m.name: weights_of[m.name, layouts[m.name]] for m in scene.materials},
        errors={m.name: chosen_errors[layouts[m.name]][m.name] for m in scene.materials},
        full_errors=full_errors,
        default_build_errors=default_best,
        candidates={name: candidates[name] for name in tables},
        table_values={name: table_rows[name][chosen_rows] for name in tables},
        aims=aims,
    )
