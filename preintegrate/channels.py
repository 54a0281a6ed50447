"""Channel sets: the functions of cos θ_d = ω_o·h whose split-sum integrals make a LUT.

Public objects: ``ChannelSet``, ``CHANNEL_SETS``, ``basis_channels``, ``schlick_channels``,
``schlick_table_channels``, ``albedo_channels``, ``average_albedo_channels``, ``model_channels``, ``channel_set``,
``combine``.

A channel set names its functions f_k, says how an engine combines the channels into F̄, and is
integrated by the one generic integrator :func:`preintegrate.quadrature.directional_albedo`.

References
----------
:cite:`Belcour2020` eq. 5: F̄ = Σ c_i b̄_i.
:cite:`Karis2013` "Real Shading in Unreal Engine 4": Schlick split sum F̄ = F0 · scale + bias with
    scale = ∫ (1 − (1 − x)^5) ρ μ_i, bias = ∫ (1 − x)^5 ρ μ_i; the talk's eq. 3.
:cite:`Schlick1994` F = F0 + (1 − F0)(1 − x)^5.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable

import numpy as np

from basis.eigenbasis import Basis, resolve_basis
from basis.models import FRESNEL_MODELS, fresnel_model
from basis.validation import check_choice

__all__ = [
    "CHANNEL_SETS",
    "ChannelSet",
    "albedo_channels",
    "average_albedo_channels",
    "basis_channels",
    "channel_set",
    "combine",
    "model_channels",
    "schlick_channels",
    "schlick_table_channels",
]


@dataclasses.dataclass(frozen=True)
class ChannelSet:
    """Functions f_k(x) of x = ω_o·h, their EXR channel names and the engine's combination rule."""

    name: str
    functions: Callable[[np.ndarray], np.ndarray]
    channel_names: tuple[str, ...]
    combination: str
    provenance: dict = dataclasses.field(default_factory=dict)

    @property
    def n_channels(self) -> int:
        return len(self.channel_names)


def schlick_channels() -> ChannelSet:
    """Karis's two channels: R = scale (f = 1 − (1 − x)^5), G = bias (f = (1 − x)^5): the ``schlick`` model's."""
    return model_channels("schlick")


def albedo_channels() -> ChannelSet:
    """One channel E = F̄[1]: GGX's directional albedo without Fresnel (what multiple-scattering compensation
    needs; equal to Schlick's scale + bias)."""
    return ChannelSet(
        name="albedo",
        functions=lambda x: np.ones(np.shape(x) + (1,)),
        channel_names=("B",),
        combination="B = E = R + G: the GGX directional albedo without Fresnel",
    )


def average_albedo_channels() -> ChannelSet:
    """The one-column E_avg table's single channel Y (a luminance channel: every EXR reader loads it)."""
    return ChannelSet(
        name="albedo_average",
        functions=albedo_channels().functions,
        channel_names=("Y",),
        combination="Y = E_avg(r) = 2 * integral of E(mu, r) mu dmu over [0, 1], E = the Schlick table's B "
        "(Kulla and Conty 2017); one column, rows as in the other tables",
    )


def schlick_table_channels() -> ChannelSet:
    """The channels of the shipped Schlick table: R = scale, G = bias (Karis 2013) and B = E, so that every
    reader of RGB images loads it (FreeImage, tinyexr and FFmpeg refuse or zero a two-channel EXR)."""
    schlick, albedo = schlick_channels(), albedo_channels()
    return ChannelSet(
        name="schlick",
        functions=combine(schlick, albedo).functions,
        channel_names=schlick.channel_names + albedo.channel_names,
        combination=f"{schlick.combination}; {albedo.combination} (multiple-scattering compensation; the "
        "'multiscatter DFG' form some engines store is (G, B))",
    )


def basis_channels(basis: Basis | None = None) -> ChannelSet:
    """One channel per basis element b_k(arccos x): R, G, B, A = b0 … b3 for K = 4."""
    basis = resolve_basis(basis)
    names = (
        ("R", "G", "B", "A")[: basis.n_terms] if basis.n_terms <= 4 else tuple(f"b{k}" for k in range(basis.n_terms))
    )
    return ChannelSet(
        name="basis",
        functions=basis._evaluate_mu_unchecked,
        channel_names=names,
        combination="Fbar = sum_k c_k * channel_k (Belcour et al. 2020, eq. 5)",
        provenance={"basis_hash": basis.content_hash},
    )


def combine(*channel_sets: ChannelSet) -> ChannelSet:
    """One set whose channels are all the given sets' side by side: one integration pass for all."""

    def functions(x: np.ndarray) -> np.ndarray:
        return np.concatenate([channels.functions(x) for channels in channel_sets], axis=-1)

    return ChannelSet(
        name="+".join(channels.name for channels in channel_sets),
        functions=functions,
        channel_names=sum((channels.channel_names for channels in channel_sets), ()),
        combination="; ".join(channels.combination for channels in channel_sets),
    )


def model_channels(name: str, **shape) -> ChannelSet:
    """The exact split-sum channels of a model of :data:`basis.models.FRESNEL_MODELS` that is
    linear in fixed functions t_n of cos θ (shape parameters such as ``exponent`` fix them)."""
    model = fresnel_model(name)
    functions = model.channel_functions(**shape)
    count = functions(np.array([0.5])).shape[-1]
    names = ("R", "G", "B", "A")[:count]
    fixed = {key: float(value) for key, value in shape.items() if key in model.shape}
    combination = model.combination or (
        "Fbar = "
        + " + ".join(f"w{n} * {channel}" for n, channel in enumerate(names))
        + f"; {model.name}: F = sum_n w_n t_n(cos theta), t = {model.terms_description}"
    )
    return ChannelSet(
        name=name,
        functions=functions,
        channel_names=names,
        combination=combination,
        provenance={"reference": model.reference, **{key: repr(value) for key, value in fixed.items()}},
    )


#: Registry: name → factory. ``fresnel-lut build --model NAME`` is one lookup here.
CHANNEL_SETS: dict[str, Callable[..., ChannelSet]] = {
    "basis": basis_channels,
    **{name: functools.partial(model_channels, name) for name, model in FRESNEL_MODELS.items() if model.linear},
}


def channel_set(name: str, **kwargs) -> ChannelSet:
    """Look up a channel set by name; the error lists the valid names."""
    return CHANNEL_SETS[check_choice("channel set", name, sorted(CHANNEL_SETS))](**kwargs)
