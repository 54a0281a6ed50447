"""Split-sum LUT tables: the texel grid and its convention, building a table, the GPU's lookup (the files, their
names and headers are :mod:`handoff`'s).

Public objects: ``LutGrid``, ``ROW_PLACEMENTS``, ``COLUMN_PLACEMENTS``, ``LTC_LAYOUT``, ``PIXEL_CONVENTION``, ``texel_centres``,
``lut_texel_weights``, ``build_table``, ``LUT_METHODS``, ``interpolation_weights``, ``lut_lookup``.

Column i ↔ √μo = i/(W − 1), row j ↔ perceptual roughness r = j/(H − 1) with α = r² (the default build; a scene's
rows span its materials' roughness range; other placements for comparison: :class:`LutGrid`); row 0 is first in the
file. Both ends of both axes stand on a texel, which a GPU reads through the half-texel remap
u = (x (W − 1) + 0.5)/W (the include's coordinate function), with linear interpolation between texels;
:meth:`LutGrid.lookup`, :func:`lut_lookup` and :meth:`LutGrid.column_weights` are that rule, once.
"""

from __future__ import annotations

import dataclasses
import inspect
from collections.abc import Callable

import numpy as np

from basis.validation import (
    ParameterError,
    as_float_array,
    check_broadcast,
    check_choice,
    check_positive_int,
    check_range,
)

from .channels import ChannelSet
from .estimators import hammersley_albedo
from .ggx import VISIBILITIES, roughness_to_alpha
from .quadrature import DEFAULT_ORDER, directional_albedo, texel_weights

__all__ = [
    "COLUMN_PLACEMENTS",
    "LTC_LAYOUT",
    "LUT_METHODS",
    "PIXEL_CONVENTION",
    "build_table",
    "LutGrid",
    "ROW_PLACEMENTS",
    "interpolation_weights",
    "lut_texel_weights",
    "lut_lookup",
    "texel_centres",
]

#: How a table's rows sample perceptual roughness: at the end points of a range (the default build over 0–1, and a
#: scene's tables over what their materials use: a lookup at either end reads its own row) or at texel centres over
#: [0, 1] (the builds before 2026-12, kept to measure against: a lookup at r = 0 or 1 reads the row half a texel in);
#: ``sine-endpoints``, row j at √(1 − μo) = j/(H − 1), holds the view instead (the LTC layout, below).
ROW_PLACEMENTS = ("endpoints", "centres", "sine-endpoints")
#: How a table's columns sample μo: ``root-endpoints``, column i at √μo = i/(W − 1) (the default build: both ends
#: on a texel, and the columns crowd where the split sum steepens, at grazing views of smooth surfaces),
#: ``endpoints`` (μo = i/(W − 1)) or ``centres`` (μo = (i + 0.5)/W: the engines' usual table, and this project's
#: before 2026-12); ``roughness-endpoints``, column i at r = i/(W − 1), holds the roughness instead (the LTC layout).
COLUMN_PLACEMENTS = ("root-endpoints", "endpoints", "centres", "roughness-endpoints")
#: The axes of the public LTC tables (Heitz et al.'s ``ltc_code``, three.js ``LTC_Uv``): roughness along the columns,
#: √(1 − μo) along the rows, both at end points, so that an engine's area-light code reads the table unchanged.
LTC_LAYOUT = ("roughness-endpoints", "sine-endpoints")


