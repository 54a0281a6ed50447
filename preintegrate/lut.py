"""Split-sum LUT tables: the texel grid and its convention, building a table, the header, the GPU's lookup.

Public objects: ``PIXEL_CONVENTION``, ``BASIS_LUT``, ``SCHLICK_LUT``, ``AVERAGE_LUT``, ``SHIPPED_LUTS``,
``model_lut_name``, ``second_rgba_path``, ``rgba_items``, ``texel_centres``, ``lut_axes``, ``lut_texel_weights``,
``shipped_lut``, ``build_table``, ``LUT_METHODS``, ``lut_attributes``, ``interpolation_weights``, ``lut_lookup``.

Column i ↔ μo = (i + 0.5)/W; row j ↔ perceptual roughness r = (j + 0.5)/H with α = r²; row 0 is
first in the file. Texel centres never touch μo = 0 or r = 0. A GPU reads a table with linear
interpolation between texel centres and clamps to the edge texels outside them; :func:`lut_lookup`
and :func:`interpolation_weights` are that rule, once.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable
from pathlib import Path

import numpy as np

from basis.storage import shipped_path
from basis.validation import ParameterError, check_choice, check_positive_int

from .channels import ChannelSet
from .estimators import hammersley_albedo
from .ggx import VISIBILITIES, roughness_to_alpha
from .quadrature import DEFAULT_ORDER, directional_albedo, texel_weights

__all__ = [
    "AVERAGE_LUT",
    "BASIS_LUT",
    "RGBA",
    "LUT_METHODS",
    "PIXEL_CONVENTION",
    "SCHLICK_LUT",
    "SHIPPED_LUTS",
    "rgba_items",
    "build_table",
    "pixel_convention",
    "interpolation_weights",
    "lut_attributes",
    "lut_axes",
    "lut_texel_weights",
    "lut_lookup",
    "model_lut_name",
    "second_rgba_path",
    "shipped_lut",
    "texel_centres",
]

#: File names of the default build's tables (``luts/``).
BASIS_LUT = "ggx_basis_rgba.exr"
SCHLICK_LUT = "ggx_schlick_rgb.exr"
#: E_avg(r), one column (:func:`preintegrate.multiple_scattering.average_albedo`).
AVERAGE_LUT = "ggx_albedo_average.exr"
SHIPPED_LUTS = (BASIS_LUT, SCHLICK_LUT, AVERAGE_LUT)


def model_lut_name(model: str, shape=()) -> str:
    """File name of a linear model's own table, its shape parameters in the name (``ggx_generalized-schlick_exponent6.exr``),
    so that tables of one model with two shapes never overwrite each other."""
    return f"ggx_{model}" + "".join(f"_{key}{value:g}" for key, value in dict(shape).items()) + ".exr"


def second_rgba_path(path) -> Path:
    """Where terms 4 … 7 of a basis table go (:func:`rgba_items`): ``<stem>_2<suffix>``."""
    path = Path(path)
    return path.with_name(f"{path.stem}_2{path.suffix}")

#: Channels of one texture an engine samples.
RGBA = ("R", "G", "B", "A")


def rgba_items(path, table: np.ndarray, attributes: dict[str, str]) -> list[tuple[Path, np.ndarray, tuple[str, ...], dict]]:
    """The files of a table of K ≤ 8 basis terms (H, W, K), as (path, values, channel names, header) items of
    :func:`preintegrate.exr.write_luts`: terms 0 … 3 in ``path`` (R, G, B, A), terms 4 … 7 in a second RGBA
    texture ``<stem>_2<suffix>`` (one more fetch in the shader). Each header is ``attributes`` with its own
    channels and, when there are two files, the terms it holds (``terms = "4-5 of 6"``)."""
    count = check_positive_int("basis terms", np.shape(table)[-1], low=1, high=8)
    path = Path(path)
    parts = [(path, slice(0, min(count, 4)))]
    if count > 4:
        parts.append((second_rgba_path(path), slice(4, count)))
    items = []
    for part_path, terms in parts:
        names = RGBA[: terms.stop - terms.start]
        header = {**attributes, "channels": ",".join(names)}
        if count > 4:
            header["terms"] = f"{terms.start}-{terms.stop - 1} of {count}"
        items.append((part_path, table[..., terms], names, header))
    return items
#: Written into every header: what produced the file.
GENERATOR = "fresnel-basis 0.1.0"

PIXEL_CONVENTION = (
    "column i <-> mu_o = cos(theta_o) = (i + 0.5) / width; row j <-> perceptual roughness r = (j + 0.5) / height, "
    "GGX alpha = r^2; row 0 first in the file (top); texel centres; values are directional albedos "
    "Fbar_k(mu_o, alpha) = integral of f_k(omega_o . h) * rho_GGX(omega_o, omega_i) * cos(theta_i) d omega_i, "
    "GGX with height-correlated Smith G2"
)


def shipped_lut(name: str = BASIS_LUT) -> Path:
    """Path of a LUT shipped with the package (``luts/`` beside it), whatever the working folder."""
    return shipped_path(check_choice("shipped LUT", name, SHIPPED_LUTS))


def texel_centres(count: int) -> np.ndarray:
    """(i + 0.5) / count, i = 0 … count − 1: the texel centres of one axis (unchecked)."""
    return (np.arange(count) + 0.5) / count


def lut_axes(width: int, height: int | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(μo of each column, perceptual roughness of each row) at texel centres."""
    width = check_positive_int("size", width, low=2, high=8192)
    height = width if height is None else check_positive_int("height", height, low=2, high=8192)
    return texel_centres(width), texel_centres(height)


