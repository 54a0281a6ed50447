"""The files a build ships and what names them: the default build's table names, a linear model's table name, the
header every table carries, and the shipped tables read back.

Public objects: ``BASIS_LUT``, ``SCHLICK_LUT``, ``AVERAGE_LUT``, ``LTC_LUT``, ``COEFFICIENT_LUT``, ``CURVE_LUT``,
``COEFFICIENT_LUT_TERMS``, ``CURVE_LUT_TERMS``, ``PACKAGE_VERSION``,
``CURVE_LUT_SIZE``, ``SHIPPED_LUTS``, ``RGBA``, ``GENERATOR``,
``model_lut_name``, ``shipped_lut``, ``shipped_tables``, ``table_header``, ``lut_attributes``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from basis.storage import shipped_path
from basis.validation import check_choice
from preintegrate.channels import ChannelSet
from preintegrate.lut import PIXEL_CONVENTION

from .exr import read_lut

__all__ = [
    "AVERAGE_LUT",
    "BASIS_LUT",
    "COEFFICIENT_LUT",
    "COEFFICIENT_LUT_TERMS",
    "CURVE_LUT",
    "CURVE_LUT_TERMS",
    "CURVE_LUT_SIZE",
    "GENERATOR",
    "LTC_LUT",
    "PACKAGE_VERSION",
    "RGBA",
    "SCHLICK_LUT",
    "SHIPPED_LUTS",
    "lut_attributes",
    "model_lut_name",
    "shipped_lut",
    "shipped_tables",
    "table_header",
]

#: File names of the default build's tables (``luts/``).
BASIS_LUT = "ggx_basis_rgba.exr"
SCHLICK_LUT = "ggx_schlick_rgba.exr"
#: E_avg(r), one column (:func:`preintegrate.multiple_scattering.average_albedo`).
AVERAGE_LUT = "ggx_albedo_average.exr"
#: The area lights' LTC table (``fresnel-lut build --ltc``; :mod:`preintegrate.ltc`).
LTC_LUT = "ggx_ltc.exr"
#: Gulbrandsen's (r, g) → c2, c3 and f90 of a four-term basis (``fresnel-lut build --pixel-tables``;
#: :mod:`basis.coefficient_table`); a basis of K terms has K − 1 channels (``fresnel_coefficients_rgba`` for five).
COEFFICIENT_LUT = "fresnel_coefficients_rgb.exr"
#: The basis sizes K whose per-pixel tables fit one RGBA texture each (c2 … c_(K−1) and f90; b1 … b_(K−1)): the others
#: have none, and the include solves (or evaluates the polynomial) instead.
COEFFICIENT_LUT_TERMS = range(3, 6)
CURVE_LUT_TERMS = range(2, 6)
#: The direct-light curves b_1 … b_(K−1) of the basis over μ = V·H, one row (``fresnel-lut build --pixel-tables``), and
#: its texels (end points of μ from 0 to 1): with a guard texel on each side, WebGL 2's guaranteed largest texture width
#: (an atlas holds it: handoff.atlas); linear interpolation between them holds the shipped basis' curves within 2.5e-5,
#: 6.0e-5 with 8-bit filter weights (the polynomial: 2.2e-5).
CURVE_LUT = "fresnel_curves_rgb.exr"
CURVE_LUT_SIZE = 2046
SHIPPED_LUTS = (BASIS_LUT, SCHLICK_LUT, AVERAGE_LUT)
#: Channels of one texture an engine samples.
RGBA = ("R", "G", "B", "A")
#: The project's version (pyproject.toml's), which the packages it writes carry.
PACKAGE_VERSION = "0.1.0"
#: Written into every header: what produced the file.
GENERATOR = f"fresnel-basis {PACKAGE_VERSION}"


def model_lut_name(model: str, shape=()) -> str:
    """File name of a linear model's own table, its shape parameters in the name (``ggx_generalized-schlick_exponent6.exr``),
    so that tables of one model with two shapes never overwrite each other."""
    return f"ggx_{model}" + "".join(f"_{key}{value:g}" for key, value in dict(shape).items()) + ".exr"


def shipped_lut(name: str = BASIS_LUT) -> Path:
    """Path of a LUT shipped with the package (``luts/`` beside it), whatever the working folder."""
    return shipped_path(check_choice("shipped LUT", name, SHIPPED_LUTS))


def shipped_tables() -> tuple[np.ndarray, np.ndarray]:
    """(basis table, Schlick table) of the shipped LUTs, as :func:`handoff.exr.read_lut` checks them."""
    return read_lut(shipped_lut())[0], read_lut(shipped_lut(SCHLICK_LUT))[0]


def table_header(
    channel_set: str,
    channel_names,
    combination: str,
    width: int,
    height: int,
    command: str,
    convention: str = PIXEL_CONVENTION,
    **extra,
) -> dict[str, str]:
    """The header of every table: convention, size, generating command, channel set and names, the engine's
    combination rule, then any ``extra`` attributes (quadrature, basis hash, an LTC fit's error, …)."""
    return {
        "convention": convention,
        "width": str(width),
        "height": str(height),
        "generator": f"{GENERATOR} ({command})",
        "channel_set": channel_set,
        "channels": ",".join(channel_names),
        "combination": combination,
        **{key: str(value) for key, value in extra.items()},
    }


def lut_attributes(
    channels: ChannelSet, width: int, height: int, command: str, convention: str = PIXEL_CONVENTION, **extra
) -> dict[str, str]:
    """The header of a table of ``channels`` (:func:`table_header` of its name, channels and combination rule; a
    scene names its table's layout in ``channel_set`` instead)."""
    name = extra.pop("channel_set", channels.name)
    return table_header(name, channels.channel_names, channels.combination, width, height, command, convention, **extra)
