"""One registry of approximate Fresnel models, each with its parameters and, where it has one, its
linear form.

Public objects: ``Parameter``, ``LinearTerms``, ``FresnelModel``, ``FRESNEL_MODELS``, ``fresnel_model``.

Every model is a vectorised evaluator with validated parameters. Most are linear in a fixed set of
functions of μ = cos θ once their *shape* parameters (an exponent, a representative IOR) are fixed:
F = Σ_n w_n(parameters) t_n(μ). Their GGX split sums are then exact with one LUT channel per t_n
(``fresnel-lut build --model NAME``), as Schlick's two channels are (Karis 2013). Two models with the
same fixed functions (:class:`LinearTerms` compare by family and shape) share one table: Schlick's
serves ``schlick``, the external-media variants and pbrt's ``fresnel-blend``. A model whose curve leaves
[0, 1] is clamped there; the split-sum channels are exact only while the clamp is inactive
(:meth:`FresnelModel.clamp_is_inactive`). Channel sets, ``build --model``, scene layouts and the CLI's
options are all derived from this registry; adding a model is adding one entry.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from ..fresnel import ETA_RANGE, KAPPA_RANGE, fresnel_kernel
from ..gulbrandsen import gulbrandsen_to_nk
from ..validation import ParameterError, check_choice, check_range
from .formulas import (
    ETA_E_RANGE,
    F82_MU,
    adobe_dip_weight,
    f82_dip_weight,
    hoffman2019_curve,
    lazanyi_curve,
    lazanyi_dip,
    metal_external_f0,
    schlick_curve,
    schlick_external_f0,
    schlick_weight,
)

__all__ = ["FRESNEL_MODELS", "FresnelModel", "LinearTerms", "Parameter", "fresnel_model"]

#: μ samples on which :meth:`FresnelModel.clamp_is_inactive` checks the unclamped curve.
_CHECK_MU = np.concatenate([np.linspace(0.0, 1.0, 2001), [F82_MU]])


@dataclasses.dataclass(frozen=True)
class Parameter:
    """A model parameter: its name, accepted range and whether it is an RGB colour (…, 3) or a scalar."""

    name: str
    low: float
    high: float
    description: str
    colour: bool = True
    default: float | None = None


@dataclasses.dataclass(frozen=True)
class LinearTerms:
    """The fixed functions t_n(μ) of a linear model, called as t(μ) → (..., n).

    Two instances are equal when their ``family`` and ``shape`` are: they are then the same functions and
    need the same LUT channels.
    """

    family: str
    shape: tuple[float, ...]
    functions: Callable[[np.ndarray], np.ndarray] = dataclasses.field(compare=False, repr=False)

    def __call__(self, mu: np.ndarray) -> np.ndarray:
        return self.functions(mu)


def _power_terms(exponent: float) -> LinearTerms:
    """(1 − (1 − μ)^p, (1 − μ)^p): Schlick's scale and bias channels for p = 5 (Karis 2013)."""

    def terms(mu: np.ndarray) -> np.ndarray:
        weight = schlick_weight(mu, exponent)
        return np.stack([1.0 - weight, weight], axis=-1)

    return LinearTerms("power", (float(exponent),), terms)


def _dip_terms(exponent: float, dip_exponent: float = 6.0) -> LinearTerms:
    """The power terms and the Lazányi dip μ (1 − μ)^α."""

    def terms(mu: np.ndarray) -> np.ndarray:
        weight = schlick_weight(mu, exponent)
        return np.stack([1.0 - weight, weight, lazanyi_dip(mu, dip_exponent)], axis=-1)

    return LinearTerms("dip", (float(exponent), float(dip_exponent)), terms)


def _cook_torrance_terms(eta_prime: float, kappa_prime: float) -> LinearTerms:
    # Hoffman 2020's corrected interpolation: g = max(0, F′(θ) − F′(0)) / (1 − F′(0)), F = F0 (1 − g) + g
    f_normal = float(fresnel_kernel(np.array(1.0), np.array(eta_prime), np.array(kappa_prime)))
    if f_normal >= 1.0:
        raise ParameterError(f"eta_prime, kappa_prime = {eta_prime}, {kappa_prime} reflect everything (F'(0) = 1)")
    if eta_prime == 1.0 and kappa_prime == 0.0:
        raise ParameterError("eta_prime = 1, kappa_prime = 0 is no interface (F' = 0): the interpolation is undefined")

    def terms(mu: np.ndarray) -> np.ndarray:
        g = np.maximum(0.0, fresnel_kernel(mu, np.array(eta_prime), np.array(kappa_prime)) - f_normal) / (
            1.0 - f_normal
        )
        return np.stack([1.0 - g, g], axis=-1)

    return LinearTerms("cook-torrance", (float(eta_prime), float(kappa_prime)), terms)