@dataclasses.dataclass(frozen=True)
class LutGrid:
    """The texel grid of a table and the BRDF it integrates: the one place that knows the axes, α = r², the
    convention text of the header and the bilinear lookup, for every table (the split-sum tables and the LTC table).

    Columns (:data:`COLUMN_PLACEMENTS`): by default √μo = i/(W − 1), i = 0 … W − 1. Rows (:data:`ROW_PLACEMENTS`): by
    default r = low + j (high − low)/(H − 1) over ``roughness_range`` (0–1; one row stands at ``low``). A GPU reads
    end-point texels through the half-texel remap u = (x (W − 1) + 0.5)/W of the axis' coordinate x ∈ [0, 1]
    (x = √μo, x = (r − low)/(high − low)): every lookup in [0, 1]² interpolates between texels, none is clamped to
    an edge texel half a texel away. GGX α = r² (Burley 2012, Karis 2013; :func:`preintegrate.ggx.roughness_to_alpha`).
    The LTC table's grid (:data:`LTC_LAYOUT`, :func:`preintegrate.ltc.ltc_grid`) swaps the quantities: roughness
    along the columns, the view along the rows as √(1 − μo).

    Examples
    --------
    >>> grid = LutGrid(4, 3, roughness_range=(0.2, 0.6))
    >>> grid.roughness.tolist(), grid.alpha.round(2).tolist(), grid.mu_o.round(3).tolist()
    ([0.2, 0.4, 0.6], [0.04, 0.16, 0.36], [0.0, 0.111, 0.444, 1.0])
    >>> grid.texture_coordinates(1.0, 0.2).tolist()
    [0.875, 0.16666666666666666]
    >>> LutGrid(3, 3, rows="sine-endpoints", columns="roughness-endpoints").mu_o.tolist()
    [1.0, 0.75, 0.0]
    """

    width: int
    height: int
    rows: str = "endpoints"
    roughness_range: tuple[float, float] = (0.0, 1.0)
    visibility: str = "height-correlated"
    columns: str = "root-endpoints"

    def __post_init__(self):
        check_positive_int("width", self.width, low=2, high=8192)
        check_choice("rows", self.rows, ROW_PLACEMENTS)
        check_choice("columns", self.columns, COLUMN_PLACEMENTS)
        check_choice("visibility", self.visibility, list(VISIBILITIES))
        if (self.columns in LTC_LAYOUT or self.rows in LTC_LAYOUT) and (self.columns, self.rows) != LTC_LAYOUT:
            raise ParameterError(
                f"columns {self.columns!r} and rows {self.rows!r} do not make a grid: roughness columns go with "
                "sine-endpoints rows (the LTC layout), view columns with roughness rows"
            )
        low, high = (float(value) for value in check_range("roughness_range", self.roughness_range, 0.0, 1.0))
        if self.rows == "centres" or self.transposed:
            check_positive_int("height", self.height, low=2, high=8192)
            if (low, high) != (0.0, 1.0):
                raise ParameterError(f"these rows span roughness 0-1, got roughness_range {(low, high)}")
        else:
            check_positive_int("height", self.height, low=1, high=8192)
            if high < low or (self.height > 1 and high == low):
                raise ParameterError(
                    f"roughness_range must be (low, high) with low < high (low = high for one row), "
                    f"got {(low, high)} for {self.height} rows"
                )
        object.__setattr__(self, "roughness_range", (low, high))

    @classmethod
    def centred(cls, width: int, height: int | None = None, visibility: str = "height-correlated") -> "LutGrid":
        """The engines' grid: both axes at texel centres over 0–1 (μo = (i + 0.5)/W, r = (j + 0.5)/H), where their
        Monte-Carlo estimate is defined (μo > 0, α > 0) and where this project's tables stood before 2026-12."""
        return cls(width, width if height is None else height, rows="centres", visibility=visibility, columns="centres")

    @property
    def transposed(self) -> bool:
        """Whether the columns hold the roughness and the rows the view (the LTC layout)."""
        return self.columns == "roughness-endpoints"

    @property
    def mu_o(self) -> np.ndarray:
        """The view cosine of each column (of each row, on the LTC layout)."""
        if self.transposed:
            return 1.0 - np.linspace(0.0, 1.0, self.height) ** 2
        if self.columns == "centres":
            return texel_centres(self.width)
        steps = np.linspace(0.0, 1.0, self.width)
        return steps * steps if self.columns == "root-endpoints" else steps

    @property
    def roughness(self) -> np.ndarray:
        """The perceptual roughness of each row (of each column, on the LTC layout)."""
        if self.transposed:
            return np.linspace(0.0, 1.0, self.width)
        if self.rows == "centres":
            return texel_centres(self.height)
        low, high = self.roughness_range
        return np.linspace(low, high, self.height) if self.height > 1 else np.array([low])

    @property
    def alpha(self) -> np.ndarray:
        """The GGX width of each roughness."""
        return roughness_to_alpha(self.roughness)

    def view_position(self, mu_o, sine=None) -> np.ndarray:
        """Fractional texel index along the view axis of view cosines (clamped to [0, 1], as a GPU clamps NdotV); on the
        LTC layout √(1 − μo) may come from ``sine`` = |N × V| as sine / √(1 + μo), which float32 holds as μo → 1,
        where the axis is steepest (a float32 N·V moves the lookup by up to 0.016 texels there, the cross product
        does not)."""
        mu_o = np.clip(as_float_array("mu_o", mu_o), 0.0, 1.0)
        if self.transposed:
            if sine is None:
                root = np.sqrt(1.0 - mu_o)
            else:
                root = np.where(mu_o > 0.0, np.minimum(as_float_array("sine", sine) / np.sqrt(1.0 + mu_o), 1.0), 1.0)
            return root * (self.height - 1.0)
        if self.columns == "centres":
            return np.clip(mu_o * self.width - 0.5, 0.0, self.width - 1.0)
        return (np.sqrt(mu_o) if self.columns == "root-endpoints" else mu_o) * (self.width - 1.0)

    def roughness_position(self, roughness) -> np.ndarray:
        """Fractional texel index along the roughness axis of perceptual roughnesses (clamped to the axis' range)."""
        roughness = np.clip(as_float_array("roughness", roughness), 0.0, 1.0)
        if self.transposed:
            return roughness * (self.width - 1.0)
        if self.rows == "centres":
            return np.clip(roughness * self.height - 0.5, 0.0, self.height - 1.0)
        low, high = self.roughness_range
        if self.height == 1:
            return np.zeros(roughness.shape)
        return np.clip((roughness - low) / (high - low), 0.0, 1.0) * (self.height - 1.0)

    def _positions(self, mu_o, roughness, sine=None) -> tuple[np.ndarray, np.ndarray]:
        """(column, row) fractional positions of (μo, r)."""
        view, rough = self.view_position(mu_o, sine), self.roughness_position(roughness)
        return (rough, view) if self.transposed else (view, rough)

    def texture_coordinates(self, mu_o, roughness, sine=None) -> np.ndarray:
        """(…, 2) the (u, v) at which a GPU samples this grid's table for (μo, r) (and ``sine``, see
        :meth:`view_position`), both clamped as a GPU clamps them: the affine maps :attr:`column_mapping` and
        :attr:`row_mapping` that the include's ``fresnelBasisLutUV`` writes as constants (end points:
        (position + 0.5)/size), on the LTC layout ``fresnelLtcUV``'s."""
        mu_o, roughness = np.broadcast_arrays(as_float_array("mu_o", mu_o), as_float_array("roughness", roughness))
        if self.transposed:
            column, row = self._positions(mu_o, roughness, sine)
            return np.stack(np.broadcast_arrays((column + 0.5) / self.width, (row + 0.5) / self.height), -1)
        mu_o = np.clip(mu_o, 0.0, 1.0)
        column_scale, column_offset = self.column_mapping
        low, high, row_scale, row_offset = self.row_mapping  # [low, high] lies in [0, 1]
        x = np.sqrt(mu_o) if self.columns == "root-endpoints" else mu_o
        return np.stack([x * column_scale + column_offset, np.clip(roughness, low, high) * row_scale + row_offset], -1)

    @property
    def holds_mirror(self) -> bool:
        """Whether a lookup at r = 0 reads the mirror's own texels, where the split sum is the curve itself
        (b̄_k(μo, 0) = b_k(μo), :mod:`preintegrate.quadrature`): end-point rows from r = 0, as the default build's (a
        scene's cropped rows may start above it; texel-centre rows hold r = 0 half a texel off)."""
        return not self.transposed and self.rows == "endpoints" and self.roughness_range[0] == 0.0

    @property
    def row_mapping(self) -> tuple[float, float, float, float]:
        """(r_low, r_high, scale, offset) of the affine v = clamp(r, r_low, r_high) · scale + offset that the generated
        include's ``fresnelBasisLutUV`` writes as constants (texel centres: v = r; end-point rows:
        v = ((r − low)/(high − low) (H − 1) + 0.5)/H, read exactly at both ends)."""
        if self.transposed:
            raise ParameterError("the LTC layout's rows hold the view: fresnelLtcUV addresses them")
        if self.rows == "centres":
            return 0.0, 1.0, 1.0, 0.0
        low, high = self.roughness_range
        if self.height == 1:
            return low, low, 0.0, 0.5
        scale = (self.height - 1) / ((high - low) * self.height)
        return low, high, scale, 0.5 / self.height - low * scale

    @property
    def column_mapping(self) -> tuple[float, float]:
        """(scale, offset) of the include's affine u = x · scale + offset of x = √NdotV (root end-point columns, the
        default), x = NdotV otherwise (end points: scale (W − 1)/W, offset 0.5/W, read exactly at both ends; centres:
        u = x)."""
        if self.columns == "centres":
            return 1.0, 0.0
        return (self.width - 1) / self.width, 0.5 / self.width

    def view_weights(self, mu_o) -> np.ndarray:
        """(P, W) weights of the linear interpolation a GPU makes along the view axis at the view cosines ``mu_o``."""
        size = self.height if self.transposed else self.width
        return _position_weights(self.view_position(np.ravel(mu_o)), size)

    def roughness_weights(self, roughness) -> np.ndarray:
        """(P, H) weights of the linear interpolation a GPU makes along the roughness axis at ``roughness``."""
        size = self.width if self.transposed else self.height
        return _position_weights(self.roughness_position(np.ravel(roughness)), size)

    @property
    def convention(self) -> str:
        """The header's ``convention`` text: axes, α, order in the file, what a texel holds, the BRDF's G2."""
        if self.transposed:
            return (
                "column i <-> perceptual roughness r = i / (size - 1), GGX alpha = max(r^2, 1e-4); row j <-> "
                "sqrt(1 - mu_o) = j / (size - 1) (mu_o at least 1e-3); row 0 first in the file (top); end points on texel "
                "centres: u = r * (size - 1) / size + 0.5 / size, v = sqrt(1 - mu_o) * (size - 1) / size + 0.5 / size "
                "(the axes of the public LTC tables, three.js LTC_Uv); values are (m00, m20, m02, m22) of M^-1 / "
                "M^-1[1][1], M^-1 = [[m00, 0, m02], [0, 1, 0], [m20, 0, m22]] (GLSL mat3(vec3(m00, 0, m20), vec3(0, 1, 0), "
                "vec3(m02, 0, m22))), in the frame T1 = tangential part of the view, T2 = N x T1, N, of the linearly "
                "transformed cosine fitted to rho_GGX(omega_o, omega_i) cos(theta_i) / E (Heitz 2016), GGX with "
                + VISIBILITIES[self.visibility].header
            )
        columns = {
            "centres": "column i <-> mu_o = cos(theta_o) = (i + 0.5) / width (texel centres; engine: u = mu_o)",
            "endpoints": "column i <-> mu_o = cos(theta_o) = i / (width - 1) (engine: u = (mu_o * (width - 1) + "
            "0.5) / width)",
            "root-endpoints": "column i <-> sqrt(mu_o) = i / (width - 1), mu_o = cos(theta_o) (engine: u = "
            "(sqrt(mu_o) * (width - 1) + 0.5) / width)",
        }[self.columns]
        if self.rows == "centres":
            rows = "row j <-> perceptual roughness r = (j + 0.5) / height (texel centres; engine: v = r)"
        elif self.height > 1:
            low, high = (f"{value:.6g}" for value in self.roughness_range)
            rows = (
                f"row j <-> perceptual roughness r = {low} + j * ({high} - {low}) / (height - 1) (rows at the range's "
                f"end points; engine: v = ((r - {low}) / ({high} - {low}) * (height - 1) + 0.5) / height)"
            )
        else:
            rows = f"one row, at perceptual roughness r = {self.roughness_range[0]:.6g} (engine: v = 0.5)"
        return (
            f"{columns}; {rows}, GGX alpha = r^2; row 0 first in the file (top); values are directional albedos "
            "Fbar_k(mu_o, alpha) = integral of f_k(omega_o . h) * rho_GGX(omega_o, omega_i) * cos(theta_i) d omega_i, "
            f"GGX with {VISIBILITIES[self.visibility].header}"
        )

    def lookup(self, table: np.ndarray, mu_o, roughness, sine=None) -> np.ndarray:
        """Bilinear, clamp-to-edge fetch of a table on this grid at (μo, r) (and ``sine``, see :meth:`view_position`),
        as a GPU samples it at level 0."""
        table = _checked_lookup_table(table, rows_at_least=1)
        if table.shape[:2] != (self.height, self.width):
            raise ParameterError(
                f"table must have this grid's {self.height} x {self.width} texels, got {table.shape[:2]}"
            )
        mu_o, roughness = as_float_array("mu_o", mu_o), as_float_array("roughness", roughness)
        check_broadcast(mu_o=mu_o, roughness=roughness)
        mu_o, roughness = np.broadcast_arrays(mu_o, roughness)
        return _bilinear(table, *self._positions(mu_o, roughness, sine))


