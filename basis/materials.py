"""What a material is: one vocabulary for every way users give one, shared by ``coeffs``, scene files and the renderer.

Public objects: ``MATERIAL_KINDS``, ``Material``, ``material_from_mapping``.

A material is a mapping of one of these kinds (:data:`MATERIAL_KINDS`; a colour is a number or three numbers R, G, B):

=============  ===============================  =====================================================
kind           keys                             exact curve
=============  ===============================  =====================================================
``preset``     ``preset`` (a measured material)  Hoffman 2020's spectral RGB curve in the working space
``nk``         ``eta``, ``kappa``                the Fresnel equations of η + iκ
``gulbrandsen`` ``reflectivity``, ``edge_tint``  the Fresnel equations of Gulbrandsen 2014's (r, g) → (η, κ)
``schlick``    ``f0``                            Schlick 1994 (the ``schlick`` model)
``f82``        ``f0``, ``f82``                   Hoffman 2019's F82 (the ``f82`` model)
``model``      ``model`` and its parameters      any model of :data:`basis.models.FRESNEL_MODELS`
=============  ===============================  =====================================================

A key outside the kind's keys (``eta`` beside ``preset``, a per-material ``space``) is refused, never dropped.

References
----------
:cite:`Hoffman2020` "Computing RGB Parameter Values From Spectral IOR Data". :cite:`Gulbrandsen2014` JCGT 3(4),
eq. 7-9. :cite:`Hoffman2019` "Fresnel Equations Considered Harmful", eq. 4.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Mapping

import numpy as np

from .eigenbasis import Basis
from .fresnel import ETA_RANGE, KAPPA_RANGE, fresnel_kernel
from .gulbrandsen import gulbrandsen_to_nk
from .models import fresnel_model
from .validation import ParameterError, check_range

__all__ = ["MATERIAL_KINDS", "Material", "material_from_mapping"]

#: kind → the keys that give it (a ``model`` material adds the model's own parameters).
MATERIAL_KINDS = {
    "preset": ("preset",),
    "nk": ("eta", "kappa"),
    "gulbrandsen": ("reflectivity", "edge_tint"),
    "schlick": ("f0",),
    "f82": ("f0", "f82"),
    "model": ("model",),
}


@dataclasses.dataclass(frozen=True)
class Material:
    """A material of :data:`MATERIAL_KINDS`: its ``description`` (JSON-ready, the keys as given, colours as lists;
    a material given by a model, ``f0`` or ``f0`` + ``f82`` included, names its ``model``) and its exact RGB curve."""

    kind: str
    description: dict
    space: str
    _curve: Callable[[np.ndarray], np.ndarray] = dataclasses.field(repr=False)

    def curve(self, mu) -> np.ndarray:
        """The exact reflectance F(μ) per colour channel: μ (...) in [0, 1] → (..., 3)."""
        mu = check_range("mu", mu, 0.0, 1.0)
        return np.broadcast_to(self._curve(mu), mu.shape + (3,))

    def coefficients(self, basis: Basis | None = None, fit: str = "four-point") -> np.ndarray:
        """(3, K) basis coefficients: a preset's fitted ones (``luts/materials.json``, or fitted afresh for another
        basis), the four-point solve of (η, κ) and (r, g), a model's projection by ``fit``."""
        from .coefficients import coefficients_from_gulbrandsen, coefficients_from_model, coefficients_from_nk

        given = self.description
        if self.kind == "preset":
            from .presets import material_coefficients

            return material_coefficients(given["preset"], self.space, basis)
        if self.kind == "nk":
            return coefficients_from_nk(np.array(given["eta"]), np.array(given["kappa"]), basis)
        if self.kind == "gulbrandsen":
            return coefficients_from_gulbrandsen(np.array(given["reflectivity"]), np.array(given["edge_tint"]), basis)
        model, parameters = self.model_parameters()
        return coefficients_from_model(model, fit, basis, **parameters)[0]

    def described(self) -> dict:
        """The JSON-ready description and what the material implies: a preset's working space, F0 and data source, the
        (η, κ) of Gulbrandsen's (r, g) (what ``coeffs`` reports and a scene's ``scene_coefficients.json`` holds)."""
        described = dict(self.description)
        if self.kind == "preset":
            from .presets import material_preset

            preset = material_preset(described["preset"], self.space)
            described.update(space=self.space, f0=preset["f0"].tolist(), source=preset["source"])
        elif self.kind == "gulbrandsen":
            eta, kappa = gulbrandsen_to_nk(np.array(described["reflectivity"]), np.array(described["edge_tint"]))
            described.update(eta=eta.tolist(), kappa=kappa.tolist())
        return described

    def model_parameters(self) -> tuple[str, dict]:
        """(model name, float64 parameters) of a ``schlick``, ``f82`` or ``model`` material."""
        if self.kind not in ("schlick", "f82", "model"):
            raise ParameterError(f"a {self.kind} material is not given by a model")
        parameters = {
            key: np.asarray(value, dtype=np.float64) for key, value in self.description.items() if key != "model"
        }
        return self.description["model"], parameters


