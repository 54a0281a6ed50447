"""Split-sum LUT tables on the engine's texel grid.

Public objects: ``lut_axes``, ``build_table``, ``PIXEL_CONVENTION``.

Column i ↔ μo = (i + 0.5)/W; row j ↔ perceptual roughness r = (j + 0.5)/H with α = r²; row 0 is
first in the file. Texel centres never touch μo = 0 or r = 0.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from basis.validation import check_positive_int

from .channels import ChannelSet
from .ggx import roughness_to_alpha
from .quadrature import DEFAULT_ORDER, QuadratureOrder, QuadratureSchedule, directional_albedo

__all__ = ["PIXEL_CONVENTION", "build_table", "lut_axes"]

PIXEL_CONVENTION = (
    "column i <-> mu_o = cos(theta_o) = (i + 0.5) / width; row j <-> perceptual roughness r = (j + 0.5) / height, "
    "GGX alpha = r^2; row 0 first in the file (top); texel centres; values are directional albedos "
    "Fbar_k(mu_o, alpha) = integral of f_k(omega_o . h) * rho_GGX(omega_o, omega_i) * cos(theta_i) d omega_i, "
    "GGX with height-correlated Smith G2"
)


def lut_axes(width: int, height: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(μo of each column, perceptual roughness of each row) at texel centres."""
    width = check_positive_int("size", width, low=2, high=8192)
    height = width if height is None else check_positive_int("height", height, low=2, high=8192)
    return (np.arange(width) + 0.5) / width, (np.arange(height) + 0.5) / height


def build_table(
    channels: ChannelSet,
    width: int,
    height: int | None = None,
    order: QuadratureOrder | QuadratureSchedule = DEFAULT_ORDER,
    progress: Callable[[int, int], None] | None = None,
) -> np.ndarray:
    """(H, W, K) float64 table of the channel set on the texel grid."""
    mu_o, roughness = lut_axes(width, height)
    alpha = roughness_to_alpha(roughness)
    table = directional_albedo(channels.functions, mu_o[None, :], alpha[:, None], order=order, progress=progress)
    return table
