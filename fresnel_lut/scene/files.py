"""Scene files (TOML or JSON): read and validate a scene's materials, roughness ranges and tolerance.

Public objects: ``SceneError``, ``SceneMaterial``, ``Scene``, ``read_scene``, ``DEFAULT_TOLERANCE``.
"""

from __future__ import annotations

import dataclasses
import json
import sys
import unicodedata
from pathlib import Path

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: the same parser as the tomli package (a dependency there)
    import tomli as tomllib

from basis.angles import cos_theta
from basis.eigenbasis import Basis, resolve_basis
from basis.materials import material_from_mapping
from basis.presets import PRESET_SPACES
from basis.storage import MAX_NESTING, DuplicateKeyError, nesting_depth, parse_json, read_regular_file
from basis.validation import ParameterError, check_choice, check_positive_int, check_range
from preintegrate.ggx import VISIBILITIES

__all__ = ["DEFAULT_TOLERANCE", "Scene", "SceneError", "SceneMaterial", "read_scene"]

#: Largest scene LUT width: the plan's texel weights grow as size² × 512 × 8 bytes (about 0.4 GB at 256).
MAX_SIZE = 256
#: Most materials one scene plans: every material adds its texel weights and curves to the plan (3,000 took 192 s
#: and 880 MiB); a scene of a few dozen takes seconds.
MAX_MATERIALS = 256
#: Narrowest roughness range of a material (a wider one than 0 but narrower than this is one roughness: its table's
#: row mapping, 1 / (high - low), would pass float32's range).
MIN_ROUGHNESS_SPAN = 1e-6
#: One 8-bit step: the default tolerance on F̄.
DEFAULT_TOLERANCE = 1.0 / 255.0


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
    size: int  # columns (μo) of the scene's tables, or the first width the plan tries when not size_fixed
    source: str
    size_fixed: bool = True  # False when the scene file leaves ``size`` to the plan
    visibility: str = "height-correlated"  # the engine's masking-shadowing form (preintegrate.ggx.VISIBILITIES)
    visibility_stated: bool = False  # whether the scene file says its visibility (the command line must agree)


#: Largest scene file read: a scene lists a few dozen materials; a device or a huge file is refused unread.
MAX_SCENE_BYTES = 1 << 20


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _describe(value) -> str:
    kind = {str: "text", bool: "a boolean", dict: "a table", list: "a list"}.get(type(value), type(value).__name__)
    return f"{str(value)[:40]!r} ({kind})"


def _target(item: dict, space: str, basis: Basis) -> tuple[np.ndarray, dict]:
    """(curve (M, 3) on basis.theta, description) of one material entry (:func:`basis.materials.material_from_mapping`;
    the description is :meth:`basis.materials.Material.described`, the record ``fresnel-lut coeffs`` gives)."""
    material = material_from_mapping({key: item[key] for key in item if key not in ("name", "roughness")}, space)
    description = material.described()  # what coeffs reports of it: a preset's space, F0 and source, (r, g)'s (η, κ)
    return material.curve(cos_theta(basis.theta)), description


def _roughness(name: str, value) -> tuple[float, float]:
    if _is_number(value):
        values = np.array([float(value)])
    elif isinstance(value, list) and len(value) == 2 and all(_is_number(element) for element in value):
        values = np.array(value, dtype=np.float64)
    else:
        raise SceneError(
            f"material {name!r}: roughness must be a number or [low, high] of numbers, got {_describe(value)}"
        )
    values = check_range(f"material {name!r}: roughness", values, 0.0, 1.0)
    if values.size == 2 and values[0] > values[1]:
        raise SceneError(f"material {name!r}: roughness range must be [low, high], got {value!r}")
    if values.size == 2 and 0.0 < values[1] - values[0] < MIN_ROUGHNESS_SPAN:
        raise SceneError(
            f"material {name!r}: roughness range {value!r} is narrower than {MIN_ROUGHNESS_SPAN:g}: give one "
            "roughness (a number) or a range at least that wide"
        )
    return float(values.min()), float(values.max())


def _read_text(path: Path) -> str:
    """The file's text, refusing what is no scene file: a folder, a FIFO, a device, more than 1 MiB."""
    data = read_regular_file(path, "scene file", MAX_SCENE_BYTES, SceneError)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise SceneError(f"scene file {path} is not UTF-8 text: {error}") from None


