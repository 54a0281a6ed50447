"""A material's hand-off as one record: its coefficients on a basis, what they hold of the exact curve, and the table
that holds a linear model's split sum exactly; JSON-ready (``fresnel-lut coeffs --json``) and as text.

Public objects: ``coefficient_record``, ``record_lines``, ``presets_listing``, ``listing_lines``.

The material is given in the vocabulary of :mod:`basis.materials` (a preset, η and κ, Gulbrandsen's r and g, a model
with its parameters); its description in the record is :meth:`basis.materials.Material.described`, the one a scene's
``scene_coefficients.json`` holds as each material's ``target``.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from basis.coefficients import MODEL_FITS, coefficients_from_model
from basis.eigenbasis import Basis, resolve_basis
from basis.materials import material_from_mapping
from basis.models import fresnel_model
from basis.presets import material_presets, preset_errors
from basis.validation import ParameterError, check_choice
from preintegrate.channels import schlick_table_weights

from .shipped import SCHLICK_LUT, model_lut_name

__all__ = ["coefficient_record", "listing_lines", "presets_listing", "record_lines"]


def own_split_sum(model: str, parameters: dict) -> dict | None:
    """The exact split sum of a linear model's material: the table that holds it (and the command that writes it),
    the weights of its channels per colour channel, and whether it is exact (the model's clamp to [0, 1] inactive);
    None for a model that is not linear. Models whose fixed functions are the Schlick table's (Schlick with F90,
    F82, F82 tint, generalised Adobe with p = 5) read the default build's table (weights of R, G, B, A); the others
    their own table (``fresnel-lut build --model``)."""
    found = fresnel_model(model)
    if not found.linear:
        return None
    weights = schlick_table_weights(found.name, **parameters)
    if weights is not None:
        table = f"{SCHLICK_LUT} (fresnel-lut build)"
    else:
        weights = found.channel_weights(**parameters)
        shape = found.shape_values(**parameters)
        options = "".join(f" --{name.replace('_', '-')} {value:g}" for name, value in shape.items())
        table = f"{model_lut_name(found.name, shape)} (fresnel-lut build --model {found.name}{options})"
    return {
        "lut": table,
        "weights": np.broadcast_to(weights, (3, weights.shape[-1])).tolist(),
        "exact": bool(np.all(found.clamp_is_inactive(**parameters))),
    }


def coefficient_record(
    mapping: Mapping, space: str = "ACEScg", basis: Basis | None = None, fit: str | None = None
) -> dict:
    """The record of the material ``mapping`` gives (:func:`basis.materials.material_from_mapping`; ``space`` the
    working space of a preset) on ``basis`` (default: the shipped one): ``basis_hash``, ``material`` (the
    description, with a preset's F0, source and RMS ΔE2000), ``coefficients`` (3, K) and their ``layout``; a model's
    material adds its ``fit`` (default four-point), ``max_abs_error_over_theta`` per channel and ``own_split_sum``.
    ``path`` says which path README's rule picks and why: a linear model whose exact table holds it exactly (its curve
    inside [0, 1]) reads that table; every other material the basis (``report/linear_models.md``).

    >>> record = coefficient_record({"eta": 1.5, "kappa": 0.0})
    >>> record["material"], len(record["coefficients"]), round(record["coefficients"][0][0], 4)
    ({'eta': [1.5, 1.5, 1.5], 'kappa': [0.0, 0.0, 0.0]}, 3, 0.04)
    """
    basis = resolve_basis(basis)
    material = material_from_mapping(mapping, space)
    by_model = material.kind in ("schlick", "f82", "model")
    if fit is not None and not by_model:
        raise ParameterError(f"a fit goes with a model's material, not with a {material.kind} one")
    record = {"basis_hash": basis.content_hash, "material": material.described()}
    if by_model:
        fit = check_choice("fit", fit or "four-point", MODEL_FITS)
        model, parameters = material.model_parameters()
        coefficients, error = coefficients_from_model(model, fit, basis, **parameters)
        record.update(
            fit=fit,
            coefficients=coefficients.tolist(),
            max_abs_error_over_theta=error.tolist(),
            own_split_sum=own_split_sum(model, parameters),
        )
    else:
        coefficients = material.coefficients(basis)
        record["coefficients"] = coefficients.tolist()
        if material.kind == "preset":
            record["material"]["rms_delta_e2000"] = preset_errors(material, coefficients, basis)
    record["layout"] = f"[channel R,G,B][term c0..c{basis.n_terms - 1}]"
    record["path"] = _path(record)
    return record


def _path(record: dict) -> dict:
    """README's rule ("Which path for which material") for this record: ``choice`` and ``why``."""
    own = record.get("own_split_sum")
    if own is not None and own["exact"]:
        return {
            "choice": "exact table",
            "why": f"a linear model: {own['lut'].split()[0]} holds its split sum exactly, where the basis projection "
            f"misses its curve by up to {max(record['max_abs_error_over_theta']):.3g}",
        }
    if own is not None:
        return {"choice": "basis", "why": "the model's curve leaves [0, 1] and is clamped: no table holds it exactly"}
    return {"choice": "basis", "why": "a physical curve: the basis fits it, no linear model does"}


