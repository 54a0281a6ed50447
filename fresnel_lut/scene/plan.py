"""Plan a scene build: which tables, which layout per material, how many roughness rows.

Public objects: ``ScenePlan``, ``plan_scene``, ``lookup_floor``, ``ACCURACY_GOAL``, ``LOOKUP_SHARE``.
"""

from __future__ import annotations

import dataclasses
import itertools
import math
from collections.abc import Callable

import numpy as np

from basis.eigenbasis import Basis, resolve_basis
from basis.validation import check_positive_int
from preintegrate.ggx import roughness_to_alpha
from preintegrate.lut import LutGrid, interpolation_weights
from preintegrate.quadrature import texel_weights

from .files import MAX_SIZE, Scene, SceneError
from .layout import SCHLICK, Layout, basis_layout, own_layout, scene_basis_layouts, training_operators

__all__ = ["ACCURACY_GOAL", "LOOKUP_SHARE", "ScenePlan", "lookup_floor", "plan_scene"]

#: What a scene build holds a material to before it saves bytes, where some layout can: one 10-bit step.
#: The tolerance is the most a build may give away; a material whose best layout reaches this goal keeps it.
ACCURACY_GOAL = 1.0 / 1023.0

#: Share of ACCURACY_GOAL the column lookup alone (:func:`lookup_floor`) may cost before a scene's table widens.
LOOKUP_SHARE = 0.5

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
    columns: int
    layouts: dict[str, str]
    coefficients: dict[str, np.ndarray]
    errors: dict[str, float]
    full_errors: dict[str, dict[str, float]]
    default_build_errors: dict[str, float]
    candidates: dict[str, Layout]
    table_values: dict[str, np.ndarray]  # the tables to write: (rows, columns, channels) per name of ``tables``
    aims: dict[str, float]  # per material: the error the build held it to (ACCURACY_GOAL where reachable)
    exact: dict[str, bool]  # per material: whether its layout's functions hold its curve exactly (lookup error only)

    def path(self, name: str) -> dict[str, str]:
        """README's rule ("Which path for which material") as the plan applied it to material ``name``: ``choice``
        (``exact table``, ``basis`` or ``Schlick approximation``) and ``why``, with the errors of F̄ it weighed."""
        layout, error, aim = self.layouts[name], self.errors[name], self.aims[name]
        if self.exact[name]:
            return {
                "choice": "exact table",
                "why": f"{layout} holds its curve exactly: what remains ({error:.2e} in Fbar) is the bilinear lookup",
            }
        others = {
            other: value[name]
            for other, value in self.full_errors.items()
            if other != layout and np.isfinite(value[name]) and other.startswith("model:")
        }
        declined = "".join(
            f"; its exact table {other} ({value:.2e}) would add a table" for other, value in others.items()
        )
        if self.candidates[layout].kind == "model":
            return {
                "choice": "exact table",
                "why": f"{layout} holds the model before its clamp to [0, 1], which this material's curve meets: "
                f"{error:.2e} in Fbar, within its aim {aim:.3g}",
            }
        if self.candidates[layout].kind == "schlick":
            return {
                "choice": "Schlick approximation",
                "why": f"F0 on Schlick's two channels holds it to {error:.2e}, within its aim {aim:.3g}" + declined,
            }
        return {
            "choice": "basis",
            "why": f"{layout} holds it to {error:.2e}, within its aim {aim:.3g}, in the fewest channels that do"
            + (declined or "; no linear model's table holds a curve of its kind"),
        }

    @property
    def grid(self) -> LutGrid:
        """The tables' grid: the default build's ``columns`` at √μo end points, ``rows`` at the end points of the
        roughness range."""
        return _scene_grid(self.columns, self.rows, self.roughness_range, self.scene.visibility)


