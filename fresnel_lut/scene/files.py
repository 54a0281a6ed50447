"""Scene files (TOML or JSON): read and validate a scene's materials, roughness ranges and tolerance.

Public objects: ``SceneError``, ``SceneMaterial``, ``Scene``, ``read_scene``, ``DEFAULT_TOLERANCE``.
"""

from __future__ import annotations

import dataclasses
import json
import sys
from pathlib import Path

import numpy as np

if sys.version_info >= (3, 11):
    import tomllib
else:  # Python 3.10: the same parser as the tomli package (a dependency there)
    import tomli as tomllib

from basis.angles import cos_theta
from basis.eigenbasis import Basis, resolve_basis
from basis.fresnel import ETA_RANGE, KAPPA_RANGE, fresnel_kernel
from basis.gulbrandsen import gulbrandsen_to_nk
from basis.models import fresnel_model
from basis.presets import PRESET_SPACES, material_preset
from basis.validation import ParameterError, check_choice, check_positive_int, check_range

__all__ = ["DEFAULT_TOLERANCE", "Scene", "SceneError", "SceneMaterial", "read_scene"]

#: Largest scene LUT width: the plan's texel weights grow as size² × 512 × 8 bytes (about 0.4 GB at 256).
MAX_SIZE = 256
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


#: Largest scene file read: a scene lists a few dozen materials; a device or a huge file is refused unread.
MAX_SCENE_BYTES = 1 << 20


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _describe(value) -> str:
    kind = {str: "text", bool: "a boolean", dict: "a table", list: "a list"}.get(type(value), type(value).__name__)
    return f"{str(value)[:40]!r} ({kind})"


def _rgb(name: str, item: dict, key: str) -> np.ndarray:
    value = item[key]
    if _is_number(value):
        return np.full(3, float(value))
    if isinstance(value, list) and len(value) == 3 and all(_is_number(element) for element in value):
        return np.array(value, dtype=np.float64)
    raise SceneError(f"material {name!r}: {key} must be a number or 3 numbers (R, G, B), got {_describe(value)}")


def _target(name: str, item: dict, space: str, basis: Basis) -> tuple[np.ndarray, dict]:
    """(curve (M, 3) on basis.theta, description) of one material entry."""
    mu = cos_theta(basis.theta)[:, None]
    keys = set(item) - {"name", "roughness"}
    if "preset" in item:
        if not isinstance(item["preset"], str):
            raise SceneError(f"material {name!r}: preset must be a material's name (text), got {_describe(item['preset'])}")
        preset = material_preset(item["preset"], space)
        from basis.material_fits import material_curve  # colour-science, only for presets

        return material_curve(preset["name"], space)(mu[:, 0]), {"preset": preset["name"], "space": space}
    if "model" in item:
        if not isinstance(item["model"], str):
            raise SceneError(f"material {name!r}: model must be a model's name (text), got {_describe(item['model'])}")
        model = fresnel_model(item["model"])
        parameters = {key: item[key] for key in item if key in keys - {"model"}}  # the file's order, not a set's
        for key, value in parameters.items():
            if not (_is_number(value) or isinstance(value, list) and all(_is_number(element) for element in value)):
                raise SceneError(f"material {name!r}: {key} must be a number or 3 numbers (R, G, B), got {_describe(value)}")
        curve = np.broadcast_to(model.evaluate(mu, **parameters), (mu.shape[0], 3))
        return curve, {"model": model.name, **parameters}
    if keys == {"eta", "kappa"}:
        eta = check_range("eta", _rgb(name, item, "eta"), *ETA_RANGE)
        kappa = check_range("kappa", _rgb(name, item, "kappa"), *KAPPA_RANGE)
        return fresnel_kernel(mu, eta, kappa), {"eta": eta.tolist(), "kappa": kappa.tolist()}
    if keys == {"reflectivity", "edge_tint"}:
        eta, kappa = gulbrandsen_to_nk(_rgb(name, item, "reflectivity"), _rgb(name, item, "edge_tint"))
        description = {"reflectivity": _rgb(name, item, "reflectivity").tolist(), "edge_tint": _rgb(name, item, "edge_tint").tolist()}
        return fresnel_kernel(mu, eta, kappa), description
    if keys == {"f0"}:
        model = fresnel_model("schlick")
        return model.evaluate(mu, f0=_rgb(name, item, "f0")), {"model": "schlick", "f0": _rgb(name, item, "f0").tolist()}
    if keys == {"f0", "f82"}:
        model = fresnel_model("f82")
        f0, f82 = _rgb(name, item, "f0"), _rgb(name, item, "f82")
        return model.evaluate(mu, f0=f0, f82=f82), {"model": "f82", "f0": f0.tolist(), "f82": f82.tolist()}
    raise SceneError(
        f"material {name!r}: give one of preset; eta and kappa; reflectivity and edge_tint; f0; f0 and f82; "
        f"or model with its parameters (got {sorted(keys)})"
    )


