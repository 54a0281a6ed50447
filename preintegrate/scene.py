"""Build for a scene: only the channels, roughness rows and tables its materials need.

Public objects: ``SceneError``, ``SceneMaterial``, ``Scene``, ``read_scene``, ``plan_scene``, ``ScenePlan``,
``write_scene``, ``DEFAULT_TOLERANCE``.

A scene file (TOML or JSON) lists materials, each with the roughness range it is used at, and an error
tolerance on F̄ (default 1/255) and a working colour space::

    tolerance = 0.0039          # optional: max |F̄ − F̄_exact| over every material's range, all view angles
    space = "ACEScg"            # optional: colour space of presets
    size = 128                  # optional: LUT columns (μo), as the default build

    [[material]]
    name = "floor"
    preset = "Gold"             # or eta/kappa, reflectivity/edge_tint, f0 (Schlick), f0 + f82,
    roughness = [0.3, 0.6]      # or model = "generalized-adobe" with its parameters
                                # a number, a [low, high] range

**Exact target of a material**: its own model — the spectral RGB curve of a preset (Hoffman's procedure),
the Fresnel equations of (η, κ) or of Gulbrandsen's (r, g), Schlick for ``f0`` alone, Hoffman 2019 for
``f0`` + ``f82``, any model of :data:`basis.approximations.APPROXIMATE_MODELS` for ``model``.

**Candidate layouts** of a material: the Schlick table with F0 = F(0°) (exact for the Schlick family),
the first K basis terms (K = 2, 3, 4) with least-squares coefficients on them (c0 = F0 and
c0 + c1 = F90 kept exact), and, for a material given by a linear model of the references (F0 + F82,
Adobe, generalized Schlick, …), that model's own exact split-sum table (``build --model``; exact while
its clamp is inactive). **Tables**: any combination of the Schlick table, one basis table and the
models' own tables; the one with the fewest channels that lets every material meet the tolerance with
one of its layouts. **Rows**: cropped to the union of the
materials' roughness ranges, endpoint-inclusive (row j ↔ r = r_lo + j (r_hi − r_lo)/(H − 1)), with
the fewest rows H ∈ {2, 3, 5, 9, 17, …} that still meet the tolerance.

**Error** is measured where it matters: at the 2 × size − 1 view cosines of the texel centres and the
midpoints between them (μo from 0.5/size up: below the first centre every engine reads the edge texel,
as with the default build), at the roughnesses of a 33-point grid over the scene's range that fall in
each material's own range (plus its end points), with bilinear, clamp-to-edge
interpolation of the table as a GPU does, against the split sum of the exact target. Every split sum is
a linear functional of the curve, computed with the texel weights of
:func:`preintegrate.studies.model_error.texel_weights`.

References
----------
:cite:`Belcour2020` eq. 5 (F̄ = Σ c_k b̄_k); :cite:`Karis2013` (Schlick split sum).
"""

from __future__ import annotations

import dataclasses
import itertools
import json
import math
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: the same parser as the tomli package (a dependency there)
    import tomli as tomllib

from basis.approximations import approximate_model
from basis.coefficients import coefficients_least_squares_from_table
from basis.eigenbasis import Basis, default_basis
from basis.fresnel import ETA_RANGE, KAPPA_RANGE, _fresnel, cos_theta
from basis.gulbrandsen import gulbrandsen_to_nk
from basis.materials import PRESET_SPACES, material_curve, material_preset
from basis.validation import ParameterError, check_positive_int, check_range

from .channels import model_channels, schlick_channels
from .exr import write_luts
from .studies.model_error import texel_weights
from .table import PIXEL_CONVENTION

__all__ = ["DEFAULT_TOLERANCE", "Scene", "SceneError", "SceneMaterial", "ScenePlan", "plan_scene", "read_scene",
           "write_scene"]

#: One 8-bit step: the default tolerance on F̄.
DEFAULT_TOLERANCE = 1.0 / 255.0
_EVAL_ROUGHNESS = 17
_SCHLICK_FAMILY = ("schlick", "fresnel-blend")


class SceneError(ParameterError):
    """A scene file that cannot be read, or whose tolerance the basis cannot meet."""


