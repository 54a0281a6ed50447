"""The shipped presets of measured materials (``luts/materials.json``): basis coefficients and their errors.

Public objects: ``PRESET_SPACES``, ``PresetFileError``, ``shipped_presets_path``, ``write_presets``,
``material_presets``, ``material_preset``, ``material_coefficients``.

Reading a preset loads no colour science: the coefficients were fitted once by
:func:`basis.material_fits.build_presets` (``fresnel-lut materials --presets``) and are tied to the basis
by its content hash. Fitting afresh for another basis imports :mod:`basis.material_fits` when asked.

References
----------
:cite:`Hoffman2020` SIGGRAPH 2020 course notes, ΔE2000 tables and "Computing RGB Parameter Values From
    Spectral IOR Data".
"""

from __future__ import annotations

import functools
from pathlib import Path

import numpy as np

from .eigenbasis import Basis, default_basis
from .storage import read_json_document, shipped_path, write_json
from .validation import ParameterError

__all__ = [
    "FORMAT",
    "PRESET_SPACES",
    "PresetFileError",
    "VERSION",
    "material_coefficients",
    "material_preset",
    "material_presets",
    "shipped_presets_path",
    "write_presets",
]

#: Working spaces the presets are written for.
PRESET_SPACES = ("ACEScg", "sRGB")

FORMAT = "fresnel-basis/material-presets"
VERSION = 1


class PresetFileError(ParameterError):
    """``luts/materials.json`` is missing, malformed or made for another basis."""


def shipped_presets_path() -> Path:
    """``luts/materials.json`` beside the package."""
    return shipped_path("materials.json")


def write_presets(document: dict, path=None) -> Path:
    """Write :func:`build_presets`' document atomically (default: the shipped file)."""
    target = shipped_presets_path() if path is None else Path(path)
    written = write_json(target, document)
    _read.cache_clear()
    return written


@functools.cache
def _read(path: str) -> dict:
    return read_json_document(path, "material presets", FORMAT, VERSION, error=PresetFileError)


def material_presets(path=None) -> dict:
    """The presets document (default: the shipped ``luts/materials.json``)."""
    return _read(str(shipped_presets_path() if path is None else Path(path)))


def material_preset(name: str, space: str = "ACEScg", path=None) -> dict:
    """One material's preset in ``space``: ``f0``, ``f82``, ``coefficients`` (3, K), errors, ``source``.

    Examples
    --------
    >>> material_preset("Gold")["coefficients"].shape
    (3, 4)
    """
    document = material_presets(path)
    if space not in PRESET_SPACES:
        raise ParameterError(f"colour space must be one of {list(PRESET_SPACES)}, got {space!r}")
    materials = document["materials"]
    if name not in materials:
        by_case = {key.lower(): key for key in materials}
        if not isinstance(name, str) or name.lower() not in by_case:
            raise ParameterError(f"material must be one of {list(materials)}, got {name!r}")
        name = by_case[name.lower()]
    entry = materials[name][space]
    return {
        "name": name,
        "space": space,
        "kind": materials[name]["kind"],
        "source": materials[name]["source"],
        "basis_hash": document["basis_hash"],
        "f0": np.array(entry["f0"]),
        "f82": np.array(entry["f82"]),
        "coefficients": np.array(entry["coefficients"]),
        "rms_delta_e2000": dict(entry["rms_delta_e2000"]),
        "delta_e2000_at_0": entry["delta_e2000_at_0"],
    }


def material_coefficients(name: str, space: str = "ACEScg", basis: Basis | None = None) -> np.ndarray:
    """(3, K) basis coefficients of a measured material (``Gold``, ``Chromium``, ``Glass BK7``, …).

    With the shipped basis they come from ``luts/materials.json``; with another ``basis`` they are
    fitted afresh (``delta-e`` fit), since coefficients only mean something for the basis they fit.

    Examples
    --------
    >>> material_coefficients("Gold")[:, 0].round(3)  # F0 in ACEScg
    array([ 0.903,  0.746,  0.418])
    """
    if basis is not None and basis.content_hash != default_basis().content_hash:
        # the preset lookup validates name and space with the usual messages
        from .material_fits import fit_material  # colour-science, only when fitting afresh

        return fit_material(material_preset(name, space)["name"], space, "delta-e", basis)
    preset = material_preset(name, space)
    if preset["basis_hash"] != default_basis().content_hash:
        raise PresetFileError(
            f"{shipped_presets_path()} was made for basis {preset['basis_hash']}, the shipped basis is "
            f"{default_basis().content_hash}; rebuild it with `fresnel-lut materials`"
        )
    return preset["coefficients"]