def lut_texel_weights(theta_grid, size: int, order=DEFAULT_ORDER) -> np.ndarray:
    """(size², M): the texel weights (:func:`preintegrate.quadrature.texel_weights`) of every texel of a
    size × size table, row-major (roughness rows, μo columns): F̄ of curves sampled on ``theta_grid`` over
    the whole table is one matrix product."""
    mu_o, roughness = lut_axes(size)
    return texel_weights(theta_grid, mu_o[None, :], roughness_to_alpha(roughness)[:, None], order).reshape(size * size, -1)


def _quadrature(functions, mu_o, alpha, progress, order=DEFAULT_ORDER, visibility="height-correlated"):
    return directional_albedo(functions, mu_o, alpha, order=order, progress=progress, visibility=visibility)


def _hammersley(functions, mu_o, alpha, progress, samples=1024, sampling="ndf", max_samples=131_072):
    return hammersley_albedo(functions, mu_o, alpha, samples, sampling, max_samples, progress)


_TEXELS = ("functions", "mu_o", "alpha", "progress")

#: Registry: how a table's texels are computed. ``quadrature`` (options: ``order``) is this project's
#: deterministic integral; ``hammersley`` (options: ``samples``, ``sampling``, ``max_samples``) is the
#: engines' Monte-Carlo estimate (Karis 2013), kept to measure them against it.
LUT_METHODS: dict[str, Callable] = {"quadrature": _quadrature, "hammersley": _hammersley}


def build_table(
    channels: ChannelSet,
    width: int,
    height: int | None = None,
    method: str = "quadrature",
    progress: Callable[[int, int], None] | None = None,
    **options,
) -> np.ndarray:
    """(H, W, K) float64 table of the channel set on the texel grid, by a method of :data:`LUT_METHODS`.

    Examples
    --------
    >>> from preintegrate.channels import schlick_channels
    >>> build_table(schlick_channels(), 4, method="hammersley", samples=64).shape
    (4, 4, 2)
    """
    if not isinstance(channels, ChannelSet):
        raise ParameterError(f"channels must be a ChannelSet, got {type(channels).__name__}")
    compute = LUT_METHODS[check_choice("method", method, sorted(LUT_METHODS))]
    accepted = [name for name in inspect.signature(compute).parameters if name not in _TEXELS]
    unknown = sorted(set(options) - set(accepted))
    if unknown:
        raise ParameterError(f"method {method!r} takes the options {accepted}, got {unknown}")
    mu_o, roughness = lut_axes(width, height)
    return compute(channels.functions, mu_o[None, :], roughness_to_alpha(roughness)[:, None], progress, **options)


def pixel_convention(visibility: str = "height-correlated") -> str:
    """:data:`PIXEL_CONVENTION` for a table of the given masking-shadowing form (the header says which)."""
    if visibility == "height-correlated":
        return PIXEL_CONVENTION
    if visibility not in VISIBILITIES:
        raise ParameterError(f"visibility must be one of {sorted(VISIBILITIES)}, got {visibility!r}")
    return PIXEL_CONVENTION.replace("GGX with height-correlated Smith G2",
                                    "GGX with separable Smith G2 = G1(omega_o) * G1(omega_i)")


def lut_attributes(channels: ChannelSet, width: int, height: int, command: str, convention: str = PIXEL_CONVENTION,
                   **extra) -> dict[str, str]:
    """The header of a table of ``channels``: convention, size, channel names, the engine's combination
    rule, the generating command and any ``extra`` attributes (quadrature, basis hash, …)."""
    return {
        "convention": convention, "width": str(width), "height": str(height),
        "generator": f"{GENERATOR} ({command})", "channel_set": channels.name,
        "channels": ",".join(channels.channel_names), "combination": channels.combination,
        **{key: str(value) for key, value in extra.items()},
    }


def _clamped_position(points: np.ndarray, centres: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Lower texel index and fraction of linear interpolation between increasing ``centres``, clamped to
    the edge texels outside them (needs at least two centres)."""
    position = np.clip(np.interp(points, centres, np.arange(centres.size)), 0.0, centres.size - 1.0)
    low = np.minimum(np.floor(position).astype(int), centres.size - 2)
    return low, position - low


def interpolation_weights(points, centres) -> np.ndarray:
    """(P, N) weights of linear, clamp-to-edge interpolation from samples at ``centres`` (increasing)."""
    points, centres = np.ravel(points), np.asarray(centres, dtype=np.float64)
    weights = np.zeros((points.size, centres.size))
    if centres.size == 1:
        weights[:, 0] = 1.0
        return weights
    low, fraction = _clamped_position(points, centres)
    rows = np.arange(points.size)
    weights[rows, low] = 1.0 - fraction
    weights[rows, low + 1] += fraction
    return weights


def lut_lookup(table: np.ndarray, mu_o, roughness) -> np.ndarray:
    """Bilinear, clamp-to-edge fetch of a LUT (H, W, K) at (μo, r), as a GPU samples it at level 0."""
    height, width = table.shape[:2]
    mu_o = np.asarray(mu_o, dtype=np.float64)
    x0, fx = _clamped_position(mu_o, texel_centres(width))
    y0, fy = _clamped_position(np.broadcast_to(np.asarray(roughness, dtype=np.float64), mu_o.shape), texel_centres(height))
    fx, fy = fx[..., None], fy[..., None]
    return ((1 - fy) * ((1 - fx) * table[y0, x0] + fx * table[y0, x0 + 1])
            + fy * ((1 - fx) * table[y0 + 1, x0] + fx * table[y0 + 1, x0 + 1]))