@dataclasses.dataclass(frozen=True)
class SceneMaterial:
    """One material of a scene: its exact target curve (M, 3) on the basis grid and its roughness range."""

    name: str
    description: dict
    curve: np.ndarray
    roughness: tuple[float, float]


@dataclasses.dataclass(frozen=True)
class Scene:
    materials: tuple[SceneMaterial, ...]
    tolerance: float
    space: str
    size: int
    source: str


def _rgb(name: str, item: dict, key: str) -> np.ndarray:
    value = np.asarray(item[key], dtype=np.float64) if not isinstance(item[key], str) else None
    if value is None or value.shape not in ((), (3,)):
        raise SceneError(f"material {name!r}: {key} must be a number or 3 numbers (R, G, B), got {item[key]!r}")
    return np.broadcast_to(value, (3,)).copy()


def _target(name: str, item: dict, space: str, basis: Basis) -> tuple[np.ndarray, dict]:
    """(curve (M, 3) on basis.theta, description) of one material entry."""
    mu = cos_theta(basis.theta)[:, None]
    keys = set(item) - {"name", "roughness"}
    if "preset" in item:
        preset = material_preset(item["preset"], space)
        return material_curve(preset["name"], space)(mu[:, 0]), {"preset": preset["name"], "space": space}
    if "model" in item:
        model = approximate_model(item["model"])
        parameters = {key: item[key] for key in keys - {"model"}}
        curve = np.broadcast_to(model.evaluate(mu, **parameters), (mu.shape[0], 3))
        return curve, {"model": model.name, **parameters}
    if keys == {"eta", "kappa"}:
        eta = check_range(f"{name}: eta", _rgb(name, item, "eta"), *ETA_RANGE)
        kappa = check_range(f"{name}: kappa", _rgb(name, item, "kappa"), *KAPPA_RANGE)
        return _fresnel(mu, eta, kappa), {"eta": eta.tolist(), "kappa": kappa.tolist()}
    if keys == {"reflectivity", "edge_tint"}:
        eta, kappa = gulbrandsen_to_nk(_rgb(name, item, "reflectivity"), _rgb(name, item, "edge_tint"))
        description = {"reflectivity": _rgb(name, item, "reflectivity").tolist(), "edge_tint": _rgb(name, item, "edge_tint").tolist()}
        return _fresnel(mu, eta, kappa), description
    if keys == {"f0"}:
        model = approximate_model("schlick")
        return model.evaluate(mu, f0=_rgb(name, item, "f0")), {"model": "schlick", "f0": _rgb(name, item, "f0").tolist()}
    if keys == {"f0", "f82"}:
        model = approximate_model("f82")
        f0, f82 = _rgb(name, item, "f0"), _rgb(name, item, "f82")
        return model.evaluate(mu, f0=f0, f82=f82), {"model": "f82", "f0": f0.tolist(), "f82": f82.tolist()}
    raise SceneError(
        f"material {name!r}: give one of preset; eta and kappa; reflectivity and edge_tint; f0; f0 and f82; "
        f"or model with its parameters (got {sorted(keys)})"
    )


def _roughness(name: str, value) -> tuple[float, float]:
    values = np.atleast_1d(np.asarray(value, dtype=np.float64)) if not isinstance(value, str) else np.array([np.nan])
    if values.ndim != 1 or values.size not in (1, 2):
        raise SceneError(f"material {name!r}: roughness must be a number or [low, high], got {value!r}")
    values = check_range(f"material {name!r}: roughness", values, 0.0, 1.0)
    low, high = float(values.min()), float(values.max())
    if values.size == 2 and values[0] > values[1]:
        raise SceneError(f"material {name!r}: roughness range must be [low, high], got {value!r}")
    return low, high