def _scene_grid(columns: int, rows: int, roughness_range: tuple[float, float], visibility: str) -> LutGrid:
    """A scene table's grid: columns as the default build's (√μo = i/(W − 1): μo = 0 and 1 on a texel, the columns
    crowding at grazing), rows at the end points of ``roughness_range``."""
    return LutGrid(columns, rows, rows="endpoints", roughness_range=roughness_range, visibility=visibility)


def plan_scene(scene: Scene, basis: Basis | None = None, progress: Callable[[str], None] | None = None) -> ScenePlan:
    """Choose tables, layouts, rows and columns (module docstring); raises :class:`SceneError` if a material
    cannot meet the tolerance with any layout, naming it and the smallest tolerance that would do.
    ``progress`` receives a line per trained scene basis.

    Columns: the scene file's ``size`` if it sets one; otherwise the default build's 128, doubled (up to
    :data:`.files.MAX_SIZE`) while reading some material's exact F̄ bilinearly between the columns alone
    costs more than :data:`LOOKUP_SHARE` of :data:`ACCURACY_GOAL` (:func:`lookup_floor`): near grazing a
    near-mirror's F̄ bends too fast for 128 columns (a clear coat at r = 0.05: 1.3e-3), and accuracy comes before
    bytes."""
    basis = resolve_basis(basis)
    width = scene.size
    floor = lookup_floor(scene, basis, width)
    while not scene.size_fixed and 2 * width <= MAX_SIZE and max(floor.values()) > LOOKUP_SHARE * ACCURACY_GOAL:
        width *= 2
        floor = lookup_floor(scene, basis, width)
    unreachable = sorted((name for name, value in floor.items() if value > scene.tolerance), key=floor.get)
    if unreachable:  # no layout reads better than the exact F̄ itself: refuse before any basis is trained
        worst = unreachable[-1]
        raise SceneError(
            f"material {worst!r} cannot meet tolerance {scene.tolerance:.3g} on Fbar: reading its exact Fbar between "
            f"{width} columns alone is {floor[worst]:.3g} off (it bends faster near grazing than the columns follow); "
            f"use tolerance >= {floor[worst] * 1.01:.3g} or a higher lowest roughness for it"
            + (f"; also out of reach: {unreachable[:-1]}" if len(unreachable) > 1 else "")
        )
    if _schlick_holds_every_curve(scene, basis):
        scene_bases = []  # two exact channels: no layout does better, so none is trained
    else:
        # trained on a coarser set of the plan's functionals (every 4th view cosine of the file's width, 5
        # roughnesses per material): 1/25 of the work or less; the plan measures them on its full set
        operators = training_operators(scene, basis, _view_cosines(scene.size)[::_TRAINING_STRIDE])
        scene_bases = scene_basis_layouts(scene, basis, operators, ACCURACY_GOAL, progress)
        del operators
    own_layouts = {layout.name: layout for layout in map(own_layout, scene.materials) if layout is not None}
    layouts = {
        SCHLICK.name: SCHLICK,
        **{basis_layout(k).name: basis_layout(k) for k in (2, 3, 4)},
        **{layout.name: layout for layout in scene_bases},
        **{name: own_layouts[name] for name in sorted(own_layouts)},
    }
    candidates = _Candidates(
        layouts=layouts,
        functions={name: layout.values(basis) for name, layout in layouts.items()},  # (M, n) on θ
        weights={
            (m.name, name): layout.coefficients(m, basis) for m in scene.materials for name, layout in layouts.items()
        },
        scene_bases=tuple(layout.name for layout in scene_bases),
        own=tuple(sorted(own_layouts)),
    )
    return _plan_for_width(scene, basis, candidates, width)


def _schlick_holds_every_curve(scene: Scene, basis: Basis) -> bool:
    """Whether every material's curve is Schlick's (F0 + (1 − F0)(1 − μ)⁵, or a model with Schlick's
    functions): the two-channel Schlick table is then exact up to the lookup, and the fewest channels."""
    functions = SCHLICK.values(basis)
    return all(np.max(np.abs(functions @ SCHLICK.coefficients(m, basis).T - m.curve)) <= 1e-12 for m in scene.materials)