def _roughness(name: str, value) -> tuple[float, float]:
    if _is_number(value):
        values = np.array([float(value)])
    elif isinstance(value, list) and len(value) == 2 and all(_is_number(element) for element in value):
        values = np.array(value, dtype=np.float64)
    else:
        raise SceneError(f"material {name!r}: roughness must be a number or [low, high] of numbers, got {_describe(value)}")
    values = check_range(f"material {name!r}: roughness", values, 0.0, 1.0)
    if values.size == 2 and values[0] > values[1]:
        raise SceneError(f"material {name!r}: roughness range must be [low, high], got {value!r}")
    return float(values.min()), float(values.max())


def _read_text(path: Path) -> str:
    """The file's text, refusing what is no scene file: a folder, a device that never ends, more than 1 MiB."""
    try:
        with open(path, "rb") as stream:
            data = stream.read(MAX_SCENE_BYTES + 1)
    except OSError as error:
        raise SceneError(f"cannot read scene file {path}: {error.strerror or error}") from None
    if len(data) > MAX_SCENE_BYTES:
        raise SceneError(f"scene file {path} is larger than {MAX_SCENE_BYTES // 1024} KiB: not a scene file")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        raise SceneError(f"scene file {path} is not UTF-8 text: {error}") from None


def _name(index: int, item: dict) -> str:
    name = item.get("name", f"material{index}")
    if not isinstance(name, str) or not name or len(name) > 100 or not name.isprintable():
        raise SceneError(f"material {index}: name must be printable text of 1 to 100 characters, got {_describe(name)}")
    return name


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
        document = json.loads(text) if path.suffix.lower() == ".json" else tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as error:
        raise SceneError(f"scene file {path} is not valid {'JSON' if path.suffix.lower() == '.json' else 'TOML'}: {error}") from None
    if not isinstance(document, dict):
        raise SceneError(f"scene file {path}: the top level must be a table")
    unknown = set(document) - {"tolerance", "space", "size", "material"}
    if unknown:
        raise SceneError(f"scene file {path}: unknown keys {sorted(unknown)} (expected tolerance, space, size, material)")
    tolerance = document.get("tolerance", DEFAULT_TOLERANCE)
    if not _is_number(tolerance):
        raise SceneError(f"tolerance must be a number, got {_describe(tolerance)}")
    tolerance = float(check_range("tolerance", tolerance, 1e-7, 1.0))
    space = document.get("space", "ACEScg")
    check_choice(f"scene file {path}: space", space, PRESET_SPACES, error=SceneError)
    size = check_positive_int("size", document.get("size", 128), low=2)
    if size > MAX_SIZE:
        raise SceneError(f"size {size}: a scene table has at most {MAX_SIZE} columns (planning holds about "
                         f"size² × 512 texel weights, 0.4 GB at {MAX_SIZE}); build larger tables with fresnel-lut build")
    entries = document.get("material")
    if not isinstance(entries, list) or not entries:
        raise SceneError(f"scene file {path}: needs at least one [[material]]")
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
            curve, description = _target(name, item, space, basis)
        except SceneError:
            raise
        except (ParameterError, TypeError, ValueError) as error:  # a model's own check names the parameter
            raise SceneError(f"material {name!r}: {error}") from None
        materials.append(SceneMaterial(name, description, np.asarray(curve, dtype=np.float64),
                                       _roughness(name, item["roughness"])))
    return Scene(tuple(materials), tolerance, space, size, str(path), size_fixed="size" in document)
