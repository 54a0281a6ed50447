"""Build recipes: the tables a build writes, as data, and the one writer of tables in every format.

Public objects: ``Table``, ``ATLAS_STEM``, ``THREE_FOLDER``, ``MATERIALX_FOLDER``, ``DEFAULT_SET``, ``DEFAULT_BUILD_FILES``, ``rgba_tables``, ``default_tables``, ``model_table``,
``ltc_build_table``, ``ltc_table``, ``kept_ltc_grid``, ``coefficient_build_table``, ``curve_table``, ``table_file_name``,
``write_tables``, ``write_default_build``, ``write_model_build``.

A :class:`Table` is a name (the file's stem), its values (H, W, K) on a :class:`~preintegrate.lut.LutGrid`, its
channel names and its header. :func:`default_tables` is the list a default build writes (the basis table, split
into RGBA files of four terms; Schlick's scale, bias and E; the one-column E_avg), :func:`model_table` a linear
model's own exact table; :func:`write_tables` writes any list in every format of
:data:`handoff.formats.FORMATS` as one transaction that owns its set (:func:`basis.storage.write_together`).
``fresnel-lut build`` and ``fresnel-lut scene`` both write through it, and so does every later table.
"""

from __future__ import annotations

import dataclasses
import os
import re
from collections.abc import Callable, Sequence
from pathlib import Path

import numpy as np

from basis.coefficient_table import COEFFICIENT_TABLE_SIZE, REFLECTIVITY_MAX, coefficient_table, coefficient_table_axes
from basis.eigenbasis import Basis, resolve_basis
from basis.models import fresnel_model
from basis.storage import write_together
from basis.validation import ParameterError, check_positive_int
from preintegrate.channels import (
    ChannelSet,
    average_albedo_channels,
    basis_channels,
    combine,
    model_channels,
    schlick_table_channels,
)
from preintegrate.ggx import VISIBILITIES
from preintegrate.ltc import LTC_CHANNELS, LtcFit, ltc_grid
from preintegrate.ltc_choice import fit_area_ltc
from preintegrate.lut import LutGrid, build_table
from preintegrate.multiple_scattering import AVERAGE_NODES, average_albedo
from preintegrate.quadrature import DEFAULT_ORDER

from .atlas import pack_atlas
from .exr import read_lut
from .formats import FORMATS, check_formats, file_family
from .materialx import write_materialx_library
from .shaders import ATLAS_INCLUDE_STEM, INCLUDE_STEM, LANGUAGES, SHADER_INCLUDES, shader_includes
from .shipped import (
    AVERAGE_LUT,
    BASIS_LUT,
    COEFFICIENT_LUT,
    COEFFICIENT_LUT_TERMS,
    CURVE_LUT,
    CURVE_LUT_SIZE,
    CURVE_LUT_TERMS,
    LTC_LUT,
    PACKAGE_VERSION,
    RGBA,
    SCHLICK_LUT,
    lut_attributes,
    model_lut_name,
    table_header,
)
from .three import write_three_package

__all__ = [
    "ATLAS_STEM",
    "MATERIALX_FOLDER",
    "THREE_FOLDER",
    "DEFAULT_BUILD_FILES",
    "DEFAULT_SET",
    "Table",
    "coefficient_build_table",
    "curve_table",
    "default_tables",
    "kept_ltc_grid",
    "ltc_build_table",
    "ltc_table",
    "model_table",
    "rgba_tables",
    "table_file_name",
    "write_default_build",
    "write_model_build",
    "write_tables",
]


@dataclasses.dataclass(frozen=True, eq=False)
class Table:
    """One table of a build: ``name`` (the file's stem), ``values`` (H, W, K) float64, the channel names and the
    header attributes (texts)."""

    name: str
    values: np.ndarray
    channel_names: tuple[str, ...]
    attributes: dict[str, str]


def _stem(file_name: str) -> str:
    return Path(file_name).stem