@dataclasses.dataclass(frozen=True)
class FresnelModel:
    """One model of the references.

    Attributes
    ----------
    name, reference, formula : str
        Registry key, citation with equation number, the formula in words.
    parameters : tuple of Parameter
        What a material sets; ``shape`` names those that fix the channel functions (scalars).
    curve : callable
        (μ, parameters) → F, unclamped and unchecked; μ broadcast against the parameters.
    terms : callable or None
        (shape parameters) → t(μ) with values (..., n): the fixed functions of the linear form, or None
        if the model is not linear in fixed functions.
    weights : callable or None
        (parameters) → (..., n) with F = Σ w_n t_n.
    clamp : bool
        Whether the curve is clamped to [0, 1] (models with a dip term).
    terms_description : str
        The fixed functions t_n in words (EXR headers).
    combination : str
        How an engine combines the model's LUT channels into F̄, where it differs from the generic
        ``Fbar = w0 * R + w1 * G …`` (Schlick's scale and bias).
    sweep : tuple of dict
        The documented parameter sweep of the projection-error table (scalars, one curve each).
    """

    name: str
    reference: str
    formula: str
    parameters: tuple[Parameter, ...]
    curve: Callable[[np.ndarray, dict], np.ndarray]
    terms: Callable[..., Callable[[np.ndarray], np.ndarray]] | None = None
    weights: Callable[[dict], np.ndarray] | None = None
    shape: tuple[str, ...] = ()
    clamp: bool = False
    sweep: tuple[dict, ...] = ()
    terms_description: str = ""
    combination: str = ""

    @property
    def linear(self) -> bool:
        return self.terms is not None

    def check(self, **values) -> dict:
        """Validated float64 parameters (names, ranges, shapes); errors name the parameter and its range."""
        expected = {parameter.name for parameter in self.parameters}
        unknown = set(values) - expected
        if unknown:
            raise ParameterError(f"model {self.name!r} takes {sorted(expected)}, got unknown {sorted(unknown)}")
        checked = {}
        for parameter in self.parameters:
            value = values.get(parameter.name, parameter.default)
            if value is None:
                raise ParameterError(f"model {self.name!r} needs {parameter.name} ({parameter.description})")
            value = check_range(parameter.name, value, parameter.low, parameter.high)
            if parameter.name in self.shape and value.ndim != 0:
                raise ParameterError(
                    f"{parameter.name} fixes the LUT channels and must be one number, got shape {value.shape}"
                )
            if not parameter.colour and value.ndim != 0:
                raise ParameterError(
                    f"{parameter.name} ({parameter.description}) is one number, got shape {value.shape}"
                )
            checked[parameter.name] = value
        return checked

    def evaluate(self, mu, **values) -> np.ndarray:
        """F(μ) for validated parameters; μ in [0, 1] broadcast against them (clamped to [0, 1] if ``clamp``)."""
        mu = check_range("mu", mu, 0.0, 1.0)
        curve = self.curve(mu, self.check(**values))
        return np.clip(curve, 0.0, 1.0) if self.clamp else curve

    def shape_values(self, **values) -> dict[str, float]:
        """The shape parameters that fix the channels, from ``values`` or their defaults (others ignored)."""
        shape = {}
        for parameter in self.parameters:
            if parameter.name in self.shape:
                value = values.get(parameter.name, parameter.default)
                if value is None:
                    raise ParameterError(f"model {self.name!r} needs {parameter.name} to fix its channels")
                value = check_range(parameter.name, value, parameter.low, parameter.high)
                if value.ndim != 0:
                    raise ParameterError(
                        f"{parameter.name} fixes the LUT channels and must be one number, got shape {value.shape}"
                    )
                shape[parameter.name] = float(value)
        return shape

    def channel_functions(self, **values) -> LinearTerms:
        """t(μ) → (..., n) for the shape parameters in ``values`` (others ignored)."""
        if not self.linear:
            raise ParameterError(
                f"model {self.name!r} is not linear in fixed functions of cos theta; "
                f"linear models: {sorted(n for n, m in FRESNEL_MODELS.items() if m.linear)}"
            )
        return self.terms(**self.shape_values(**values))

    def channel_weights(self, **values) -> np.ndarray:
        """(…, n) weights of :meth:`channel_functions` for validated parameters."""
        if not self.linear:
            self.channel_functions()
        return self.weights(self.check(**values))

    def clamp_is_inactive(self, **values) -> np.ndarray:
        """True where the unclamped curve stays in [0, 1] (then Σ w_n t̄_n is the exact split sum)."""
        checked = self.check(**values)
        mu = _CHECK_MU.reshape((-1,) + (1,) * max(np.ndim(v) for v in checked.values()))
        curve = self.curve(mu, checked)
        tolerance = 1e-12
        return np.all((curve >= -tolerance) & (curve <= 1.0 + tolerance), axis=0)