#: The default build's convention (root end-point columns, end-point rows over 0–1, height-correlated G2), as every
#: shipped header states it.
PIXEL_CONVENTION = LutGrid(2, 2).convention


def texel_centres(count: int) -> np.ndarray:
    """(i + 0.5) / count, i = 0 … count − 1: the texel centres of one axis (unchecked)."""
    return (np.arange(count) + 0.5) / count


def lut_texel_weights(theta_grid, grid: LutGrid | int, order=DEFAULT_ORDER) -> np.ndarray:
    """(H W, M): the texel weights (:func:`preintegrate.quadrature.texel_weights`) of every texel of a table on
    ``grid`` (or the default size × size grid), row-major (roughness rows, μo columns): F̄ of curves sampled on
    ``theta_grid`` over the whole table is one matrix product."""
    grid = grid if isinstance(grid, LutGrid) else LutGrid(grid, grid)
    weights = texel_weights(theta_grid, grid.mu_o[None, :], grid.alpha[:, None], order, grid.visibility)
    return weights.reshape(grid.height * grid.width, -1)


def _quadrature(functions, mu_o, alpha, progress, visibility, order=DEFAULT_ORDER):
    return directional_albedo(functions, mu_o, alpha, order=order, progress=progress, visibility=visibility)


def _hammersley(functions, mu_o, alpha, progress, visibility, samples=1024, sampling="ndf", max_samples=131_072):
    return hammersley_albedo(functions, mu_o, alpha, samples, sampling, max_samples, progress, visibility)