#: The stems of the default build's set: the basis table (terms 4 … 7 of a larger basis in ``_2``), Schlick's
#: table and E_avg, and the three-channel Schlick table of the builds before it gained the dip channel (December
#: 2026). A default build owns these in every format: those it does not write are removed. The area lights' LTC
#: table joins the set only when the build fits it (``--ltc``): a build without it keeps the folder's.
DEFAULT_SET = (_stem(BASIS_LUT), f"{_stem(BASIS_LUT)}_2", _stem(SCHLICK_LUT), "ggx_schlick_rgb", _stem(AVERAGE_LUT))


def _channels_stem(shipped: str, channels: int) -> str:
    """The stem of a shipped per-pixel table (``COEFFICIENT_LUT``, ``CURVE_LUT``) for ``channels`` channels: its
    channel suffix replaced (``fresnel_coefficients_rgba`` for a five-term basis)."""
    return _stem(shipped).rsplit("_", 1)[0] + "_" + "rgba"[:channels]


#: The per-pixel tables' stems of every basis size that has them, owned by a build with ``--pixel-tables``.
_PIXEL_TABLE_STEMS = tuple(_channels_stem(COEFFICIENT_LUT, k) for k in range(1, 5)) + tuple(
    _channels_stem(CURVE_LUT, k) for k in range(1, 5)
)


#: Every file of a default build of a four-term basis: the tables and the generated shader include.
DEFAULT_BUILD_FILES = (BASIS_LUT, SCHLICK_LUT, AVERAGE_LUT, *(name for name, _ in SHADER_INCLUDES.values()))
#: The includes of the builds before one include per build (December 2026): a build removes them with its set.
LEGACY_INCLUDES = tuple(f"fresnel_basis_material.{language}" for language in LANGUAGES)


def table_file_name(name: str, format_name: str = "exr") -> str:
    """The file a table of stem ``name`` is written to in a format of :data:`~handoff.formats.FORMATS`."""
    return name + FORMATS[check_formats([format_name])[0]].suffix


def rgba_tables(name: str, values: np.ndarray, attributes: dict[str, str]) -> list[Table]:
    """A table of K ≤ 8 basis terms (H, W, K) as the textures an engine samples: terms 0 … 3 in ``name`` (R, G, B,
    A), terms 4 … 7 in ``<name>_2`` (one more fetch in the shader). Each header is ``attributes`` with its own
    channels and, when there are two, the terms it holds (``terms = "4-5 of 6"``)."""
    count = check_positive_int("basis terms", np.shape(values)[-1], low=1, high=8)
    parts = [(name, slice(0, min(count, 4)))] + ([(f"{name}_2", slice(4, count))] if count > 4 else [])
    tables = []
    for part, terms in parts:
        names = RGBA[: terms.stop - terms.start]
        header = {**attributes, "channels": ",".join(names)}
        if count > 4:
            header["terms"] = f"{terms.start}-{terms.stop - 1} of {count}"
        tables.append(Table(part, values[..., terms], names, header))
    return tables


def default_tables(
    basis: Basis | None = None,
    grid: LutGrid | None = None,
    order=DEFAULT_ORDER,
    progress: Callable[[int, int], None] | None = None,
    command: str = "fresnel-lut build",
) -> list[Table]:
    """The tables of a default build on ``grid`` (default 128 × 128, height-correlated): the basis and Schlick
    channels integrated in one pass, then E_avg(r) at the grid's rows (Kulla and Conty 2017)."""
    basis = resolve_basis(basis)
    grid = LutGrid(128, 128) if grid is None else grid
    if (grid.rows, grid.columns, grid.roughness_range) != ("endpoints", "root-endpoints", (0.0, 1.0)):
        raise ParameterError(
            "the default build's tables are on the default grid: columns at sqrt(mu_o) end points, rows at the end "
            "points of roughness 0-1 (LutGrid(width, height))"
        )
    basis_set, schlick_set, average_set = basis_channels(basis), schlick_table_channels(), average_albedo_channels()
    values = build_table(combine(basis_set, schlick_set), grid, order=order, progress=progress)
    k, quadrature, convention = basis_set.n_channels, order.describe(), grid.convention
    basis_header = lut_attributes(
        basis_set,
        grid.width,
        grid.height,
        command,
        convention,
        quadrature=quadrature,
        basis_hash=basis.content_hash,
        basis_fit_angles=",".join(f"{angle:.6f}" for angle in basis.fit_angles),
    )
    average = average_albedo(grid.roughness, grid.visibility, order)[:, None, None]
    return [
        *rgba_tables(_stem(BASIS_LUT), values[:, :, :k], basis_header),
        Table(
            _stem(SCHLICK_LUT),
            values[:, :, k:],
            schlick_set.channel_names,
            lut_attributes(schlick_set, grid.width, grid.height, command, convention, quadrature=quadrature),
        ),
        Table(
            _stem(AVERAGE_LUT),
            average,
            average_set.channel_names,
            lut_attributes(
                average_set,
                1,
                grid.height,
                command,
                f"one column; rows as in: {convention}",
                quadrature=f"{AVERAGE_NODES} Gauss-Legendre nodes in mu, each: {quadrature}",
            ),
        ),
    ]