def _name(index: int, item: dict) -> str:
    name = item.get("name", f"material{index}")
    if not isinstance(name, str) or not name or len(name) > 100 or not name.isprintable():
        raise SceneError(f"material {index}: name must be printable text of 1 to 100 characters, got {_describe(name)}")
    return unicodedata.normalize("NFC", name)  # one material, however the editor composed its accents


def read_scene(path, basis: Basis | None = None) -> Scene:
    """Read and validate a TOML or JSON scene file; errors name the file, the material and the key."""
    basis = resolve_basis(basis)
    path = Path(path)
    try:
        return _read_scene(path, _read_text(path), basis)
    except ParameterError as error:  # SceneError or a checked value's own error: one line naming the file
        message = str(error)
        raise SceneError(message if str(path) in message else f"scene file {path}: {message}") from None


def _read_scene(path: Path, text: str, basis: Basis) -> Scene:
    try:
        document = parse_json(text) if path.suffix.lower() == ".json" else tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError, DuplicateKeyError) as error:
        raise SceneError(
            f"scene file {path} is not valid {'JSON' if path.suffix.lower() == '.json' else 'TOML'}: {error}"
        ) from None
    except RecursionError:
        raise SceneError(f"scene file {path} is nested deeper than Python's parser allows") from None
    if nesting_depth(document) > MAX_NESTING:
        raise SceneError(f"scene file {path} is nested deeper than {MAX_NESTING} levels (a scene has 4)")
    if not isinstance(document, dict):
        raise SceneError(f"scene file {path}: the top level must be a table")
    unknown = set(document) - {"tolerance", "space", "size", "visibility", "material"}
    if unknown:
        raise SceneError(
            f"scene file {path}: unknown keys {sorted(unknown)} (expected tolerance, space, size, visibility, material)"
        )
    visibility = check_choice(
        f"scene file {path}: visibility",
        document.get("visibility", "height-correlated"),
        list(VISIBILITIES),
        error=SceneError,
    )
    tolerance = document.get("tolerance", DEFAULT_TOLERANCE)
    if not _is_number(tolerance):
        raise SceneError(f"tolerance must be a number, got {_describe(tolerance)}")
    tolerance = float(check_range("tolerance", tolerance, 1e-7, 1.0))
    space = document.get("space", "ACEScg")
    check_choice(f"scene file {path}: space", space, PRESET_SPACES, error=SceneError)
    size = check_positive_int("size", document.get("size", 128), low=2)
    if size > MAX_SIZE:
        raise SceneError(
            f"size {size}: a scene table has at most {MAX_SIZE} columns (planning holds about "
            f"size² × 512 texel weights, 0.4 GB at {MAX_SIZE}); build larger tables with fresnel-lut build"
        )
    entries = document.get("material")
    if not isinstance(entries, list) or not entries:
        raise SceneError(f"scene file {path}: needs at least one [[material]]")
    if len(entries) > MAX_MATERIALS:
        raise SceneError(
            f"scene file {path}: {len(entries)} materials; a scene build plans at most {MAX_MATERIALS} "
            "(planning time and memory grow with each: split the scene)"
        )
    materials, names = [], set()
    for index, item in enumerate(entries):
        if not isinstance(item, dict):
            raise SceneError(f"scene file {path}: material {index} must be a table")
        name = _name(index, item)
        if name in names:
            raise SceneError(f"scene file {path}: material name {name!r} appears twice")
        names.add(name)
        if "roughness" not in item:
            raise SceneError(f"material {name!r}: roughness (a number or [low, high]) is missing")
        try:
            curve, description = _target(item, space, basis)
        except SceneError:
            raise
        except (ParameterError, TypeError, ValueError) as error:  # a model's own check names the parameter
            raise SceneError(f"material {name!r}: {error}") from None
        materials.append(
            SceneMaterial(name, description, np.asarray(curve, dtype=np.float64), _roughness(name, item["roughness"]))
        )
    low, high = min(m.roughness[0] for m in materials), max(m.roughness[1] for m in materials)
    if 0.0 < high - low < MIN_ROUGHNESS_SPAN:
        raise SceneError(
            f"scene file {path}: the materials' roughnesses span {low:g} to {high:g}, narrower than "
            f"{MIN_ROUGHNESS_SPAN:g} but not one roughness: give them one roughness, or a span at least that wide"
        )
    return Scene(
        tuple(materials),
        tolerance,
        space,
        size,
        str(path),
        size_fixed="size" in document,
        visibility=visibility,
        visibility_stated="visibility" in document,
    )