def read_scene(path, basis: Basis | None = None) -> Scene:
    """Read and validate a TOML or JSON scene file; errors name the file, the material and the key."""
    basis = default_basis() if basis is None else basis
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as error:
        raise SceneError(f"cannot read scene file {path}: {error}") from None
    try:
        document = json.loads(text) if path.suffix.lower() == ".json" else tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as error:
        raise SceneError(f"scene file {path} is not valid {'JSON' if path.suffix.lower() == '.json' else 'TOML'}: {error}") from None
    if not isinstance(document, dict):
        raise SceneError(f"scene file {path}: the top level must be a table")
    unknown = set(document) - {"tolerance", "space", "size", "material"}
    if unknown:
        raise SceneError(f"scene file {path}: unknown keys {sorted(unknown)} (expected tolerance, space, size, material)")
    tolerance = float(check_range("tolerance", document.get("tolerance", DEFAULT_TOLERANCE), 1e-7, 1.0))
    space = document.get("space", "ACEScg")
    if space not in PRESET_SPACES:
        raise SceneError(f"scene file {path}: space must be one of {list(PRESET_SPACES)}, got {space!r}")
    size = check_positive_int("size", document.get("size", 128), low=2, high=8192)
    entries = document.get("material")
    if not isinstance(entries, list) or not entries:
        raise SceneError(f"scene file {path}: needs at least one [[material]]")
    materials, names = [], set()
    for index, item in enumerate(entries):
        if not isinstance(item, dict):
            raise SceneError(f"scene file {path}: material {index} must be a table")
        name = str(item.get("name", f"material{index}"))
        if name in names:
            raise SceneError(f"scene file {path}: material name {name!r} appears twice")
        names.add(name)
        if "roughness" not in item:
            raise SceneError(f"material {name!r}: roughness (a number or [low, high]) is missing")
        try:
            curve, description = _target(name, item, space, basis)
        except SceneError:
            raise
        except ParameterError as error:
            raise SceneError(f"material {name!r}: {error}") from None
        materials.append(SceneMaterial(name, description, np.asarray(curve, dtype=np.float64),
                                       _roughness(name, item["roughness"])))
    return Scene(tuple(materials), tolerance, space, size, str(path))


def _own_layout(material: SceneMaterial) -> str | None:
    """``model:NAME[:shape=value,…]`` for a material given by a linear model of the references other
    than Schlick's (whose own table is the Schlick table), else None."""
    name = material.description.get("model")
    if name is None or name in _SCHLICK_FAMILY or not approximate_model(name).linear:
        return None
    model = approximate_model(name)
    shape = ",".join(f"{key}={float(material.description.get(key, p.default))!r}"
                     for key, p in ((p.name, p) for p in model.parameters) if key in model.shape)
    return f"model:{name}" + (f":{shape}" if shape else "")


def _own_model(layout: str) -> tuple[str, dict]:
    parts = layout.split(":")
    shape = dict(item.split("=") for item in parts[2].split(",")) if len(parts) > 2 else {}
    return parts[1], {key: float(value) for key, value in shape.items()}


def _own_functions(layout: str):
    name, shape = _own_model(layout)
    return approximate_model(name).channel_functions(**shape)


def _layout_coefficients(material: SceneMaterial, layout: str, basis: Basis) -> np.ndarray | None:
    """(3, n) weights of a layout: Schlick (F0, 1), the first K basis terms by least squares, or a
    linear model's own weights (NaN for a material of another model: not a candidate)."""
    if layout.startswith("model:"):
        if _own_layout(material) != layout:
            return None  # another model's table: not a candidate for this material
        name, _ = _own_model(layout)
        parameters = {key: value for key, value in material.description.items() if key != "model"}
        weights = np.asarray(approximate_model(name).channel_weights(**parameters), dtype=np.float64)
        return np.broadcast_to(weights, (3, weights.shape[-1])).copy()
    if layout == "schlick":
        f0 = material.curve[0]
        return np.stack([f0, np.ones(3)], axis=-1)
    terms = int(layout.split("-")[1])
    truncated = Basis(basis.theta, basis.curves[:terms], basis.fit_angles[:terms]) if terms < basis.n_terms else basis
    if terms == 2:
        return np.stack([material.curve[0], material.curve[-1] - material.curve[0]], axis=-1)
    return coefficients_least_squares_from_table(basis.theta, material.curve.T, truncated)


def _interpolation(points: np.ndarray, centres: np.ndarray) -> np.ndarray:
    """(P, N) weights of linear, clamp-to-edge interpolation from samples at ``centres`` (increasing)."""
    weights = np.zeros((points.size, centres.size))
    if centres.size == 1:
        weights[:, 0] = 1.0
        return weights
    position = np.clip(np.interp(points, centres, np.arange(centres.size)), 0.0, centres.size - 1.0)
    low = np.minimum(np.floor(position).astype(int), centres.size - 2)
    fraction = position - low
    rows = np.arange(points.size)
    weights[rows, low] = 1.0 - fraction
    weights[rows, low + 1] += fraction
    return weights