def model_table(
    model: str,
    shape: dict | None = None,
    grid: LutGrid | None = None,
    order=DEFAULT_ORDER,
    progress: Callable[[int, int], None] | None = None,
    command: str = "fresnel-lut build --model",
) -> tuple[Table, ChannelSet]:
    """The exact split-sum table of a linear model with its shape parameters (defaults filled in), named by both
    (:func:`handoff.shipped.model_lut_name`), and its channel set (whose ``combination`` says how to read it)."""
    grid = LutGrid(128, 128) if grid is None else grid
    found = fresnel_model(model)
    given = dict(shape or {})
    unused = sorted(set(given) - set(found.shape))
    if unused:
        raise ParameterError(f"model {found.name} takes the shape parameters {list(found.shape)}, not {unused}")
    found.channel_functions(**given)  # a non-linear model is refused here, with the list of linear ones
    shape = found.shape_values(**given)
    channels = model_channels(found.name, **shape)
    values = build_table(channels, grid, order=order, progress=progress)
    header = lut_attributes(
        channels,
        grid.width,
        grid.height,
        command,
        grid.convention,
        quadrature=order.describe(),
        **{f"model_{key}": value for key, value in channels.provenance.items()},
    )
    return Table(_stem(model_lut_name(found.name, shape)), values, channels.channel_names, header), channels


def write_tables(
    tables: Sequence[Table],
    out,
    formats=("exr",),
    half: bool = False,
    texts=(),
    owned: Sequence[str] = (),
    owned_files: Sequence[str] = (),
) -> list[Path]:
    """Write ``tables`` into the folder ``out`` in every format asked for, with ``texts`` ((file name, UTF-8 text)
    pairs that belong to the same build), as one transaction; the paths written, tables first.

    ``owned``: the stems of the set this build owns (e.g. :data:`DEFAULT_SET`); the tables of that set the build
    does not write, in any format, are removed in the same transaction, and so are the files named in
    ``owned_files`` that it does not write (a scene's basis); nothing else of the folder is.
    ``half`` stores half floats (EXR, KTX2) and rounds the values of the other formats the same way.
    """
    formats = check_formats(formats)
    out = Path(out)
    writers = []  # every table is checked and encoded here, before any file is begun
    for table in tables:
        if not isinstance(table, Table):
            raise ParameterError(f"tables must be Table records, got {type(table).__name__}")
        for name in formats:
            fmt = FORMATS[name]
            writers.append(
                (
                    out / table_file_name(table.name, name),
                    fmt.writer(table.values, table.channel_names, table.attributes, table.name, half),
                )
            )
    writers += [(out / name, lambda path, text=text: path.write_text(text, encoding="utf-8")) for name, text in texts]
    if not writers:
        raise ParameterError("write_tables needs at least one table or text to write")
    patterns = ([file_family(owned)] if owned else []) + [re.escape(name) for name in owned_files]
    return write_together(writers, owned="|".join(patterns) or None)