def _is_number(value) -> bool:
    return isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, (bool, np.bool_))


def _colour(key: str, value) -> np.ndarray:
    """A number or three numbers R, G, B, as (3,) float64."""
    if _is_number(value):
        return np.full(3, float(value))
    if (
        isinstance(value, (list, tuple, np.ndarray))
        and len(value) == 3
        and all(_is_number(element) for element in value)
    ):
        return np.array([float(element) for element in value])
    shown = " ".join(repr(value).split())
    raise ParameterError(f"{key} must be a number or 3 numbers (R, G, B), got {shown[:60]}")


def _kind(mapping: Mapping) -> str:
    keys = set(mapping)
    for kind in ("preset", "model"):
        if kind in keys:
            return kind
    exact = [kind for kind, names in MATERIAL_KINDS.items() if kind not in ("preset", "model") and keys == set(names)]
    if exact:
        return exact[0]
    raise ParameterError(
        "give one of: preset; eta and kappa; reflectivity and edge_tint; f0; f0 and f82; or model "
        f"with its parameters (got {sorted(keys)})"
    )


def material_from_mapping(mapping: Mapping, space: str = "ACEScg") -> Material:
    """The material a mapping gives (module docstring); every key is checked, none is dropped.

    ``space`` is the working space of a preset's RGB curve (``ACEScg`` or ``sRGB``).

    Examples
    --------
    >>> gold = material_from_mapping({"reflectivity": [0.944, 0.776, 0.373], "edge_tint": [0.998, 0.981, 0.751]})
    >>> gold.kind, gold.curve(1.0).round(3).tolist()
    ('gulbrandsen', [0.944, 0.776, 0.373])
    """
    if not isinstance(mapping, Mapping):
        raise ParameterError(f"a material must be a table of keys, got {type(mapping).__name__}")
    kind = _kind(mapping)
    if kind == "preset":
        return _preset(mapping, space)
    if kind == "model":
        return _model(mapping)
    colours = {key: _colour(key, mapping[key]) for key in MATERIAL_KINDS[kind]}
    if kind == "nk":
        eta = check_range("eta", colours["eta"], *ETA_RANGE)
        kappa = check_range("kappa", colours["kappa"], *KAPPA_RANGE)
        return Material(
            kind,
            {"eta": eta.tolist(), "kappa": kappa.tolist()},
            space,
            lambda mu: fresnel_kernel(mu[..., None], eta, kappa),
        )
    if kind == "gulbrandsen":
        reflectivity, edge_tint = colours["reflectivity"], colours["edge_tint"]
        eta, kappa = gulbrandsen_to_nk(reflectivity, edge_tint)  # checks both ranges
        return Material(
            kind,
            {"reflectivity": reflectivity.tolist(), "edge_tint": edge_tint.tolist()},
            space,
            lambda mu: fresnel_kernel(mu[..., None], eta, kappa),
        )
    model = fresnel_model(kind)  # the schlick and f82 kinds are those models
    parameters = model.check(**colours)
    return Material(
        kind,
        {"model": model.name, **{key: value.tolist() for key, value in parameters.items()}},
        space,
        lambda mu: model.evaluate(mu[..., None], **parameters),
    )


def _preset(mapping: Mapping, space: str) -> Material:
    from .presets import PRESET_SPACES, material_preset
    from .validation import check_choice

    extra = sorted(set(mapping) - {"preset"})
    if extra:
        raise ParameterError(
            f"a preset material takes only preset (its working space is the scene file's space key, or coeffs' --space), not {extra}"
        )
    name = mapping["preset"]
    if not isinstance(name, str):
        raise ParameterError(f"preset must be a material's name (text), got {' '.join(repr(name).split())[:60]}")
    check_choice("colour space", space, PRESET_SPACES)
    name = material_preset(name, space)["name"]

    def curve(mu: np.ndarray) -> np.ndarray:
        from .material_fits import material_curve  # colour science, only when a preset's curve is asked for

        return material_curve(name, space)(mu)

    return Material("preset", {"preset": name}, space, curve)


def _model(mapping: Mapping) -> Material:
    name = mapping["model"]
    if not isinstance(name, str):
        raise ParameterError(f"model must be a model's name (text), got {' '.join(repr(name).split())[:60]}")
    model = fresnel_model(name)
    given = {key: mapping[key] for key in mapping if key != "model"}  # the mapping's order, not a set's
    for key, value in given.items():
        if not (
            _is_number(value) or isinstance(value, (list, tuple)) and all(_is_number(element) for element in value)
        ):
            raise ParameterError(
                f"{key} must be a number or 3 numbers (R, G, B), got {' '.join(repr(value).split())[:60]}"
            )
    parameters = model.check(**{key: np.asarray(value, dtype=np.float64) for key, value in given.items()})
    description = {"model": model.name, **{key: np.asarray(value).tolist() for key, value in given.items()}}
    return Material("model", description, "", lambda mu: model.evaluate(mu[..., None], **parameters))