def record_lines(record: dict) -> list[str]:
    """The record as a person reads it: what the material is (a preset's F0 and errors, a model's projection error),
    the combination rule and the coefficients per colour channel, a linear model's own exact table and weights."""
    material, coefficients = record["material"], np.array(record["coefficients"])
    lines = []
    if "preset" in material:
        errors = material["rms_delta_e2000"]
        lines.append(
            f"{material['preset']} ({material['space']}, linear): F0 = "
            + ", ".join(f"{v:.4f}" for v in material["f0"])
            + f"; RMS dE2000 basis {errors['basis']:.3f}, Schlick {errors['schlick']:.3f}"
        )
    if "fit" in record:
        model = fresnel_model(material["model"])
        lines.append(
            f"{model.name} ({model.reference}); {record['fit']} projection, max |dF| over theta per channel: "
            + ", ".join(f"{value:.4f}" for value in record["max_abs_error_over_theta"])
        )
    terms = " + ".join(f"c{k}*{'LUT' if k < 4 else 'LUT2'}.{'rgba'[k % 4]}" for k in range(coefficients.shape[-1]))
    lines.append(f"basis {record['basis_hash']}; Fbar = {terms} per colour channel")
    lines += [
        f"  {name}: " + "  ".join(f"c{k}={value: .6f}" for k, value in enumerate(row))
        for name, row in zip("RGB", coefficients)
    ]
    lines.append(f"path: {record['path']['choice']} ({record['path']['why']})")
    own = record.get("own_split_sum")
    if own is not None:
        lines.append(
            f"own exact split sum ({'exact' if own['exact'] else 'approximate: the curve is clamped'}): {own['lut']}"
        )
        lines += [
            f"  {name}: " + "  ".join(f"w{k}={value: .6f}" for k, value in enumerate(row))
            for name, row in zip("RGB", own["weights"])
        ]
    return lines


def presets_listing(space: str = "ACEScg") -> dict:
    """The measured materials of ``luts/materials.json`` in ``space``: kind, F0 and RMS ΔE2000 of each."""
    document = material_presets()
    return {
        "basis_hash": document["basis_hash"],
        "space": space,
        "materials": {
            name: {
                "kind": material["kind"],
                "f0": material[space]["f0"],
                "rms_delta_e2000": material[space]["rms_delta_e2000"],
            }
            for name, material in document["materials"].items()
        },
    }


def listing_lines(listing: dict) -> list[str]:
    """:func:`presets_listing` as a table a person reads."""
    lines = [
        f"measured materials of --material ({listing['space']}; luts/materials.json, basis {listing['basis_hash']}):",
        f"  {'name':16s} {'kind':10s} {'F0 (R, G, B)':24s} RMS dE2000 basis / Schlick",
    ]
    for name, entry in listing["materials"].items():
        f0 = ", ".join(f"{value:.3f}" for value in entry["f0"])
        errors = entry["rms_delta_e2000"]
        lines.append(f"  {name:16s} {entry['kind']:10s} {f0:24s} {errors['basis']:.3f} / {errors['schlick']:.2f}")
    return lines
