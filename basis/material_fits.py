"""Measured materials as basis coefficients: fitting RGB Fresnel curves, and the shipped presets.

Public objects: ``ANGLES_DEGREES``, ``rms_delta_E_2000``, ``delta_e_fit``,
``fit_rgb_curve``, ``fit_material``, ``material_curve``, ``build_presets``, ``minimise_delta_e``.
The presets themselves are read by :mod:`basis.presets`, which needs none of this.

A material's ground truth is its RGB Fresnel curve by Hoffman's spectral procedure
(:func:`basis.spectral.rgb_fresnel`). Its error is Hoffman's measure: the RMS over θ = 0°, 1°, …, 90° of
CIEDE2000 between the approximation and the ground truth (with this sampling his dielectric Schlick
column is reproduced to 0.01; ``tests/basis/test_material_fits.py``).

Coefficient fits (:data:`basis.coefficients.COEFFICIENT_FITS`); all keep F(90°) = c0 + c1 exact (white):

==================  ==============================================================================
``four-point``      the talk's scheme: the curve at the basis' fit angles (Belcour 2020, eq. 5)
``least-squares``   L2 over θ on the basis grid, c0 = F0 exact
                    (:func:`basis.coefficients_least_squares_from_table`)
``delta-e-exact-f0`` c2, c3 minimising Σ_θ ΔE2000² on a 0.25° grid, c0 = F0 exact, from the
                    least-squares start
``delta-e``         c0, c2, c3 minimising the same, c1 = F90 − c0: F0 may move by an invisible ΔE
                    (the presets report it as ``delta_e2000_at_0``); what the presets use
==================  ==============================================================================

The shader cost is the same for all three: four multiply-adds per channel. Presets
(``luts/materials.json``) store the ``delta-e`` coefficients for ACEScg and sRGB, with F0, F82, the
data source and the achieved errors; they are tied to the basis by its content hash.

References
----------
:cite:`Hoffman2020` SIGGRAPH 2020 course notes, ΔE2000 tables and "Computing RGB Parameter Values From
    Spectral IOR Data".
:cite:`Belcour2020` SIGGRAPH 2020 Talks, eq. 4–5.
"""

from __future__ import annotations

import functools
from collections.abc import Callable

import numpy as np
import scipy.optimize

from .angles import cos_theta
from .coefficients import coefficients_from_function
from .colorimetry import delta_E_2000, delta_E_2000_Lab, rgb_to_Lab, working_space
from .eigenbasis import Basis, resolve_basis
from .models.formulas import F82_MU, schlick_curve
from .presets import FORMAT, PRESET_SPACES, VERSION
from .spectral import rgb_fresnel, spectral_ior, spectral_iors

__all__ = [
    "ANGLES_DEGREES",
    "build_presets",
    "fit_material",
    "fit_rgb_curve",
    "material_curve",
    "delta_e_fit",
    "minimise_delta_e",
    "rms_delta_E_2000",
]

#: Hoffman's angle sampling of "ΔE2000 averaged over all incidence angles": 0°, 1°, …, 90°.
ANGLES_DEGREES = np.arange(0.0, 91.0)
#: The finer grid the ``delta-e`` fit minimises on (0.25°), so that it is not fitted to the scoring samples.
_FIT_DEGREES = np.linspace(0.0, 90.0, 361)

Curve = Callable[[np.ndarray], np.ndarray]


def rms_delta_E_2000(reference, approximation, space: str) -> float | np.ndarray:
    """RMS over the angle axis (second to last) of ΔE2000 between two RGB curves (..., A, 3) → (...)."""
    difference = delta_E_2000(reference, approximation, space)
    return np.sqrt(np.mean(difference**2, axis=-1))


def material_curve(name: str, space: str = "ACEScg") -> Curve:
    """The ground-truth RGB curve μ (...) → (..., 3) of a measured material in ``space``."""
    material = spectral_ior(name)
    working_space(space)
    return functools.partial(rgb_fresnel, material, space=space)


def minimise_delta_e(reference_Lab: np.ndarray, rgb_of: Callable[[np.ndarray], np.ndarray], initial: np.ndarray,
                     space: str, bounds=(-np.inf, np.inf)) -> np.ndarray:
    """Parameters p minimising Σ ΔE2000(reference, rgb_of(p))² (scipy's trust-region least squares).

    ``rgb_of`` maps parameters (..., P) to RGB curves (..., A, 3) and must accept a stack of parameter
    vectors: the forward-difference Jacobian evaluates all P perturbations in one colour-science call.
    """

    def residuals(parameters: np.ndarray) -> np.ndarray:
        return delta_E_2000_Lab(reference_Lab, rgb_to_Lab(rgb_of(parameters), space))

    def jacobian(parameters: np.ndarray) -> np.ndarray:
        step = 1e-7 * np.maximum(1.0, np.abs(parameters))
        if np.isfinite(bounds[1]).all() if np.ndim(bounds[1]) else np.isfinite(bounds[1]):
            step = np.where(parameters + step > bounds[1], -step, step)  # stay inside an upper bound
        return ((residuals(parameters + np.diag(step)) - residuals(parameters)) / step[:, None]).T

    return scipy.optimize.least_squares(residuals, initial, jac=jacobian, bounds=bounds).x