def _generalized_adobe_a(p: dict) -> np.ndarray:
    return adobe_dip_weight(p["r0"], p["tint"], p["r90"], p["exponent"])


_F0 = Parameter("f0", 0.0, 1.0, "reflectance at normal incidence")
_R0 = Parameter("r0", 0.0, 1.0, "reflectance at normal incidence")
_R90 = Parameter("r90", 0.0, 1.0, "reflectance at grazing incidence")
_EXPONENT = Parameter("exponent", 0.1, 50.0, "exponent p of (1 - cos theta)", colour=False, default=5.0)
_TINT = Parameter("tint", 0.0, 1.0, "tint of the reflectance at arccos(1/7) (1 = no dip)")
_ETA_PRIME = Parameter("eta_prime", *ETA_RANGE, "representative (scalar) eta", colour=False)
_KAPPA_PRIME = Parameter("kappa_prime", *KAPPA_RANGE, "representative (scalar) kappa", colour=False, default=0.0)
_ETA_E = Parameter("eta_e", *ETA_E_RANGE, "index of the external medium", colour=False)

_F0_SWEEP = (0.02, 0.04, 0.1, 0.3, 0.5, 0.7, 0.9, 0.98)


def _grid(**axes) -> tuple[dict, ...]:
    names = list(axes)
    mesh = np.meshgrid(*(np.asarray(axes[name], dtype=float) for name in names), indexing="ij")
    return tuple({name: float(values.flat[i]) for name, values in zip(names, mesh)} for i in range(mesh[0].size))


#: Registry: name → model. ``--model NAME`` of ``build`` and ``coeffs`` is one lookup here.
FRESNEL_MODELS: dict[str, FresnelModel] = {}


def _register(model: FresnelModel) -> None:
    FRESNEL_MODELS[model.name] = model


