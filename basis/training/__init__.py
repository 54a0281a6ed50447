"""Building the eigen-basis: the training set, the iterative SVD, the fit angles, the held-out materials.

Public objects: ``TrainingDomain``, ``Component``, ``DEFAULT_DOMAIN``, ``NOTEBOOK_DOMAIN``, ``REFINEMENT_DOMAINS`` (:mod:`.domain`, the seeded training
set); ``build_curves``, ``GramAccumulator``, ``MIN_SPAN`` (:mod:`.svd`, the streaming iterative SVD);
``build_basis``, ``choose_fit_angles``, ``holdout_fit_errors``, ``holdout_lines``, ``TALK_ANGLES``, ``NOTEBOOK_ANGLES``,
``FIT_ANGLE_CHOICES`` (:mod:`.builder`); ``holdout_materials``, ``validation_groups``, ``FIGURE_2``, ``VALIDATION_SEED`` (:mod:`.holdout`, never used in
training); ``refine_basis`` (:mod:`.refine`, the
minimax refinement of the curves and fit angles).

References
----------
:cite:`Belcour2020` SIGGRAPH 2020 Talks, "An Empirical Decomposition", eq. 4 and 6, and "Coefficients".
"""

from .builder import (
    FIT_ANGLE_CHOICES,
    NOTEBOOK_ANGLES,
    TALK_ANGLES,
    build_basis,
    choose_fit_angles,
    holdout_fit_errors,
    holdout_lines,
)
from .domain import DEFAULT_DOMAIN, NOTEBOOK_DOMAIN, REFINEMENT_DOMAINS, Component, TrainingDomain
from .holdout import FIGURE_2, VALIDATION_SEED, holdout_materials, validation_groups
from .refine import refine_basis
from .svd import MIN_SPAN, GramAccumulator, build_curves

__all__ = [
    "FIT_ANGLE_CHOICES",
    "DEFAULT_DOMAIN",
    "FIGURE_2",
    "MIN_SPAN",
    "NOTEBOOK_DOMAIN",
    "REFINEMENT_DOMAINS",
    "NOTEBOOK_ANGLES",
    "TALK_ANGLES",
    "VALIDATION_SEED",
    "Component",
    "GramAccumulator",
    "TrainingDomain",
    "build_basis",
    "holdout_lines",
    "build_curves",
    "choose_fit_angles",
    "holdout_fit_errors",
    "holdout_materials",
    "validation_groups",
    "refine_basis",
]