def write_default_build(
    out,
    basis: Basis | None = None,
    grid: LutGrid | None = None,
    order=DEFAULT_ORDER,
    formats=("exr",),
    half: bool = False,
    progress: Callable[[int, int], None] | None = None,
    ltc: LutGrid | None = None,
    ltc_progress: Callable[[int, int], None] | None = None,
    pixel_tables: bool = False,
    atlas: bool = False,
    three: bool = False,
    materialx: bool = False,
) -> list[Path]:
    """``fresnel-lut build``: :func:`default_tables` written by :func:`write_tables`, owning :data:`DEFAULT_SET`, with
    the shader includes generated from the same basis (:mod:`handoff.shaders`) in the same
    transaction, so that tables and per-pixel coefficients always share one basis; with ``ltc`` (``--ltc``), the
    area lights' LTC table fitted on that grid (:func:`ltc_build_table`) too; with ``pixel_tables``
    (``--pixel-tables``), the per-pixel tables: Gulbrandsen's (r, g) → coefficients (:func:`coefficient_build_table`)
    and the direct-light curves over V·H (:func:`curve_table`); with ``atlas`` (``--atlas``, which needs both), every
    table the include reads packed into one texture (:func:`handoff.atlas.pack_atlas`) and the include that reads it,
    ``fresnel_basis_atlas.*``; with ``three`` (``--three``, which needs ``ltc``), the three.js package in
    ``out/three/`` (:func:`handoff.three.write_three_package`, its own transaction after the tables'); with
    ``materialx`` (``--materialx``, which needs ``atlas``), the MaterialX node library in ``out/materialx/``
    (:func:`handoff.materialx.write_materialx_library`, likewise)."""
    formats = check_formats(formats)  # refused before the work
    basis = resolve_basis(basis)
    if atlas and (ltc is None or not pixel_tables):
        raise ParameterError("--atlas packs every table the include reads: build it with --ltc and --pixel-tables")
    if materialx and not atlas:
        raise ParameterError("--materialx reads the atlas: build it with --atlas (and so --ltc --pixel-tables)")
    if three and (ltc is None or basis.n_terms != 4):
        raise ParameterError(
            "--three packs the basis, Schlick and LTC tables of a four-term basis: build it with --ltc"
        )
    if ltc is not None and (not isinstance(ltc, LutGrid) or not ltc.transposed):
        raise ParameterError(f"ltc must be an LTC table's grid (preintegrate.ltc.ltc_grid) or None, got {ltc!r}")
    visibility = (LutGrid(128, 128) if grid is None else grid).visibility
    if ltc is not None and ltc.visibility != visibility:
        raise ParameterError(f"the LTC table's visibility {ltc.visibility!r} must be the build's, {visibility!r}")
    kept = kept_ltc_grid(out, visibility) if ltc is None else None  # refused before the work
    includes = shader_includes(basis, grid=grid, ltc_size=(ltc or kept or ltc_grid()).width)
    tables = default_tables(basis, grid, order, progress)
    if ltc is not None:
        tables.append(ltc_build_table(ltc, ltc_progress))
    if pixel_tables:
        tables += [coefficient_build_table(basis), curve_table(basis)]
    atlas_includes = []
    if atlas:
        packed, atlas_includes = _atlas(tables, basis, grid, ltc.width, command="fresnel-lut build --atlas")
        tables.append(packed)
        includes += atlas_includes
    written = write_tables(
        tables,
        out,
        formats,
        half,
        texts=includes,
        owned=DEFAULT_SET
        + ((_stem(LTC_LUT),) if ltc is not None else ())
        + ((ATLAS_STEM,) if atlas else ())
        + (_PIXEL_TABLE_STEMS if pixel_tables else ()),
        owned_files=[
            *(name for name, _ in SHADER_INCLUDES.values()),
            *(name.replace(INCLUDE_STEM, ATLAS_INCLUDE_STEM, 1) for name, _ in SHADER_INCLUDES.values()),
            *LEGACY_INCLUDES,
        ],
    )
    if three:
        by_stem = {table.name: table.values for table in tables}
        roles = {"basis": _stem(BASIS_LUT), "schlick": _stem(SCHLICK_LUT), "ltc": _stem(LTC_LUT)}
        package = {role: by_stem[stem] for role, stem in roles.items()}
        written += write_three_package(Path(out) / THREE_FOLDER, basis, package, grid, ltc.width, PACKAGE_VERSION)
    if materialx:
        include = dict(atlas_includes)[f"{ATLAS_INCLUDE_STEM}.glsl"]
        written += write_materialx_library(Path(out) / MATERIALX_FOLDER, include, basis.content_hash)
    return written