_register(
    FresnelModel(
        "schlick",
        "Schlick 1994, eq. 15",
        "F0 + (1 - F0)(1 - mu)^5",
        (_F0,),
        curve=lambda mu, p: schlick_curve(mu, p["f0"]),
        terms=lambda: _power_terms(5.0),
        terms_description="(1 - (1-x)^5, (1-x)^5), w = (f0, 1)",
        combination="Fbar = F0 * R + G (Karis 2013; R = scale, G = bias)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["f0"], 1.0), axis=-1),
        sweep=_grid(f0=_F0_SWEEP),
    )
)
_register(
    FresnelModel(
        "generalized-schlick",
        "Hoffman 2023, eq. 4 (F90 and exponent); the GLSL tutorial's artistic exponent",
        "r0 + (r90 - r0)(1 - mu)^p",
        (_R0, _R90, _EXPONENT),
        curve=lambda mu, p: schlick_curve(mu, p["r0"], p["r90"], p["exponent"]),
        terms=lambda exponent: _power_terms(exponent),
        terms_description="(1 - (1-x)^p, (1-x)^p), w = (r0, r90)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["r0"], p["r90"]), axis=-1),
        shape=("exponent",),
        sweep=_grid(r0=(0.04, 0.5, 0.9), r90=(0.5, 1.0), exponent=(0.5, 1.0, 2.0, 3.0, 5.0, 8.0, 15.0)),
    )
)
_register(
    FresnelModel(
        "lazanyi",
        "Lazanyi and Szirmay-Kalos 2005; Hoffman 2023, eq. 2",
        "F0 + (1 - F0)(1 - mu)^5 - a mu (1 - mu)^alpha",
        (
            _F0,
            Parameter("a", -20.0, 20.0, "weight of the dip term"),
            Parameter("alpha", 1.0, 30.0, "exponent of the dip term", colour=False, default=6.0),
        ),
        curve=lambda mu, p: lazanyi_curve(mu, p["f0"], p["a"], p["alpha"]),
        terms=lambda alpha: _dip_terms(5.0, alpha),
        terms_description="(1 - (1-x)^5, (1-x)^5, x (1-x)^alpha), w = (f0, 1, -a)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["f0"], 1.0, -p["a"]), axis=-1),
        shape=("alpha",),
        clamp=True,
        sweep=_grid(f0=(0.04, 0.5, 0.9), a=(0.0, 0.5, 1.0, 2.0), alpha=(3.0, 6.0, 10.0)),
    )
)
_register(
    FresnelModel(
        "f82",
        "Hoffman 2020, '2019: Reparameterized Lazanyi' (beta = 6, theta_max = arccos 1/7)",
        "F0 + (1 - F0)(1 - mu)^5 - a mu (1 - mu)^6, a = 823543/46656 (F0 - F82) + 49/6 (1 - F0), clamped",
        (_F0, Parameter("f82", 0.0, 1.0, "reflectance at arccos(1/7), about 82 degrees")),
        curve=lambda mu, p: hoffman2019_curve(mu, p["f0"], p["f82"]),
        terms=lambda: _dip_terms(5.0),
        terms_description="(1 - (1-x)^5, (1-x)^5, x (1-x)^6), w = (f0, 1, -a), a = 823543/46656 (f0 - f82) + 49/6 (1 - f0)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["f0"], 1.0, -f82_dip_weight(p["f0"], p["f82"])), axis=-1),
        clamp=True,
        sweep=_grid(f0=(0.04, 0.3, 0.6, 0.9), f82=(0.0, 0.2, 0.4, 0.6, 0.8, 1.0)),
    )
)
_register(
    FresnelModel(
        "adobe",
        "Kutz et al. 2021 (Adobe Standard Material); Hoffman 2023, eq. 2-3",
        "F0 + (1 - F0)(1 - mu)^5 - a mu (1 - mu)^6, a from the tint t at arccos(1/7)",
        (_F0, _TINT),
        curve=lambda mu, p: lazanyi_curve(mu, p["f0"], adobe_dip_weight(p["f0"], p["tint"])),
        terms=lambda: _dip_terms(5.0),
        terms_description="(1 - (1-x)^5, (1-x)^5, x (1-x)^6), w = (f0, 1, -a), a from the tint (Hoffman 2023 eq. 3)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["f0"], 1.0, -adobe_dip_weight(p["f0"], p["tint"])), axis=-1),
        clamp=True,
        sweep=_grid(f0=(0.04, 0.3, 0.6, 0.9), tint=(0.0, 0.25, 0.5, 0.75, 1.0)),
    )
)
_register(
    FresnelModel(
        "generalized-adobe",
        "Hoffman 2023, eq. 5-6",
        "r0 + (r90 - r0)(1 - mu)^p - a mu (1 - mu)^6, a from the tint t at arccos(1/7)",
        (_R0, _R90, _EXPONENT, _TINT),
        curve=lambda mu, p: (
            schlick_curve(mu, p["r0"], p["r90"], p["exponent"]) - _generalized_adobe_a(p) * lazanyi_dip(mu)
        ),
        terms=lambda exponent: _dip_terms(exponent),
        terms_description="(1 - (1-x)^p, (1-x)^p, x (1-x)^6), w = (r0, r90, -a), a from the tint (Hoffman 2023 eq. 6)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["r0"], p["r90"], -_generalized_adobe_a(p)), axis=-1),
        shape=("exponent",),
        clamp=True,
        sweep=_grid(r0=(0.04, 0.6, 0.9), r90=(0.6, 1.0), exponent=(2.0, 5.0, 8.0), tint=(0.0, 0.5, 1.0)),
    )
)
_register(
    FresnelModel(
        "cook-torrance",
        "Hoffman 2020, Cook-Torrance colour interpolation (corrected form)",
        "F0 + (1 - F0) max(0, F'(mu) - F'(1)) / (1 - F'(1)), F' = Fresnel of (eta', kappa')",
        (_F0, _ETA_PRIME, _KAPPA_PRIME),
        curve=lambda mu, p: _cook_torrance_curve(mu, p),
        terms=lambda eta_prime, kappa_prime: _cook_torrance_terms(eta_prime, kappa_prime),
        terms_description="(1 - g, g), g = max(0, F'(x) - F'(1)) / (1 - F'(1)), w = (f0, 1)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["f0"], 1.0), axis=-1),
        shape=("eta_prime", "kappa_prime"),
        # representative IORs of a dielectric, a glass, gold and aluminium at 550 nm
        sweep=tuple(
            {"f0": f0, "eta_prime": eta, "kappa_prime": kappa}
            for f0 in (0.04, 0.5, 0.9)
            for eta, kappa in ((1.33, 0.0), (1.5, 0.0), (0.42, 2.35), (0.96, 6.69))
        ),
    )
)