_TEXELS = ("functions", "mu_o", "alpha", "progress", "visibility")

#: Registry: how a table's texels are computed. ``quadrature`` (options: ``order``) is this project's
#: deterministic integral; ``hammersley`` (options: ``samples``, ``sampling``, ``max_samples``) is the
#: engines' Monte-Carlo estimate (Karis 2013), kept to measure them against it.
LUT_METHODS: dict[str, Callable] = {"quadrature": _quadrature, "hammersley": _hammersley}


def build_table(
    channels: ChannelSet,
    grid: LutGrid | int,
    height: int | None = None,
    method: str = "quadrature",
    progress: Callable[[int, int], None] | None = None,
    **options,
) -> np.ndarray:
    """(H, W, K) float64 table of the channel set on a :class:`LutGrid` (or the default grid of ``grid`` columns,
    ``height`` rows and the ``visibility`` option), by a method of :data:`LUT_METHODS`.

    Examples
    --------
    >>> from preintegrate.channels import schlick_channels
    >>> build_table(schlick_channels(), 4).shape
    (4, 4, 2)
    >>> engines = LutGrid.centred(4)  # the engines' estimate needs μo, α > 0
    >>> build_table(schlick_channels(), engines, method="hammersley", samples=64).shape
    (4, 4, 2)
    """
    if not isinstance(channels, ChannelSet):
        raise ParameterError(f"channels must be a ChannelSet, got {type(channels).__name__}")
    compute = LUT_METHODS[check_choice("method", method, sorted(LUT_METHODS))]
    if not isinstance(grid, LutGrid):
        visibility = options.pop("visibility", "height-correlated")
        grid = LutGrid(grid, grid if height is None else height, visibility=visibility)
    elif height is not None or "visibility" in options:
        raise ParameterError("a LutGrid carries its own height and visibility; pass neither beside it")
    if method == "hammersley" and (grid.mu_o[0] == 0.0 or grid.alpha[0] == 0.0):
        raise ParameterError(
            "the engines' Monte-Carlo estimate (method 'hammersley') divides by mu_o and needs alpha > 0, and this "
            "grid has texels at mu_o = 0 or r = 0: give it the engines' grid at texel centres, LutGrid.centred(width, height)"
        )
    accepted = [name for name in inspect.signature(compute).parameters if name not in _TEXELS]
    unknown = sorted(set(options) - set(accepted))
    if unknown:
        raise ParameterError(f"method {method!r} takes the options {accepted + ['visibility']}, got {unknown}")
    return compute(channels.functions, grid.mu_o[None, :], grid.alpha[:, None], progress, grid.visibility, **options)