#: The three.js package's folder in a build (``fresnel-lut build --three``).
THREE_FOLDER = "three"
#: The MaterialX node library's folder in a build (``fresnel-lut build --materialx``).
MATERIALX_FOLDER = "materialx"


#: The atlas' stem (``fresnel-lut build --atlas``).
ATLAS_STEM = "fresnel_atlas_rgba"


def _atlas(tables: list[Table], basis: Basis, grid, ltc_size: int, command: str) -> tuple[Table, list[tuple[str, str]]]:
    """The atlas of a build's tables, by role, and the includes that read it."""
    by_stem = {table.name: table.values for table in tables}
    stems = {
        "basis": _stem(BASIS_LUT),
        "basis2": f"{_stem(BASIS_LUT)}_2",
        "schlick": _stem(SCHLICK_LUT),
        "ltc": _stem(LTC_LUT),
        "coefficients": _channels_stem(COEFFICIENT_LUT, basis.n_terms - 1),
        "curves": _channels_stem(CURVE_LUT, basis.n_terms - 1),
    }
    values, layout = pack_atlas({role: by_stem[stem] for role, stem in stems.items() if stem in by_stem})
    header = table_header(
        "atlas",
        RGBA,
        "every table the include fresnel_basis_atlas reads, each in its rectangle inside a guard ring of its edge texels",
        layout.width,
        layout.height,
        command,
        "tables at (x0, y0, width, height) of their first texel: " + layout.describe(),
        basis_hash=basis.content_hash,
    )
    maps = {role: layout.uv_map(role) for role in layout.rects}
    return Table(ATLAS_STEM, values, RGBA, header), shader_includes(basis, command, grid, ltc_size, atlas=maps)


def kept_ltc_grid(out, visibility: str) -> LutGrid | None:
    """The grid of the LTC table a build without ``--ltc`` keeps in ``out`` (its includes address that table), None
    where there is none; a table of another visibility, or one that cannot be read, is refused with what to run."""
    path = Path(out) / LTC_LUT
    if not os.path.lexists(path):
        return None
    refit = f"add --ltc to fit it anew for this build (fresnel-lut build --ltc --out {out}), or remove it"
    try:
        _, header = read_lut(path)
        size = int(header["width"])
        grids = [ltc_grid(size, form) for form in VISIBILITIES]
    except (ParameterError, KeyError) as error:
        raise ParameterError(f"{path} cannot be read as an LTC table ({error}): {refit}") from None
    found = next((grid for grid in grids if grid.convention == header.get("convention")), None)
    if found is None:
        raise ParameterError(f"{path} is not an LTC table of this project's (its convention differs): {refit}")
    if found.visibility != visibility:
        raise ParameterError(f"{path} was fitted for {found.visibility} G2 and this build is {visibility}: {refit}")
    return found


def ltc_build_table(grid: LutGrid | None = None, progress: Callable[[int, int], None] | None = None) -> Table:
    """The area lights' LTC table (:func:`preintegrate.ltc_choice.fit_area_ltc`) as a :class:`Table` named after
    :data:`LTC_LUT`."""
    return ltc_table(fit_area_ltc(grid, progress))


def ltc_table(fit: LtcFit, command: str = "fresnel-lut build --ltc") -> Table:
    """A fitted LTC table: the stored M⁻¹ entries (size, size, 4), their names and the header with the fit's method
    and lobe error."""
    grid = fit.grid
    header = table_header(
        "ltc",
        LTC_CHANNELS,
        "specular = polygon integral of the LTC x split sum of the basis table (sum_k c_k b_k)",
        grid.width,
        grid.height,
        command,
        grid.convention,
        ltc_fit=fit.method,
        ltc_lobe_error_max=f"{float(np.max(fit.error)):.6g}",
        ltc_lobe_error_mean=f"{float(np.mean(fit.error)):.6g}",
    )
    return Table(_stem(LTC_LUT), fit.inverse, LTC_CHANNELS, header)


