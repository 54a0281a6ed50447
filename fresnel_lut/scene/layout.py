"""The tables a scene may ship: a :class:`Layout` names one, its channels on the basis grid, and the
weights with which a material reads it.

Public objects: ``Layout``, ``SCENE_TABLE_PREFIX``, ``SCHLICK``, ``basis_layout``, ``own_layout``, ``scene_basis_layouts``,
``train_scene_basis``, ``training_operators``.

References
----------
:cite:`Belcour2020` eq. 5 (F̄ = Σ c_k b̄_k); :cite:`Karis2013` (Schlick split sum).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from pathlib import Path

import numpy as np

from basis.angles import cos_theta
from basis.coefficients import coefficients_from_table, coefficients_least_squares_from_table
from basis.eigenbasis import Basis, BasisFileError
from basis.models import fresnel_model
from basis.training import MIN_SPAN, refine_basis
from handoff.shipped import model_lut_name
from preintegrate.channels import ChannelSet, basis_channels, model_channels, schlick_channels
from preintegrate.ggx import roughness_to_alpha
from preintegrate.quadrature import texel_weights

from .files import Scene, SceneMaterial

__all__ = [
    "SCENE_TABLE_PREFIX",
    "SCHLICK",
    "Layout",
    "basis_layout",
    "own_layout",
    "scene_basis_layouts",
    "train_scene_basis",
    "training_operators",
]


#: Every table a scene writes is named ``scene_ggx_…``, apart from a build's ``ggx_…`` tables: a scene written into a
#: build's folder replaces none of them, and a scene's own earlier tables are known by the prefix alone.
SCENE_TABLE_PREFIX = "scene_"


@dataclasses.dataclass(frozen=True)
class Layout:
    """One candidate table: Schlick's two channels, the first ``terms`` basis terms, a linear model's own
    channels (``model`` with the ``shape`` parameters that fix them), or the ``terms`` of a basis ``trained``
    on the scene's own curves (on the generic basis' θ grid)."""

    kind: str  # "schlick", "basis", "model" or "scene"
    terms: int = 0
    model: str = ""
    shape: tuple[tuple[str, float], ...] = ()
    trained: Basis | None = dataclasses.field(default=None, compare=False, repr=False)

    @property
    def name(self) -> str:
        """``schlick``, ``basis-K``, ``scene-basis`` or ``model:NAME[:shape=value,…]``: the name in reports and files."""
        if self.kind == "scene":
            return f"scene-basis-{self.terms}"
        if self.kind == "model":
            shape = ",".join(f"{key}={value!r}" for key, value in self.shape)
            return f"model:{self.model}" + (f":{shape}" if shape else "")
        return "schlick" if self.kind == "schlick" else f"basis-{self.terms}"

    def channel_set(self, basis: Basis) -> ChannelSet:
        """The channels, their names and the engine's combination rule."""
        if self.kind == "schlick":
            return schlick_channels()
        if self.kind == "model":
            return model_channels(self.model, **dict(self.shape))
        return basis_channels(self.trained if self.kind == "scene" else _truncated(basis, self.terms))

    def values(self, basis: Basis) -> np.ndarray:
        """(M, n) channel functions on ``basis.theta`` (the basis curves exactly, on their own grid)."""
        if self.kind == "basis":
            return basis.curves[: self.terms].T
        if self.kind == "scene":
            return self.trained.evaluate(basis.theta)
        return self.channel_set(basis).functions(cos_theta(basis.theta))

    def file_name(self) -> str:
        """The table's file, named apart from every table a build writes (:data:`SCENE_TABLE_PREFIX`)."""
        if self.kind == "schlick":
            stem = "ggx_schlick_rg"  # a scene keeps Schlick's two channels (the default build adds E as B)
        elif self.kind == "scene":
            stem = "ggx_own_basis_rgba"  # terms 4 … 7, if any, go to a second table (tables.rgba_tables)
        elif self.kind == "model":
            stem = Path(model_lut_name(self.model, self.shape)).stem
        else:
            stem = f"ggx_basis_{'rgba'[: self.terms]}"
        return f"{SCENE_TABLE_PREFIX}{stem}.exr"

    def coefficients(self, material: SceneMaterial, basis: Basis) -> np.ndarray | None:
        """(3, n) weights of a material: Schlick (F0, 1), the first K basis terms by least squares (c0 = F0
        and c0 + c1 = F90 exact), the scene basis' four-point fit (what it was refined for), or a linear
        model's own weights; None where the layout cannot represent the material (another model's table)."""
        if self.kind == "scene":
            return coefficients_from_table(basis.theta, material.curve.T, self.trained)
        if self.kind == "model":
            if own_layout(material) != self:
                return None
            parameters = {key: value for key, value in material.description.items() if key != "model"}
            weights = np.asarray(fresnel_model(self.model).channel_weights(**parameters), dtype=np.float64)
            return np.broadcast_to(weights, (3, weights.shape[-1])).copy()
        if self.kind == "schlick":
            return np.stack([material.curve[0], np.ones(3)], axis=-1)
        if self.terms == 2:
            return np.stack([material.curve[0], material.curve[-1] - material.curve[0]], axis=-1)
        return coefficients_least_squares_from_table(basis.theta, material.curve.T, _truncated(basis, self.terms))


