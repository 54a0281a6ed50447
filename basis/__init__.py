"""Fresnel curves and their eigen-basis (Belcour, Bati, Barla 2020).

The coefficient API engines call::

    from basis import coefficients_from_nk, coefficients_from_gulbrandsen, default_basis, material_coefficients

Public objects: ``Basis``, ``BasisFileError``, ``ParameterError``, ``default_basis``, ``coefficients_from_nk``,
``coefficients_from_gulbrandsen``, ``coefficients_from_curve``, ``coefficients_from_samples``,
``coefficients_from_table``, ``coefficients_least_squares``, ``coefficients_least_squares_from_table``,
``fit_condition_number``, ``reconstruct``, ``fresnel_conductor``, ``fresnel_dielectric``, ``gulbrandsen_to_nk``,
``nk_to_gulbrandsen``, ``material_coefficients``, ``material_preset``.

Modules: ``fresnel`` (exact Fresnel), ``gulbrandsen`` (artist parameters), ``training`` (the training domain,
the streaming iterative SVD, the basis build, held-out materials, the minimax refinement), ``eigenbasis`` (the
``Basis`` data and ``basis.json``), ``coefficients`` (the solvers), ``materials`` (what a material is: preset,
η/κ, r/g, F0, F0 + F82, model), ``validation``, ``colorimetry`` (working spaces, ΔE2000), ``spectral`` (measured
η(λ), κ(λ) → RGB curves), ``presets`` (the shipped presets of measured materials; no colour science),
``material_fits`` and ``delta_e_fits`` (ΔE2000 fits), ``datasets`` (Hoffman's published tables), ``models``
(approximate Fresnel models), ``angles`` (θ grids, the θ spline), ``storage`` (shipped paths, atomic writes,
journals, JSON documents), ``parallel`` (worker threads and BLAS threads).
"""

from .coefficients import (
    coefficients_from_curve,
    coefficients_from_gulbrandsen,
    coefficients_from_nk,
    coefficients_from_samples,
    coefficients_from_table,
    coefficients_least_squares,
    coefficients_least_squares_from_table,
    fit_condition_number,
    reconstruct,
)
from .eigenbasis import Basis, BasisFileError, default_basis
from .fresnel import fresnel_conductor, fresnel_dielectric
from .gulbrandsen import gulbrandsen_to_nk, nk_to_gulbrandsen
from .presets import material_coefficients, material_preset
from .validation import ParameterError

__all__ = [
    "Basis",
    "BasisFileError",
    "ParameterError",
    "coefficients_from_curve",
    "coefficients_from_gulbrandsen",
    "coefficients_from_nk",
    "coefficients_from_samples",
    "coefficients_from_table",
    "coefficients_least_squares",
    "coefficients_least_squares_from_table",
    "default_basis",
    "fit_condition_number",
    "fresnel_conductor",
    "fresnel_dielectric",
    "gulbrandsen_to_nk",
    "material_coefficients",
    "material_preset",
    "nk_to_gulbrandsen",
    "reconstruct",
]