@dataclasses.dataclass
class ScenePlan:
    """What :func:`plan_scene` decided, with every material's achieved error."""

    scene: Scene
    tables: tuple[str, ...]  # "schlick" and/or "basis-K"
    roughness_range: tuple[float, float]
    rows: int
    layouts: dict[str, str]
    coefficients: dict[str, np.ndarray]
    errors: dict[str, float]
    full_errors: dict[str, dict[str, float]]
    default_build_errors: dict[str, float]


def plan_scene(scene: Scene, basis: Basis | None = None) -> ScenePlan:
    """Choose tables, layouts and rows (module docstring); raises :class:`SceneError` if a material cannot
    meet the tolerance with any layout, naming it and the smallest tolerance that would do."""
    basis = default_basis() if basis is None else basis
    theta = basis.theta
    low = min(m.roughness[0] for m in scene.materials)
    high = max(m.roughness[1] for m in scene.materials)
    # view cosines: the texel centres and the midpoints between them, μo ∈ [0.5/W, 1 − 0.5/W]; below the
    # first centre every engine reads the edge texel (clamped NdotV), as the default build does
    mu_eval = (np.arange(2 * scene.size - 1) + 1.0) / (2 * scene.size)
    mu_columns = (np.arange(scene.size) + 0.5) / scene.size
    grid = np.linspace(low, high, 2 * _EVAL_ROUGHNESS - 1)
    r_eval = {m.name: np.unique(np.concatenate([grid[(grid >= m.roughness[0]) & (grid <= m.roughness[1])], m.roughness]))
              for m in scene.materials}
    all_r = np.unique(np.concatenate(list(r_eval.values())))
    w_eval = texel_weights(theta, mu_eval[None, :], (all_r**2)[:, None])  # (R, P, M)
    # rows of the densest candidate, nested: H = 2^k + 1 endpoint-inclusive rows over [low, high]
    levels = 1 if high == low else max(1, math.ceil(math.log2(max(1.0, scene.size * (high - low)))))
    max_rows = 1 if high == low else 2**levels + 1
    r_rows = np.linspace(low, high, max_rows)
    w_rows = texel_weights(theta, mu_columns[None, :], (r_rows**2)[:, None])  # (H, W, M)
    interp_mu = _interpolation(mu_eval, mu_columns)  # (P, W)
    w_rows_mu = np.einsum("pw,hwm->hpm", interp_mu, w_rows)  # table texels interpolated along μo
    functions = {"schlick": schlick_channels().functions(cos_theta(theta)), **{f"basis-{k}": basis.curves[:k].T for k in (2, 3, 4)}}
    own = sorted({layout for layout in map(_own_layout, scene.materials) if layout is not None})
    functions.update({layout: _own_functions(layout)(cos_theta(theta)) for layout in own})

    # each material's weights per layout, once: the error loops below reuse them for every row count
    weights_of = {(m.name, layout): _layout_coefficients(m, layout, basis) for m in scene.materials for layout in functions}

    def errors_for(layout: str, rows: np.ndarray, weights=None, positions=None) -> dict[str, float]:
        result = {}
        weights_rows = w_rows_mu[rows] if weights is None else weights  # (H', P, M)
        positions = r_rows[rows] if positions is None else positions
        for material in scene.materials:
            r_index = np.searchsorted(all_r, r_eval[material.name])
            exact = w_eval[r_index] @ material.curve  # (r, P, 3)
            interp_r = _interpolation(r_eval[material.name], positions)  # (r, H')
            coefficients = weights_of[material.name, layout]
            if coefficients is None:
                result[material.name] = np.inf
                continue
            approx_curve = functions[layout] @ coefficients.T  # (M, 3)
            approx = np.einsum("rh,hpc->rpc", interp_r, weights_rows @ approx_curve)
            result[material.name] = float(np.max(np.abs(approx - exact)))
        return result

    # the full default build (basis RGBA + Schlick RG, rows at (j + 0.5)/size over 0–1), for comparison
    default_r = (np.arange(scene.size) + 0.5) / scene.size
    near = np.flatnonzero((default_r >= low - 1.0 / scene.size) & (default_r <= high + 1.0 / scene.size))
    w_default = np.einsum("pw,hwm->hpm", interp_mu,
                          texel_weights(theta, mu_columns[None, :], (default_r[near] ** 2)[:, None]))
    default_errors = {layout: errors_for(layout, near, w_default, default_r[near]) for layout in ("schlick", "basis-4")}
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
    channels = {"schlick": 2, "basis-2": 2, "basis-3": 3, "basis-4": 4,
                **{layout: functions[layout].shape[-1] for layout in own}}
    # every combination of at most one basis table, the Schlick table and the models' own tables
    options = [tuple(x for x in (schlick, basis_table, *extra) if x)
               for schlick in ("", "schlick") for basis_table in ("", "basis-2", "basis-3", "basis-4")
               for count in range(len(own) + 1) for extra in itertools.combinations(own, count)]
    options = [option for option in options if option]

    def assign(tables, errors) -> dict[str, str] | None:
        layouts = {}
        for material in scene.materials:
            fitting = [t for t in tables if errors[t][material.name] <= tolerance]
            if not fitting:
                return None
            layouts[material.name] = min(fitting, key=lambda t: errors[t][material.name])
        return layouts

    feasible = [tables for tables in options if assign(tables, full_errors) is not None]
    tables = min(feasible, key=lambda t: (sum(channels[x] for x in t), len(t)))
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
    )