def _cook_torrance_curve(mu: np.ndarray, p: dict) -> np.ndarray:
    terms = _cook_torrance_terms(float(p["eta_prime"]), float(p["kappa_prime"]))(mu)  # (..., 2)
    return p["f0"] * terms[..., 0] + terms[..., 1]


def _external_curve(adjust) -> Callable[[np.ndarray, dict], np.ndarray]:
    def curve(mu: np.ndarray, p: dict) -> np.ndarray:
        return schlick_curve(mu, adjust(p["f0"], p["eta_e"]))

    return curve


def _external_weights(adjust) -> Callable[[dict], np.ndarray]:
    def weights(p: dict) -> np.ndarray:
        return np.stack(np.broadcast_arrays(adjust(p["f0"], p["eta_e"]), 1.0), axis=-1)

    return weights


for _name, _adjust, _reference in (
    ("schlick-external", schlick_external_f0, "Hoffman 2020, 'External Media Adjustment' (dielectric formula)"),
    ("schlick-external-metal", metal_external_f0, "Hoffman 2020, 'External Media Adjustment' (metal variant)"),
):
    _register(
        FresnelModel(
            _name,
            _reference,
            "Schlick with F0' = adjusted F0 for an external medium of index eta_e",
            (_F0, _ETA_E),
            curve=_external_curve(_adjust),
            terms=lambda: _power_terms(5.0),
            terms_description="(1 - (1-x)^5, (1-x)^5), w = (adjusted f0, 1)",
            weights=_external_weights(_adjust),
            sweep=_grid(f0=(0.04, 0.3, 0.6, 0.9), eta_e=(1.0, 1.33, 1.6, 2.0, 2.42)),
        )
    )

_register(
    FresnelModel(
        "exact-external",
        "Hoffman 2020: divide eta and kappa by the external medium's eta",
        "Fresnel equations of (eta / eta_e, kappa / eta_e)",
        (Parameter("eta", *ETA_RANGE, "real part of the IOR"), Parameter("kappa", *KAPPA_RANGE, "extinction"), _ETA_E),
        curve=lambda mu, p: fresnel_kernel(mu, p["eta"] / p["eta_e"], p["kappa"] / p["eta_e"]),
        sweep=_grid(eta=(0.2, 1.5, 2.5), kappa=(0.0, 3.0), eta_e=(1.0, 1.33, 2.0)),
    )
)
_register(
    FresnelModel(
        "gulbrandsen",
        "Gulbrandsen 2014, eq. 7-9, then the Fresnel equations",
        "Fresnel equations of gulbrandsen_to_nk(r, g)",
        # r = 1 is refused by gulbrandsen_to_nk itself, with the reason (η, κ out of range)
        (Parameter("reflectivity", 0.0, 1.0, "reflectivity r"), Parameter("edge_tint", 0.0, 1.0, "edge tint g")),
        curve=lambda mu, p: fresnel_kernel(mu, *gulbrandsen_to_nk(p["reflectivity"], p["edge_tint"])),
        sweep=_grid(reflectivity=(0.04, 0.3, 0.6, 0.9), edge_tint=(0.0, 0.5, 1.0)),
    )
)
_register(
    FresnelModel(
        "fresnel-blend",
        "pbrt 3rd ed. 8.5, FresnelBlend (Ashikhmin and Shirley 2000): its SchlickFresnel",
        "Rs + (1 - Rs)(1 - cos theta_d)^5 (the diffuse term is in preintegrate.fresnel_blend)",
        (Parameter("rs", 0.0, 1.0, "specular reflectance Rs"),),
        curve=lambda mu, p: schlick_curve(mu, p["rs"]),
        terms=lambda: _power_terms(5.0),
        terms_description="(1 - (1-x)^5, (1-x)^5), w = (rs, 1)",
        weights=lambda p: np.stack(np.broadcast_arrays(p["rs"], 1.0), axis=-1),
        sweep=_grid(rs=_F0_SWEEP),
    )
)


def fresnel_model(name: str) -> FresnelModel:
    """Look up a model; the error lists the valid names.

    Examples
    --------
    >>> fresnel_model("schlick").channel_functions()(np.array(1.0)).tolist()
    [1.0, 0.0]
    """
    return FRESNEL_MODELS[check_choice("model", name, sorted(FRESNEL_MODELS))]
