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
from basis.validation import ParameterError, check_positive_int, check_range

__all__ = ["DEFAULT_TOLERANCE", "Scene", "SceneError", "SceneMaterial", "read_scene"]

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
        from basis.material_fits import material_curve  # colour-science, only for presets

        return material_curve(preset["name"], space)(mu[:, 0]), {"preset": preset["name"], "space": space}
    if "model" in item:
        model = fresnel_model(item["model"])
        parameters = {key: item[key] for key in keys - {"model"}}
        curve = np.broadcast_to(model.evaluate(mu, **parameters), (mu.shape[0], 3))
        return curve, {"model": model.name, **parameters}
    if keys == {"eta", "kappa"}:
        eta = check_range(f"{name}: eta", _rgb(name, item, "eta"), *ETA_RANGE)
        kappa = check_range(f"{name}: kappa", _rgb(name, item, "kappa"), *KAPPA_RANGE)
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
    basis = resolve_basis(basis)
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