def delta_e_fit(values_of: Callable, space: str, basis: Basis, free_f0: bool) -> np.ndarray:
    """(3, K): minimise Σ_θ ΔE2000² over c2 … c_{K−1} (and c0 if ``free_f0``), with c0 + c1 = F90 kept exact.

    ``values_of`` maps μ (A,) to the RGB curve (3, A); the ``delta-e`` entries of
    :data:`basis.coefficients.COEFFICIENT_FITS` call this.
    """
    # the free-F0 fit starts from the exact-F0 optimum, so it can only improve on it
    start = (delta_e_fit(values_of, space, basis, False) if free_f0
             else coefficients_from_function(values_of, "least-squares", basis))
    theta = np.deg2rad(_FIT_DEGREES)
    truth = values_of(cos_theta(theta)).T
    reference = rgb_to_Lab(truth, space)
    curves = basis.evaluate(theta)  # (A, K)
    f90 = truth[-1]
    # F = c0 (b0 − b1) + F90 b1 + Σ_{k≥2} c_k b_k once c1 = F90 − c0
    fixed = f90[:, None] * curves[:, 1] + (0.0 if free_f0 else start[:, :1] * (curves[:, 0] - curves[:, 1]))
    shapes = [curves[:, 0] - curves[:, 1]] if free_f0 else []
    shape = np.stack([*shapes, *curves[:, 2:].T], axis=1)  # (A, free terms)
    initial = np.concatenate([start[:, :1], start[:, 2:]], axis=1) if free_f0 else start[:, 2:]

    def rgb_of(free: np.ndarray) -> np.ndarray:
        return fixed.T + np.einsum("...cj,aj->...ac", free.reshape(*free.shape[:-1], 3, -1), shape)

    free = minimise_delta_e(reference, rgb_of, initial.ravel(), space).reshape(3, -1)
    c0 = free[:, :1] if free_f0 else start[:, :1]
    return np.concatenate([c0, f90[:, None] - c0, free[:, 1:] if free_f0 else free], axis=1)


def fit_rgb_curve(curve: Curve, space: str = "ACEScg", fit: str = "delta-e", basis: Basis | None = None) -> np.ndarray:
    """(3, K) coefficients of an RGB curve μ → (..., 3) by a fit of :data:`basis.coefficients.COEFFICIENT_FITS`."""
    working_space(space)
    return coefficients_from_function(lambda mu: curve(mu).T, fit, basis, space)


_FITS: dict[tuple, np.ndarray] = {}


def fit_material(name: str, space: str = "ACEScg", fit: str = "delta-e", basis: Basis | None = None) -> np.ndarray:
    """(3, K) coefficients of a measured material by a fit of :data:`basis.coefficients.COEFFICIENT_FITS`
    (memoised per basis hash).

    Unlike :func:`material_coefficients` this always fits; the presets, the tables and the report share
    the fits through the memo.
    """
    basis = resolve_basis(basis)
    key = (name, space, fit, basis.content_hash)
    if key not in _FITS:
        _FITS[key] = fit_rgb_curve(material_curve(name, space), space, fit, basis)
    return _FITS[key].copy()


def build_presets(
    basis: Basis | None = None, fit: str = "delta-e", progress: Callable[[int, int], None] | None = None
) -> dict:
    """The JSON document of ``luts/materials.json`` for every measured material and :data:`PRESET_SPACES`.

    ``progress(done, total)`` is called after each material.
    """
    basis = resolve_basis(basis)
    theta = np.deg2rad(ANGLES_DEGREES)
    materials = {}
    measured = spectral_iors()
    for done, (name, material) in enumerate(measured.items(), start=1):
        spaces = {}
        for space in PRESET_SPACES:
            curve = material_curve(name, space)
            truth = curve(cos_theta(theta))
            coefficients = fit_material(name, space, fit, basis)
            f0 = truth[0]
            schlick = schlick_curve(cos_theta(theta)[:, None], f0)
            spaces[space] = {
                "f0": [round(float(v), 8) for v in f0],
                "f82": [round(float(v), 8) for v in curve(np.array(F82_MU))],
                "coefficients": [[round(float(v), 10) for v in row] for row in coefficients],
                "rms_delta_e2000": {
                    "basis": round(float(rms_delta_E_2000(truth, (coefficients @ basis.evaluate(theta).T).T, space)), 4),
                    "schlick": round(float(rms_delta_E_2000(truth, schlick, space)), 4),
                },
                "delta_e2000_at_0": round(float(delta_E_2000(f0, coefficients[:, 0], space)), 4),
            }
        source = material.source
        materials[name] = {
            "kind": material.kind,
            "source": {key: source[key] for key in ("database", "file", "references", "constant_eta", "note") if key in source},
            **spaces,
        }
        if progress is not None:
            progress(done, len(measured))
    return {
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
            "spaces": "ACEScg: D60 illuminant, Bradford to the ACES white; sRGB: linear Rec.709 primaries, D65",
        },
        "materials": materials,
    }