def interpolation_weights(points, centres) -> np.ndarray:
    """(P, N) weights of linear, clamp-to-edge interpolation from samples at ``centres`` (increasing)."""
    points, centres = np.ravel(points), np.asarray(centres, dtype=np.float64)
    position = np.clip(np.interp(points, centres, np.arange(centres.size)), 0.0, centres.size - 1.0)
    return _position_weights(position, centres.size)


def lut_lookup(table: np.ndarray, mu_o, roughness) -> np.ndarray:
    """Bilinear, clamp-to-edge fetch at (μo, r) of a table (H, W, K) on the default build's grid of its size
    (:class:`LutGrid` ``(W, H)``), as a GPU samples it at level 0 through the include's coordinates
    (:meth:`LutGrid.lookup` for any other grid). μo and r are clamped to [0, 1] as a GPU clamps."""
    table = _checked_lookup_table(table, rows_at_least=2)
    height, width = table.shape[:2]
    return LutGrid(width, height).lookup(table, mu_o, roughness)


def _checked_lookup_table(table, rows_at_least: int) -> np.ndarray:
    table = as_float_array("table", table)
    if table.ndim != 3 or table.shape[0] < rows_at_least or table.shape[1] < 2 or table.shape[2] < 1:
        raise ParameterError(f"table must have shape (H >= {rows_at_least}, W >= 2, K >= 1), got {table.shape}")
    return table