def _table(functions: np.ndarray, plan: ScenePlan, basis: Basis) -> np.ndarray:
    low, high = plan.roughness_range
    rows = np.linspace(low, high, plan.rows) if plan.rows > 1 else np.array([low])
    mu_columns = (np.arange(plan.scene.size) + 0.5) / plan.scene.size
    weights = texel_weights(basis.theta, mu_columns[None, :], (rows**2)[:, None])
    return weights @ functions


def write_scene(plan: ScenePlan, out, basis: Basis | None = None, reference_folder=None) -> dict:
    """Write the plan's tables, ``scene_coefficients.json`` and ``scene_report.md`` into ``out``.

    ``reference_folder`` holds the full default build to compare sizes with (default: the shipped luts).
    """
    basis = default_basis() if basis is None else basis
    out = Path(out)
    low, high = plan.roughness_range
    rows_text = (
        f"row j <-> perceptual roughness r = {low:.6g} + j * ({high:.6g} - {low:.6g}) / (height - 1) (rows at the "
        f"range's end points; engine: v = ((r - {low:.6g}) / ({high:.6g} - {low:.6g}) * (height - 1) + 0.5) / height)"
        if plan.rows > 1 else f"one row, at perceptual roughness r = {low:.6g} (engine: v = 0.5)"
    )
    convention = PIXEL_CONVENTION.replace("row j <-> perceptual roughness r = (j + 0.5) / height", rows_text)
    items, names = [], {}
    for table in plan.tables:
        if table == "schlick":
            values = _table(schlick_channels().functions(cos_theta(basis.theta)), plan, basis)
            path, channel_names, combination = out / "ggx_schlick_rg.exr", ("R", "G"), "Fbar = F0 * R + G"
        elif table.startswith("model:"):
            name, shape = _own_model(table)
            channel_set_ = model_channels(name, **shape)
            values = _table(_own_functions(table)(cos_theta(basis.theta)), plan, basis)
            channel_names, combination = channel_set_.channel_names, channel_set_.combination
            suffix = "".join(f"_{key}{value:g}" for key, value in shape.items())
            path = out / f"ggx_{name}{suffix}.exr"
        else:
            terms = int(table.split("-")[1])
            values = _table(basis.curves[:terms].T, plan, basis)
            channel_names = ("R", "G", "B", "A")[:terms]
            path = out / f"ggx_basis_{''.join(channel_names).lower()}.exr"
            combination = "Fbar = " + " + ".join(f"c{k} * {name}" for k, name in enumerate(channel_names))
        names[table] = path.name
        items.append((path, values, channel_names, {
            "convention": convention, "roughness_range": f"{low:.9g},{high:.9g}", "width": str(plan.scene.size),
            "height": str(plan.rows), "channel_set": table, "channels": ",".join(channel_names),
            "combination": combination, "basis_hash": basis.content_hash,
            "generator": f"fresnel-basis 0.1.0 (fresnel-lut scene {Path(plan.scene.source).name})",
        }))
    materials = {
        material.name: {
            "target": material.description,
            "roughness": list(material.roughness),
            "layout": plan.layouts[material.name],
            "lut": names[plan.layouts[material.name]],
            "coefficients": plan.coefficients[material.name].tolist(),
            "max_abs_error_fbar": plan.errors[material.name],
            "max_abs_error_fbar_full_default_build": plan.default_build_errors[material.name],
        }
        for material in plan.scene.materials
    }
    document = {
        "scene": Path(plan.scene.source).name, "basis_hash": basis.content_hash, "tolerance": plan.scene.tolerance,
        "space": plan.scene.space, "roughness_range": [low, high], "rows": plan.rows, "columns": plan.scene.size,
        "layout": "coefficients[channel R,G,B][LUT channel]: Fbar = sum_k coefficients[c][k] * LUT_k",
        "materials": materials,
    }
    # the tables, the coefficients and the report are renamed into place together (or not at all); the
    # report quotes the tables' sizes, so the tables are encoded once to measure them
    sizes_folder = Path(tempfile.mkdtemp(prefix=".scene-", dir=out)) if out.exists() else None
    if sizes_folder is None:
        out.mkdir(parents=True)
        sizes_folder = Path(tempfile.mkdtemp(prefix=".scene-", dir=out))
    try:
        measured = write_luts([(sizes_folder / Path(path).name, *rest) for path, *rest in items])
        written = {path.name: path.stat().st_size for path in measured}
    finally:
        shutil.rmtree(sizes_folder, ignore_errors=True)
    reference_folder = Path(__file__).resolve().parent.parent / "luts" if reference_folder is None else Path(reference_folder)
    full = {name: (reference_folder / name).stat().st_size for name in ("ggx_basis_rgba.exr", "ggx_schlick_rg.exr")
            if (reference_folder / name).exists()}
    left_out = [name for name in ("schlick", "basis-4") if name not in plan.tables]
    report = [
        f"# Scene build: {Path(plan.scene.source).name}", "",
        (f"Tolerance {plan.scene.tolerance:.4g} on Fbar (max over each material's roughness range and all view "
         f"angles, bilinear lookup), space {plan.scene.space}, basis {basis.content_hash}."), "",
        ("| material | roughness | layout | max abs error of Fbar | full default build | "
         "error with Schlick, basis 2, 3, 4 terms (all rows) |"),
        "|---|---|---|---|---|---|",
        *[f"| {m.name} | {m.roughness[0]:g}–{m.roughness[1]:g} | {plan.layouts[m.name]} | {plan.errors[m.name]:.2e} | "
          f"{plan.default_build_errors[m.name]:.2e} | "
          + ", ".join(f"{plan.full_errors[layout][m.name]:.1e}" for layout in ("schlick", "basis-2", "basis-3", "basis-4"))
          + " |" for m in plan.scene.materials],
        "",
        (f"Tables: {', '.join(f'{names[t]} ({t})' for t in plan.tables)}; {plan.rows} rows over roughness "
         f"{low:g}–{high:g} (the default build: {plan.scene.size} rows over 0–1), {plan.scene.size} columns."),
        f"Left out: {', '.join(left_out) if left_out else 'no table'}"
        + ("" if "basis-4" in plan.tables or not any(t.startswith("basis") for t in plan.tables)
           else f" (basis terms beyond {plan.tables[-1].split('-')[1]})") + ".",
        (f"Bytes: {sum(written.values()):,} written against {sum(full.values()):,} for the full default build "
         f"({100.0 * (1.0 - sum(written.values()) / max(1, sum(full.values()))):.1f} % saved)."),
    ]
    coefficients_path, report_path = out / "scene_coefficients.json", out / "scene_report.md"
    paths = write_luts(items, texts=[(coefficients_path, json.dumps(document, indent=1) + "\n"),
                                     (report_path, "\n".join(report) + "\n")])
    return {"tables": paths, "coefficients": coefficients_path, "report": report_path, "bytes": written,
            "full_bytes": full, "text": "\n".join(report)}
