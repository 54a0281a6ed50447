"""Fresnel models compared in the report: the exact curve, Schlick's, and the eigen-basis.

Public objects: ``FresnelModel``, ``FRESNEL_MODELS``, ``fresnel_model``, ``fresnel_Schlick1994``,
``fresnel_Hoffman2019``, ``F82_MU``.

Every model splits into what a renderer stores per material, ``parameters(eta, kappa)`` (computed once,
shape (..., P)), and what it evaluates per shading sample, ``curve(mu, parameters)``. A material is the
pair (η, κ) of arrays, as in :func:`basis.holdout.holdout_materials`. ``shader_terms`` counts the LUT
channels a shader fetches for the preintegrated F̄ (split sum): 2 for Schlick (scale and bias), K for
the basis (one per element), ``None`` for the exact curve, which no shared LUT preintegrates.

=================  ======================================================================  ==========
name               F(μ)                                                                    parameters
=================  ======================================================================  ==========
``exact``          Fresnel equations of η + iκ (:func:`basis.fresnel.fresnel_conductor`)   η, κ
``schlick``        F0 + (1 − F0)(1 − μ)^5, F0 = F_exact(1)                                 F0
``basis-4point``   Σ c_k b_k, c from the four-point scheme (:func:`coefficients_from_nk`)  c (K)
``basis-lsq``      Σ c_k b_k, c by least squares in L2 over θ, F0 and F90 exact            c (K)
``basis-minimax``  Σ c_k b_k, c by Lawson-reweighted least squares (≈ max norm)            c (K)
=================  ======================================================================  ==========

Adding a model is adding one entry to ``FRESNEL_MODELS``.

References
----------
:cite:`Schlick1994` C. Schlick, "An Inexpensive BRDF Model for Physically-based Rendering", Computer
    Graphics Forum 13(3), 1994, eq. 15.
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4 and "Coefficients".
:cite:`Hoffman2020` SIGGRAPH 2020 Physically Based Shading course, "1823: Fresnel's Equations".
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np

from .coefficients import coefficients_from_nk, coefficients_least_squares
from .eigenbasis import Basis, default_basis
from .fresnel import ETA_RANGE, KAPPA_RANGE, _fresnel
from .validation import ParameterError, check_range

__all__ = ["F82_MU", "FRESNEL_MODELS", "FresnelModel", "fresnel_Hoffman2019", "fresnel_Schlick1994", "fresnel_model"]


def fresnel_Schlick1994(mu, f0) -> np.ndarray:
    """Schlick's approximation F = F0 + (1 − F0)(1 − μ)^5 (Schlick 1994, eq. 15).

    Parameters
    ----------
    mu : array_like
        Cosine of the angle of incidence, in [0, 1].
    f0 : array_like
        Reflectance at normal incidence, in [0, 1]; broadcast against ``mu``.

    Examples
    --------
    >>> float(fresnel_Schlick1994(0.0, 0.04))
    1.0
    """
    mu = check_range("mu", mu, 0.0, 1.0)
    f0 = check_range("f0", f0, 0.0, 1.0)
    return _schlick(mu, f0)


#: θ of Hoffman's F82 parameter: "approximately 82 degrees: to be precise, arccos(1/7)" (Hoffman 2020).
F82_MU = 1.0 / 7.0


def fresnel_Hoffman2019(mu, f0, f82) -> np.ndarray:
    """Hoffman's reparameterised Lazányi model with F82, clamped to [0, 1] (Hoffman 2020, "2019:
    Reparameterized Lazányi").

    F = F0 + (1 − F0)(1 − μ)^5 − a μ (1 − μ)^6,  a = 823543/46656 (F0 − F82) + 49/6 (1 − F0),

    so that F(arccos 1/7) = F82. Extreme (F0, F82) pairs leave [0, 1]; the result is clamped there, as
    Hoffman warns (a C1 kink).

    Parameters
    ----------
    mu : array_like
        Cosine of the angle of incidence, in [0, 1].
    f0, f82 : array_like
        Reflectance at normal incidence and at arccos(1/7) ≈ 81.8°, in [0, 1]; broadcast.

    Examples
    --------
    >>> round(float(fresnel_Hoffman2019(1.0 / 7.0, 0.9, 0.8)), 12)
    0.8
    """
    mu = check_range("mu", mu, 0.0, 1.0)
    f0 = check_range("f0", f0, 0.0, 1.0)
    f82 = check_range("f82", f82, 0.0, 1.0)
    return np.clip(_hoffman2019(mu, f0, f82), 0.0, 1.0)


def _hoffman2019(mu: np.ndarray, f0: np.ndarray, f82: np.ndarray) -> np.ndarray:
    """Unclamped, unchecked kernel of :func:`fresnel_Hoffman2019` (RGB values out of gamut may pass 1)."""
    a = 823543.0 / 46656.0 * (f0 - f82) + 49.0 / 6.0 * (1.0 - f0)
    return _schlick(mu, f0) - a * mu * (1.0 - mu) ** 6


def _checked_nk(eta, kappa) -> tuple[np.ndarray, np.ndarray]:
    eta = check_range("eta", eta, ETA_RANGE[0], ETA_RANGE[1])
    kappa = check_range("kappa", kappa, KAPPA_RANGE[0], KAPPA_RANGE[1])
    return np.broadcast_arrays(eta, kappa)


def _schlick(mu: np.ndarray, f0: np.ndarray) -> np.ndarray:
    return f0 + (1.0 - f0) * (1.0 - mu) ** 5


def _exact_parameters(eta, kappa, basis: Basis) -> np.ndarray:
    return np.stack(_checked_nk(eta, kappa), axis=-1)


def _exact_curve(mu: np.ndarray, parameters: np.ndarray, basis: Basis) -> np.ndarray:
    return _fresnel(mu, parameters[..., 0], parameters[..., 1])


def _schlick_parameters(eta, kappa, basis: Basis) -> np.ndarray:
    eta, kappa = _checked_nk(eta, kappa)
    return _fresnel(np.ones_like(eta), eta, kappa)[..., None]


def _schlick_curve(mu: np.ndarray, parameters: np.ndarray, basis: Basis) -> np.ndarray:
    return _schlick(mu, parameters[..., 0])


def _basis_curve(mu: np.ndarray, parameters: np.ndarray, basis: Basis) -> np.ndarray:
    """Σ_k c_k b_k(arccos μ), the cubic spline of the basis in θ (what a 1-D texture holds)."""
    return np.einsum("...k,...k->...", parameters, basis.spline(np.arccos(mu)))


def _four_point_parameters(eta, kappa, basis: Basis) -> np.ndarray:
    return coefficients_from_nk(eta, kappa, basis)


def _least_squares(weight: str) -> Callable[[np.ndarray, np.ndarray, Basis], np.ndarray]:
    def parameters(eta, kappa, basis: Basis) -> np.ndarray:
        return coefficients_least_squares(eta, kappa, basis, weight=weight)

    return parameters


@dataclasses.dataclass(frozen=True)
class FresnelModel:
    """One Fresnel model: per-material parameters, the per-sample curve and its shader cost.

    Attributes
    ----------
    name : str
        Registry key.
    description : str
        The formula in words, for tables and legends.
    parameters : callable
        (eta, kappa, basis) → (..., P) what a renderer stores per material and colour channel.
    curve : callable
        (mu, parameters, basis) → (...) F(μ); unchecked, μ in [0, 1] broadcast against the materials.
    lut_channels : int, "basis" or None
        LUT channels a shader fetches for F̄: a count, "basis" for ``basis.n_terms``, ``None`` if the
        model has no shared split-sum LUT.
    """

    name: str
    description: str
    parameters: Callable[[np.ndarray, np.ndarray, Basis], np.ndarray]
    curve: Callable[[np.ndarray, np.ndarray, Basis], np.ndarray]
    lut_channels: int | str | None

    def shader_terms(self, basis: Basis | None = None) -> int | None:
        """Number of LUT channels (multiply-adds per colour channel) a shader needs for F̄."""
        if self.lut_channels == "basis":
            return (default_basis() if basis is None else basis).n_terms
        return self.lut_channels

    def evaluate(self, mu, material, basis: Basis | None = None) -> np.ndarray:
        """F(μ) of ``material = (eta, kappa)``; μ broadcast against the material arrays.

        Parameters
        ----------
        mu : array_like
            Cosine of the angle of incidence, in [0, 1].
        material : tuple of array_like
            (η, κ), η in [1e-8, 1e6], κ in [0, 1e6], broadcast against each other.
        basis : Basis, optional
            Basis of the ``basis-*`` models; default the shipped one.

        Examples
        --------
        >>> round(float(FRESNEL_MODELS["schlick"].evaluate(1.0, (1.5, 0.0))), 12)
        0.04
        """
        basis = default_basis() if basis is None else basis
        if not isinstance(basis, Basis):
            raise ParameterError(f"basis must be a fresnel basis.Basis or None, got {type(basis).__name__}")
        if not isinstance(material, (tuple, list)) or len(material) != 2:
            raise ParameterError(f"material must be a pair (eta, kappa), got {type(material).__name__}")
        mu = check_range("mu", mu, 0.0, 1.0)
        return self.curve(mu, self.parameters(material[0], material[1], basis), basis)


#: Registry: name → model. ``--model NAME`` and the report's rows are one lookup here.
FRESNEL_MODELS: dict[str, FresnelModel] = {
    "exact": FresnelModel(
        "exact", "Fresnel equations of eta + i kappa (Hoffman 2020)", _exact_parameters, _exact_curve, None
    ),
    "schlick": FresnelModel(
        "schlick", "Schlick 1994, F0 from the exact curve", _schlick_parameters, _schlick_curve, 2
    ),
    "basis-4point": FresnelModel(
        "basis-4point", "eigen-basis, four-point coefficients (Belcour 2020)",
        _four_point_parameters, _basis_curve, "basis",
    ),
    "basis-lsq": FresnelModel(
        "basis-lsq", "eigen-basis, L2 least squares over theta, F0 and F90 exact",
        _least_squares("uniform"), _basis_curve, "basis",
    ),
    "basis-minimax": FresnelModel(
        "basis-minimax", "eigen-basis, Lawson-reweighted least squares (max norm), F0 and F90 exact",
        _least_squares("minimax"), _basis_curve, "basis",
    ),
}


def fresnel_model(name: str) -> FresnelModel:
    """Look up a model by name; the error lists the valid names.

    Examples
    --------
    >>> fresnel_model("schlick").shader_terms()
    2
    """
    try:
        return FRESNEL_MODELS[name]
    except (KeyError, TypeError):
        raise ParameterError(f"model must be one of {sorted(FRESNEL_MODELS)}, got {name!r}") from None
