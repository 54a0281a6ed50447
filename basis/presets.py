"""The shipped presets of measured materials (``luts/materials.json``): basis coefficients and their errors.

Public objects: ``PRESET_SPACES``, ``PresetFileError``, ``shipped_presets_path``, ``build_presets``, ``write_presets``,
``material_presets``, ``material_preset``, ``material_coefficients``, ``preset_errors``, ``presets_summary_lines``,
``content_hash``, ``FORMAT``, ``VERSION``.

The document carries a SHA-256 ``content_hash`` of its canonical JSON, and every number a reader uses is checked
against :data:`RANGES`.

Reading a preset loads no colour science: the coefficients were fitted once by
:func:`basis.presets.build_presets` (``fresnel-lut materials --presets``) and are tied to the basis
by its content hash. Fitting afresh for another basis imports :mod:`basis.material_fits` when asked.

References
----------
:cite:`Hoffman2020` SIGGRAPH 2020 course notes, ΔE2000 tables and "Computing RGB Parameter Values From
    Spectral IOR Data".
"""

from __future__ import annotations

import functools
import hashlib
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np

from .angles import cos_theta
from .eigenbasis import Basis, default_basis, resolve_basis
from .models.formulas import F82_MU, schlick_curve
from .parallel import one_blas_thread
from .storage import read_json_document, shipped_path, write_json
from .validation import ParameterError, check_choice

__all__ = [
    "FORMAT",
    "PRESET_SPACES",
    "PresetFileError",
    "VERSION",
    "build_presets",
    "content_hash",
    "material_coefficients",
    "material_preset",
    "material_presets",
    "preset_errors",
    "presets_summary_lines",
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
    document = read_json_document(path, "material presets", FORMAT, VERSION, error=PresetFileError)
    _check_document(path, document)
    return document


#: What a reader accepts of each number (a working-space reflectance may leave [0, 1] a little: sRGB gold's F0 red
#: is 1.038; a basis coefficient of a curve in [0, 1] stays far inside ±10 as max |b_k| = 1; ΔE2000 is ≥ 0).
RANGES = {
    "f0": (-0.25, 1.25),
    "f82": (-0.25, 1.25),
    "coefficients": (-10.0, 10.0),
    "delta_e2000_at_0": (0.0, 100.0),
    "rms_delta_e2000": (0.0, 100.0),
}


def content_hash(document: dict) -> str:
    """SHA-256 (first 16 hex digits) of the document without its ``content_hash``, as canonical JSON."""
    body = {key: value for key, value in document.items() if key != "content_hash"}
    text = json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=False)
    return hashlib.sha256(text.encode("utf-8")).hexdigest()[:16]


def _finite(where: str, value, shape: tuple[int, ...] | None, bounds: tuple[float, float] | None = None) -> None:
    """A number or nested list of numbers (no bool, string, NaN or inf) of the given shape, within ``bounds``."""

    def bad(reason: str):
        return PresetFileError(f"material presets {where} {reason}, got {str(value)[:60]!r}")

    def numbers(item) -> bool:
        if isinstance(item, list):
            return all(numbers(element) for element in item)
        return isinstance(item, (int, float)) and not isinstance(item, bool)

    if not numbers(value):
        raise bad("must hold numbers only")
    try:
        array = np.asarray(value, dtype=np.float64)
    except ValueError:  # ragged nesting
        raise bad("must be a regular array of numbers") from None
    if shape is not None and (
        array.ndim != len(shape) or any(n not in (size, -1) for n, size in zip(shape, array.shape))
    ):
        raise bad(f"must have shape {tuple('K' if n == -1 else n for n in shape)}")
    if not np.all(np.isfinite(array)):
        raise bad("must be finite (no NaN or inf)")
    if bounds is not None and not np.all((array >= bounds[0]) & (array <= bounds[1])):
        raise bad(f"must lie in [{bounds[0]:g}, {bounds[1]:g}]")


