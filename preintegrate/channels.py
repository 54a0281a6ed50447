"""Channel sets: the functions of cos θ_d = ω_o·h whose split-sum integrals make a LUT.

Public objects: ``ChannelSet``, ``CHANNEL_SETS``, ``basis_channels``, ``schlick_channels``,
``schlick_table_channels``, ``schlick_table_weights``, ``albedo_channels``, ``average_albedo_channels``, ``model_channels``, ``channel_set``,
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
    "schlick_table_weights",
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
    """The channels of the shipped Schlick table: R = scale, G = bias (Karis 2013), B = E and A = the dip
    ∫ x (1 − x)^6. Every model linear in 1 − (1 − x)^5, (1 − x)^5 and x (1 − x)^6 — Schlick with F0 and F90, Hoffman
    2019's F82, Adobe's F82 tint, Hoffman 2023's generalised Adobe with p = 5 (eq. 5-6) — has its exact split sum
    w0 · R + w1 · G + w2 · A; B is what multiple-scattering compensation needs. Four channels, so that every reader
    of RGBA images loads it (FreeImage, tinyexr and FFmpeg refuse or zero a two-channel EXR)."""
    linear, albedo = model_channels("adobe"), albedo_channels()

    def functions(x: np.ndarray) -> np.ndarray:
        terms = linear.functions(x)  # 1 - (1 - x)^5, (1 - x)^5, x (1 - x)^6
        return np.concatenate([terms[..., :2], albedo.functions(x), terms[..., 2:]], axis=-1)

    return ChannelSet(
        name="schlick",
        functions=functions,
        channel_names=("R", "G", "B", "A"),
        combination="R = scale, G = bias: Schlick's Fbar = F0 * R + F90 * G (Karis 2013); B = E = R + G, the GGX "
        "directional albedo without Fresnel (multiple-scattering compensation; the 'multiscatter DFG' form some "
        "engines store is (G, B)); A = the dip, integral of mu (1 - mu)^6: a linear model F = w0 (1 - (1 - mu)^5) + "
        "w1 (1 - mu)^5 + w2 mu (1 - mu)^6 (F82, F82 tint, generalised Adobe with p = 5) has Fbar = w0 * R + w1 * G + "
        "w2 * A exactly",
    )


def schlick_table_weights(model: str, **parameters) -> np.ndarray | None:
    """Weights (…, 4) of the Schlick table's R, G, B, A whose sum is a linear model's exact split sum, where the
    model's fixed functions are columns of the table (:func:`schlick_table_channels`: Schlick with F90, F82, F82
    tint, generalised Adobe and generalised Schlick with p = 5, Lazányi with α = 6); None for any other model.

    >>> schlick_table_weights("adobe", f0=0.9, tint=0.5).round(4).tolist()  # F̄ = 0.9 R + G − 8.3515 A
    [0.9, 1.0, 0.0, -8.3515]
    >>> schlick_table_weights("generalized-schlick", r0=0.04, r90=1.0, exponent=4.0) is None
    True
    """
    found = fresnel_model(model)
    if not found.linear:
        return None
    mu = np.linspace(0.0, 1.0, 65)
    shape = {key: value for key, value in parameters.items() if key in found.shape}
    terms, columns = found.channel_functions(**shape)(mu), schlick_table_channels().functions(mu)
    matches = [np.flatnonzero(np.max(np.abs(columns - terms[:, [n]]), axis=0) <= 1e-12) for n in range(terms.shape[1])]
    if any(match.size == 0 for match in matches):
        return None
    weights = found.channel_weights(**parameters)
    table = np.zeros(np.shape(weights)[:-1] + (4,))
    for n, match in enumerate(matches):
        table[..., match[0]] += weights[..., n]
    return table


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