def _bilinear(table: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Linear interpolation of ``table`` (H, W, K) at fractional texel positions x ∈ [0, W − 1], y ∈ [0, H − 1]."""
    x0, fx = _split_position(x, table.shape[1])
    y0, fy = _split_position(y, table.shape[0])
    x1, y1 = np.minimum(x0 + 1, table.shape[1] - 1), np.minimum(y0 + 1, table.shape[0] - 1)
    fx, fy = fx[..., None], fy[..., None]
    return (1 - fy) * ((1 - fx) * table[y0, x0] + fx * table[y0, x1]) + fy * (
        (1 - fx) * table[y1, x0] + fx * table[y1, x1]
    )


def _split_position(position: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(lower index, fraction) of fractional texel positions in [0, count − 1]."""
    low = np.clip(np.floor(position).astype(int), 0, max(count - 2, 0))
    return low, position - low


def _position_weights(position: np.ndarray, count: int) -> np.ndarray:
    """(P, count) linear-interpolation weights of fractional texel positions in [0, count − 1]."""
    weights = np.zeros((position.size, count))
    if count == 1:
        weights[:, 0] = 1.0
        return weights
    low, fraction = _split_position(position, count)
    rows = np.arange(position.size)
    weights[rows, low] = 1.0 - fraction
    weights[rows, low + 1] += fraction
    return weights