def _check_document(path: str, document: dict) -> None:
    """Every field a reader uses, with its type, shape and finiteness; one line naming the file, material, key."""
    if not isinstance(document.get("basis_hash"), str):
        raise PresetFileError(f"material presets {path}: basis_hash must be a string")
    materials = document.get("materials")
    if not isinstance(materials, dict) or not materials:
        raise PresetFileError(f"material presets {path}: materials must be a non-empty table of materials")
    for name, material in materials.items():
        where = f"{path}: {name!r}"
        if (
            not isinstance(material, dict)
            or not isinstance(material.get("kind"), str)
            or not isinstance(material.get("source"), dict)
        ):
            raise PresetFileError(f"material presets {where} must be a table with kind (text) and source (table)")
        for space in PRESET_SPACES:
            entry = material.get(space)
            if not isinstance(entry, dict):
                raise PresetFileError(f"material presets {where} lacks the {space} table")
            for key, shape in (("f0", (3,)), ("f82", (3,)), ("coefficients", (3, -1)), ("delta_e2000_at_0", ())):
                if key not in entry:
                    raise PresetFileError(f"material presets {where} {space} lacks {key}")
                _finite(f"{where} {space} {key}", entry[key], shape, RANGES[key])
            errors = entry.get("rms_delta_e2000")
            if not isinstance(errors, dict) or set(errors) != {"basis", "schlick"}:
                raise PresetFileError(f"material presets {where} {space} rms_delta_e2000 must hold basis and schlick")
            for key, value in errors.items():
                _finite(f"{where} {space} rms_delta_e2000 {key}", value, (), RANGES["rms_delta_e2000"])
    computed = content_hash(document)  # last: a field out of its range is named above
    if document.get("content_hash") != computed:
        raise PresetFileError(
            f"material presets {path}: content hash {document.get('content_hash')!r} does not match "
            f"the document ({computed}): the file is corrupt or was edited"
        )


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
    if not isinstance(name, str):
        raise ParameterError(
            f"material must be a name (text), got {type(name).__name__} {' '.join(repr(name).split())[:60]}"
        )
    document = material_presets(path)
    check_choice("colour space", space, PRESET_SPACES)
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
        "fit": dict(entry.get("fit", {})),
    }


def preset_errors(material, coefficients, basis: Basis) -> dict:
    """RMS ΔE2000 of a preset material's ``coefficients`` (3, K) on ``basis`` against its spectral truth, and
    Schlick's: the shipped file's numbers for the shipped basis, the basis' measured afresh for another (the shipped
    numbers belong to the shipped basis' coefficients)."""
    preset = material_preset(material.description["preset"], material.space)
    if basis.content_hash == material_presets()["basis_hash"]:
        return dict(preset["rms_delta_e2000"])
    from .material_fits import ANGLES_DEGREES, rms_delta_E_2000

    theta = np.deg2rad(ANGLES_DEGREES)
    truth = material.curve(np.cos(theta))
    return {
        "basis": float(rms_delta_E_2000(truth, (np.asarray(coefficients) @ basis.evaluate(theta).T).T, material.space)),
        "schlick": preset["rms_delta_e2000"]["schlick"],
    }


def material_coefficients(name: str, space: str = "ACEScg", basis: Basis | None = None) -> np.ndarray:
    """(3, K) basis coefficients of a measured material (``Gold``, ``Chromium``, ``Glass BK7``, …).

    With the shipped basis they come from ``luts/materials.json``; with another ``basis`` they are
    fitted afresh (``delta-e`` fit), since coefficients only mean something for the basis they fit.

    Examples
    --------
    >>> material_coefficients("Gold")[:, 0].round(3)  # c0 in ACEScg: F0 (0.903, 0.746, 0.418) moved by ΔE2000 0.05
    array([ 0.904,  0.746,  0.418])
    """
    if basis is not None and resolve_basis(basis).content_hash != default_basis().content_hash:
        # the preset lookup validates name and space with the usual messages
        from .material_fits import fit_material  # colour-science, only when fitting afresh

        return fit_material(material_preset(name, space)["name"], space, "delta-e", basis)
    preset = material_preset(name, space)
    if preset["basis_hash"] != default_basis().content_hash:
        raise PresetFileError(
            f"{shipped_presets_path()} was made for basis {preset['basis_hash']}, the shipped basis is "
            f"{default_basis().content_hash}; refit the shipped presets with `make materials` (or pass the basis "
            "that goes with them)"
        )
    if preset["coefficients"].shape != (3, default_basis().n_terms):
        raise PresetFileError(
            f"{shipped_presets_path()}: {preset['name']} has coefficients of shape "
            f"{preset['coefficients'].shape}, the shipped basis has {default_basis().n_terms} terms"
        )
    return preset["coefficients"]