def lookup_floor(scene: Scene, basis: Basis, width: int) -> dict[str, float]:
    """Per material, max |ΔF̄| of reading its exact F̄ bilinearly between ``width`` columns (at the error grid's
    view cosines, at both ends of its roughness range): what no layout beats with that width."""
    width = check_positive_int("width", width, low=2, high=MAX_SIZE)
    mu_eval = _view_cosines(width)  # the columns are its even entries
    interpolate = _scene_grid(width, 1, (0.0, 0.0), scene.visibility).view_weights(mu_eval)
    floor = {}
    for material in scene.materials:
        exact = (
            texel_weights(
                basis.theta,
                mu_eval[None, :],
                roughness_to_alpha(material.roughness)[:, None],
                visibility=scene.visibility,
            )
            @ material.curve
        )
        floor[material.name] = float(np.max(np.abs(interpolate @ exact[:, ::2] - exact)))
    return floor


@dataclasses.dataclass(frozen=True)
class _Candidates:
    """The candidate layouts, their functions (M, n) on the θ grid and each material's weights per layout
    (None where a layout cannot represent it); the scene bases' and the models' own layouts by name."""

    layouts: dict[str, Layout]
    functions: dict[str, np.ndarray]
    weights: dict[tuple[str, str], np.ndarray | None]
    scene_bases: tuple[str, ...]
    own: tuple[str, ...]


def _view_cosines(width: int) -> np.ndarray:
    """The error grid's view cosines: the ``width`` columns (√μo = i/(W − 1)) and the midpoints in √μo between
    them, μo from 0 to 1: every lookup a GPU makes interpolates between two of the columns."""
    root = np.arange(2 * width - 1) / (2.0 * (width - 1))
    return root * root