def coefficient_build_table(
    basis: Basis | None = None, fit: str = "weighted", command: str = "fresnel-lut build --pixel-tables"
) -> Table:
    """The table of Gulbrandsen's (r, g) → c2 … c_(K−1) and f90 (:func:`basis.coefficient_table.coefficient_table`)
    of a basis of three to five terms, with the basis hash, the axes and the criterion in its header."""
    basis = resolve_basis(basis)
    if basis.n_terms not in COEFFICIENT_LUT_TERMS:
        raise ParameterError(
            f"the coefficient table holds c2 ... c(K-1) and f90 in one RGBA texture: a basis of 3 to 5 terms, not "
            f"{basis.n_terms}"
        )
    width, height = COEFFICIENT_TABLE_SIZE
    first, step = coefficient_table_axes(width, height)
    names = (*(f"c{k}" for k in range(2, basis.n_terms)), "f90")
    criteria = {
        "weighted": "weighted least squares over theta, c0 and c1 exact, one weight per basis angle for every texel "
        "(Lawson's reweighting of the worst ratio to the four-point solve's max error over the table's materials); "
        "max over theta of |F - F_exact| bounds the split sum's error too",
        "minimax": "minimax over theta of |F - F_exact| on the basis grid, c0 and c1 exact (40 Lawson steps)",
        "four-point": "the four-point solve at the basis' fit angles",
    }
    header = table_header(
        "gulbrandsen coefficients",
        names,
        "per colour channel: c0 = r, c1 = f90 - r, (c2 ...) = texture(x, y) (all 0 at r = 0)",
        width,
        height,
        command,
        f"columns: x = r^(1/4) - sqrt(1 - r)/2, texel centres from x = {first!r} by {step!r} (r = 0 at x = -0.5, a "
        f"quarter texel before column 0, which holds r = 0: all 0; the last centre r = {REFLECTIVITY_MAX}); rows: "
        f"y = 1 - (1 - g)^(1/4) at {height} end points from g = 0 to 1 (bilinear, clamp)",
        basis_hash=basis.content_hash,
        fit=fit,
        criterion=criteria[fit],
    )
    return Table(_channels_stem(COEFFICIENT_LUT, basis.n_terms - 1), coefficient_table(basis, fit), names, header)


def curve_table(basis: Basis | None = None, command: str = "fresnel-lut build --pixel-tables") -> Table:
    """The direct-light curves b_1 … b_(K−1) of a basis of two to five terms at :data:`CURVE_LUT_SIZE` end points of
    μ = V·H (one row; ``fresnelBasisDirectTable`` reads it with one fetch)."""
    basis = resolve_basis(basis)
    if basis.n_terms not in CURVE_LUT_TERMS:
        raise ParameterError(
            f"the curve table holds b1 ... b(K-1) in one RGBA texture: a basis of 2 to 5 terms, not {basis.n_terms}"
        )
    names = tuple(f"b{k}" for k in range(1, basis.n_terms))
    header = table_header(
        "direct-light curves",
        names,
        "F(V.H) = c0 + sum_k c_k texture(V.H).k per colour channel (b0 = 1)",
        CURVE_LUT_SIZE,
        1,
        command,
        f"one row; columns: mu = V.H at {CURVE_LUT_SIZE} end points from 0 to 1 (texel centres on both ends; bilinear, "
        "clamp)",
        basis_hash=basis.content_hash,
    )
    values = basis.evaluate_mu(np.linspace(0.0, 1.0, CURVE_LUT_SIZE))[None, :, 1:]
    return Table(_channels_stem(CURVE_LUT, basis.n_terms - 1), values, names, header)


def write_model_build(
    out,
    model: str,
    shape: dict | None = None,
    grid: LutGrid | None = None,
    order=DEFAULT_ORDER,
    formats=("exr",),
    half: bool = False,
    progress: Callable[[int, int], None] | None = None,
) -> tuple[list[Path], ChannelSet]:
    """``fresnel-lut build --model``: :func:`model_table` written by :func:`write_tables`, owning its own table."""
    formats = check_formats(formats)
    table, channels = model_table(model, shape, grid, order, progress)
    return write_tables([table], out, formats, half, owned=[table.name]), channels