#: Schlick's table, shared by every model whose fixed functions are Schlick's (schlick, the external-media
#: variants, fresnel-blend).
SCHLICK = Layout("schlick")


def basis_layout(terms: int) -> Layout:
    """The first ``terms`` basis terms."""
    return Layout("basis", terms=terms)


def _truncated(basis: Basis, terms: int) -> Basis:
    return Basis(basis.theta, basis.curves[:terms], basis.fit_angles[:terms]) if terms < basis.n_terms else basis


def own_layout(material: SceneMaterial) -> Layout | None:
    """The own exact table of a material given by a linear model whose fixed functions are not Schlick's
    (those read the Schlick table), else None."""
    name = material.description.get("model")
    if name is None or not fresnel_model(name).linear:
        return None
    model = fresnel_model(name)
    shape = tuple(
        (parameter.name, float(material.description.get(parameter.name, parameter.default)))
        for parameter in model.parameters
        if parameter.name in model.shape
    )
    if model.channel_functions(**dict(shape)) == fresnel_model("schlick").channel_functions():
        return None
    return Layout("model", model=name, shape=shape)


#: Terms of a scene basis: four (one RGBA table, as the generic one), then up to eight (a second RGBA table).
SCENE_BASIS_TERMS = (4, 5, 6, 7, 8)
#: Roughnesses per material at which a scene basis is trained (its range, end points included).
TRAINING_ROUGHNESSES = 5


def training_operators(scene: Scene, basis: Basis, mu_o: np.ndarray) -> dict[str, np.ndarray]:
    """name → texel weights (P, M) of each material at the view cosines ``mu_o`` and
    :data:`TRAINING_ROUGHNESSES` roughnesses of its range: what a scene basis is refined on (F̄, not F)."""
    return {
        m.name: texel_weights(
            basis.theta,
            mu_o[None, :],
            roughness_to_alpha(np.linspace(*m.roughness, TRAINING_ROUGHNESSES))[:, None],
            visibility=scene.visibility,
        ).reshape(-1, basis.theta.size)
        for m in scene.materials
    }


def train_scene_basis(scene: Scene, basis: Basis, operators: dict[str, np.ndarray], terms: int) -> Basis:
    """A ``terms``-term basis of the scene's own curves (every channel of every material, on ``basis.theta``),
    refined (:func:`basis.training.refine_basis`) to minimise the worst error of F̄ through ``operators``
    (:func:`training_operators`). One stage at p = 64, six dictionary curves, 150 iterations: on the
    example scenes within 2 % of the (16, 64) continuation with ten curves and 500 iterations, in half the time."""
    groups = {
        material.name: (material.curve.T, scene.tolerance, operators[material.name]) for material in scene.materials
    }
    return refine_basis(basis.theta, groups, n_terms=terms, dictionary_terms=6, powers=(64.0,), iterations=150)


def scene_basis_layouts(
    scene: Scene,
    basis: Basis,
    operators: dict[str, np.ndarray],
    goal: float,
    progress: Callable[[str], None] | None = None,
) -> list[Layout]:
    """Scene bases (:func:`train_scene_basis`) of four terms, then one more at a time while the worst trained
    error stays above half of ``goal`` (the other half is left to the table lookup). None when every curve is
    constant (η = 1; κ → ∞; r = 0 and g = 1): b0 alone holds those exactly, and an SVD has no shape to learn."""
    if all(np.max(np.abs(m.curve[-1] - m.curve[0])) <= MIN_SPAN for m in scene.materials):
        return []
    layouts = []
    for terms in SCENE_BASIS_TERMS:
        try:
            trained = train_scene_basis(scene, basis, operators, terms)
        except BasisFileError as error:  # e.g. a four-point system the refinement left ill-conditioned
            if progress is not None:
                progress(f"scene basis of {terms} terms: not usable ({error}); planning with the fewer terms")
            break
        layouts.append(Layout("scene", terms=terms, trained=trained))
        achieved = max(group["max_abs_error"] for group in trained.training["refinement"]["groups"].values())
        if progress is not None:
            progress(f"scene basis of {terms} terms: worst trained Fbar error {achieved:.2e}")
        if achieved <= 0.5 * goal:
            break
    return layouts