def _plan_for_width(scene: Scene, basis: Basis, candidates: _Candidates, width: int) -> ScenePlan:
    """The plan with ``width`` columns: tables, layouts and rows."""
    theta, visibility = basis.theta, scene.visibility
    low = min(m.roughness[0] for m in scene.materials)
    high = max(m.roughness[1] for m in scene.materials)
    mu_eval = _view_cosines(width)
    columns = _scene_grid(width, 1, (0.0, 0.0), visibility)
    mu_columns = columns.mu_o
    grid = np.linspace(low, high, 2 * _EVAL_ROUGHNESS - 1)
    r_eval = {
        m.name: np.unique(np.concatenate([grid[(grid >= m.roughness[0]) & (grid <= m.roughness[1])], m.roughness]))
        for m in scene.materials
    }
    all_r = np.unique(np.concatenate(list(r_eval.values())))
    # rows of the densest candidate, nested: H = 2^k + 1 endpoint-inclusive rows over [low, high], at most the
    # default build's density (scene.size rows over 0–1) whatever the width: wider tables are for μo
    levels = 1 if high == low else max(1, math.ceil(math.log2(max(1.0, scene.size * (high - low)))))
    max_rows = 1 if high == low else 2**levels + 1
    r_rows = np.linspace(low, high, max_rows)
    interp_mu = columns.view_weights(mu_eval)  # (P, W), linear in √μo as a GPU reads the table
    # Every split sum is a linear functional of the curve: the texel weights (…, M) are computed once per
    # texel set and contracted at once with what they act on, so no (…, M) array outlives this block.
    w_eval = texel_weights(
        theta, mu_eval[None, :], roughness_to_alpha(all_r)[:, None], visibility=visibility
    )  # (R, P, M)
    exact_of = {m.name: w_eval[np.searchsorted(all_r, r_eval[m.name])] @ m.curve for m in scene.materials}  # (r, P, 3)
    del w_eval
    functions, weights_of, own = candidates.functions, candidates.weights, candidates.own

    w_rows = texel_weights(
        theta, mu_columns[None, :], roughness_to_alpha(r_rows)[:, None], visibility=visibility
    )  # (H, W, M)
    table_rows = {name: w_rows @ values for name, values in functions.items()}  # the candidate tables (H, W, n)
    del w_rows
    rows_mu = {name: interp_mu @ table for name, table in table_rows.items()}  # (H, P, n): texels read along μo

    def errors_for(
        layout: str, rows: np.ndarray, projected=None, positions=None, views=slice(None)
    ) -> dict[str, float]:
        result = {}
        table_mu = rows_mu[layout][rows] if projected is None else projected  # (H', P, n): texels read along μo
        positions = r_rows[rows] if positions is None else positions
        for material in scene.materials:
            coefficients = weights_of[material.name, layout]
            if coefficients is None:
                result[material.name] = np.inf
                continue
            interp_r = interpolation_weights(r_eval[material.name], positions)  # (r, H')
            approx = np.tensordot(interp_r, table_mu @ coefficients.T, axes=1)  # (r, P, 3)
            result[material.name] = float(np.max(np.abs(approx - exact_of[material.name][:, views])))
        return result

    # the full default build (basis RGBA + Schlick RG on the default grid of scene.size × scene.size texels over
    # 0–1, its ends on texels), for comparison, read at the same error grid
    default_grid = LutGrid(scene.size, scene.size, visibility=visibility)
    default_r = default_grid.roughness
    # only the rows a lookup at the error grid's roughnesses reads: the two around each (one at an edge)
    above = np.searchsorted(default_r, all_r)
    near = np.unique(np.clip(np.concatenate([above - 1, above]), 0, scene.size - 1))
    w_default = texel_weights(
        theta, default_grid.mu_o[None, :], roughness_to_alpha(default_r[near])[:, None], visibility=visibility
    )
    interp_default = default_grid.view_weights(mu_eval)
    default_errors = {
        layout: errors_for(layout, near, interp_default @ (w_default @ functions[layout]), default_r[near])
        for layout in ("schlick", "basis-4")
    }
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
            f"{best[worst]:.3g} with {width} columns; use tolerance >= {best[worst] * 1.01:.3g} (or another model for it)"
            + (f"; also failing: {sorted(set(failing) - {worst})}" if len(failing) > 1 else "")
        )
    # accuracy first: a material that some layout holds to ACCURACY_GOAL is held to it, the rest to the tolerance
    aims = {
        name: min(tolerance, ACCURACY_GOAL) if value <= ACCURACY_GOAL else tolerance for name, value in best.items()
    }
    channels = {name: functions[name].shape[-1] for name in functions}
    # every combination of at most one basis table (generic or the scene's), the Schlick table and the models' own
    options = [
        tuple(x for x in (schlick, basis_table, *extra) if x)
        for schlick in ("", "schlick")
        for basis_table in ("", "basis-2", "basis-3", "basis-4", *candidates.scene_bases)
        for count in range(len(own) + 1)
        for extra in itertools.combinations(own, count)
    ]
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
        scene=scene,
        tables=tables,
        roughness_range=(low, high),
        rows=len(chosen_rows),
        columns=width,
        layouts=layouts,
        coefficients={m.name: weights_of[m.name, layouts[m.name]] for m in scene.materials},
        errors={m.name: chosen_errors[layouts[m.name]][m.name] for m in scene.materials},
        full_errors=full_errors,
        default_build_errors=default_best,
        candidates={name: candidates.layouts[name] for name in tables},
        table_values={name: table_rows[name][chosen_rows] for name in tables},
        aims=aims,
        exact={
            m.name: bool(
                np.max(np.abs(functions[layouts[m.name]] @ weights_of[m.name, layouts[m.name]].T - m.curve)) <= 1e-9
            )
            for m in scene.materials
        },
    )