def build_presets(
    basis: Basis | None = None, fit: str = "delta-e", progress: Callable[[int, int], None] | None = None
) -> dict:
    """The JSON document of ``luts/materials.json`` for every measured material and :data:`PRESET_SPACES`.

    ``progress(done, total)`` is called after each material.
    """
    # colour science: loaded by this command, never by reading a preset
    basis = resolve_basis(basis)
    with one_blas_thread():  # the same bits whatever the machine's BLAS threads (basis.parallel)
        return _presets_document(basis, fit, progress)


def _presets_document(basis: Basis, fit: str, progress) -> dict:
    from .colorimetry import delta_E_2000
    from .material_fits import ANGLES_DEGREES, fit_material, material_curve, rms_delta_E_2000
    from .spectral import spectral_iors

    theta = np.deg2rad(ANGLES_DEGREES)
    materials = {}
    measured = spectral_iors()
    for done, (name, material) in enumerate(measured.items(), start=1):
        spaces = {}
        for space in PRESET_SPACES:
            curve = material_curve(name, space)
            truth = curve(cos_theta(theta))
            convergence: dict = {}
            coefficients = fit_material(name, space, fit, basis, report=convergence)
            f0 = truth[0]
            schlick = schlick_curve(cos_theta(theta)[:, None], f0)
            spaces[space] = {
                "f0": [round(float(v), 8) for v in f0],
                "f82": [round(float(v), 8) for v in curve(np.array(F82_MU))],
                "coefficients": [[round(float(v), 10) for v in row] for row in coefficients],
                "rms_delta_e2000": {
                    "basis": round(
                        float(rms_delta_E_2000(truth, (coefficients @ basis.evaluate(theta).T).T, space)), 4
                    ),
                    "schlick": round(float(rms_delta_E_2000(truth, schlick, space)), 4),
                },
                "delta_e2000_at_0": round(float(delta_E_2000(f0, coefficients[:, 0], space)), 4),
                **({"fit": convergence} if convergence else {}),
            }
        source = material.source
        materials[name] = {
            "kind": material.kind,
            "source": {
                key: source[key] for key in ("database", "file", "references", "constant_eta", "note") if key in source
            },
            **spaces,
        }
        if progress is not None:
            progress(done, len(measured))
    document = {
        "format": FORMAT,
        "version": VERSION,
        "basis_hash": basis.content_hash,
        "description": {
            "f0": "RGB reflectance at normal incidence, Hoffman 2020's spectral procedure (linear, working space)",
            "f82": "RGB reflectance at arccos(1/7) (about 82.3 degrees), for Hoffman 2019's F82 model",
            "coefficients": f"3 x {basis.n_terms}: per channel R, G, B the basis coefficients c0..c{basis.n_terms - 1} "
            f"({fit} fit; c0 = F0, c0 + c1 = F90 = 1)",
            "rms_delta_e2000": "RMS over 0, 1, ..., 90 degrees of CIEDE2000 against the spectral ground truth",
            "delta_e2000_at_0": "CIEDE2000 between f0 and the fitted c0 (the fit trades F0 exactness for the RMS)",
            "fit": "convergence of the fit: converged (scipy status > 0), status, function evaluations, final "
            "gradient (max norm of J^T r over the dE2000 residual components)",
            "spaces": "ACEScg: D60 illuminant, Bradford to the ACES white; sRGB: linear Rec.709 primaries, D65",
            "content_hash": "first 16 hex digits of the SHA-256 of this document without content_hash, as UTF-8 "
            "JSON with sorted keys and no spaces",
        },
        "materials": materials,
    }
    return {**document, "content_hash": content_hash(document)}


def presets_summary_lines(document: dict) -> list[str]:
    """What a fit of the presets (:func:`build_presets`) achieved, per working space: the worst metal's RMS ΔE2000 and
    how many fits converged."""
    lines = []
    for space in PRESET_SPACES:
        entries = {name: entry[space] for name, entry in document["materials"].items()}
        metals = {
            name: entry["rms_delta_e2000"]["basis"]
            for name, entry in entries.items()
            if document["materials"][name]["kind"] == "metal"
        }
        worst = max(metals, key=metals.get)
        unconverged = sorted(name for name, entry in entries.items() if not entry.get("fit", {}).get("converged", True))
        evaluations = [entry["fit"]["evaluations"] for entry in entries.values() if "fit" in entry]
        lines.append(
            f"  {space}: worst metal {worst} {metals[worst]:.3f} RMS dE2000 (basis); fits converged: "
            f"{len(entries) - len(unconverged)} of {len(entries)}, {max(evaluations, default=0)} evaluations at most"
            + (f"; NOT converged: {', '.join(unconverged)}" if unconverged else "")
        )
    return lines
