"""EXR I/O of LUT tables: atomic writes, self-describing headers, verified reads.

Public objects: ``write_lut``, ``write_luts``, ``exr_writer``, ``read_lut``, ``content_hash``, ``stored_values``,
``table_attributes``, ``LutFileError``.

Files are written with OpenEXR 3.x (``OpenEXR.File``), ZIP-compressed scanlines, float32 by default
or half; in half, magnitudes below 2^-14 are written as 0 rather than as subnormals. Every file is first written to a temporary name in the destination folder and renamed into
place only when complete, so a crash or Ctrl-C never leaves a half-written LUT and an existing file is
only ever replaced by a complete one. :func:`write_luts` renames a whole set only after every file of
it is written, and rolls the set back if the renames are interrupted (:mod:`basis.storage`); reading
never renames, removes or writes anything. Header attributes carry no time stamp, so the same build gives bit-identical files.
"""

from __future__ import annotations

import hashlib
import os
from collections.abc import Callable, Mapping
from pathlib import Path

import numpy as np
import OpenEXR

from basis.storage import (
    JOURNAL,
    MAX_TABLE_BYTES,
    check_regular_file,
    reading_folder,
    unfinished_group,
    write_together,
)
from basis.validation import ParameterError, as_float_array, safe_line

__all__ = [
    "LutFileError",
    "content_hash",
    "exr_writer",
    "read_lut",
    "stored_values",
    "table_attributes",
    "write_lut",
    "write_luts",
]

#: Largest magnitude a texel of this project's tables may have (albedos of curves of order 1, LTC matrices divided by
#: their middle entry: within ±2 in the shipped tables); a larger value is refused on reading as damage or an edit.
MAX_TEXEL_MAGNITUDE = 1e3
#: Prefix of this project's header attributes.
ATTRIBUTE_PREFIX = "fresnel:"
HALF_MAX = float(np.finfo(np.float16).max)
FLOAT32_MAX = float(np.finfo(np.float32).max)
#: Smallest normal half float, 2^-14 ≈ 6.1e-5. Smaller magnitudes would be stored as subnormals (slow on
#: some GPUs, flushed to zero by others); they are written as 0, a change below half's step near 1.
HALF_MIN_NORMAL = float(np.finfo(np.float16).tiny)


class LutFileError(ParameterError):
    """An EXR LUT is missing, unreadable, truncated or lacks this project's header."""


def _prepare(table: np.ndarray, channel_names, half: bool) -> dict[str, np.ndarray]:
    table = as_float_array("table", table, finite=False)
    if table.ndim != 3 or table.shape[2] != len(channel_names):
        raise ParameterError(f"table must have shape (H, W, {len(channel_names)}), got {table.shape}")
    table = stored_values(table, half)
    return {name: np.ascontiguousarray(table[:, :, k]) for k, name in enumerate(channel_names)}


def stored_values(table: np.ndarray, half: bool) -> np.ndarray:
    """The table as a LUT file stores it, float32 or half (subnormal halves written as 0), refusing NaN,
    inf and values beyond the type's range: the one rule of every float format (EXR, KTX2)."""
    table = as_float_array("table", table, finite=False)
    if not np.all(np.isfinite(table)):
        raise ParameterError("table contains NaN or inf; refusing to write it")
    if half and np.max(np.abs(table)) > HALF_MAX:
        raise ParameterError(f"table exceeds the half-float range ({HALF_MAX}); write float32 instead")
    if np.max(np.abs(table), initial=0.0) > FLOAT32_MAX:
        raise ParameterError(f"table exceeds the float32 range ({FLOAT32_MAX:.4g}); refusing to write inf")
    if half:
        table = np.where(np.abs(table) < HALF_MIN_NORMAL, 0.0, table)
    return table.astype(np.float16 if half else np.float32)


def content_hash(attributes: Mapping[str, str], channels: Mapping[str, np.ndarray]) -> str:
    """SHA-256 (first 16 hex digits) of this project's attributes and the stored pixels.

    EXR has no checksum of its own (a flipped bit in a header or an uncompressed block goes unseen);
    this hash, stored as ``fresnel:content_hash``, lets :func:`read_lut` refuse such a file.
    """
    digest = hashlib.sha256()
    for key in sorted(attributes):
        if key != "content_hash":
            digest.update(f"{key}={attributes[key]}\n".encode("utf-8"))
    for name in sorted(channels):
        pixels = np.asarray(channels[name])
        digest.update(f"{name}:{pixels.dtype.str}:{pixels.shape}\n".encode("utf-8"))
        digest.update(np.ascontiguousarray(pixels).tobytes())
    return digest.hexdigest()[:16]


def write_luts(items, half: bool = False, texts=(), extra_writers=(), owned: str | None = None) -> list[Path]:
    """Write several LUTs as one transaction: all temporaries first, then all renames.

    ``items`` is a sequence of (path, table (H, W, K), channel names, attributes mapping str → str);
    ``texts`` a sequence of (path, UTF-8 text) files that belong to the same transaction (a scene's
    coefficients and report); ``extra_writers`` (path, writer(temporary)) pairs of other files (the same
    tables in other formats); ``owned`` the names of the set the transaction owns (files it matches and does
    not write are removed: :func:`basis.storage.write_together`).
    """
    writers = [
        (Path(path), exr_writer(table, channel_names, attributes, half))
        for path, table, channel_names, attributes in items
    ]
    writers += [
        (Path(path), lambda temporary, text=text: temporary.write_text(text, encoding="utf-8")) for path, text in texts
    ]
    write_together(writers + [(Path(path), writer) for path, writer in extra_writers], owned=owned)
    return [path for path, _ in writers[: len(items)]]


def table_attributes(attributes) -> dict[str, str]:
    """A table's header attributes as every format writes them: names of letters, digits and ``_``, each value one
    inert line (:func:`basis.validation.safe_line`: a file name or command can carry no line, comment end or
    non-ASCII character into a header, a PNG text chunk or a C comment)."""
    if not isinstance(attributes, Mapping):
        raise ParameterError(f"attributes must be a mapping of names to texts, got {type(attributes).__name__}")
    for key in attributes:
        if not isinstance(key, str) or not key.isascii() or not key.replace("_", "a").isalnum():
            raise ParameterError(f"an attribute name is letters, digits and '_', got {str(key)[:60]!r}")
    return {key: safe_line(value) for key, value in attributes.items()}


def exr_writer(table, channel_names, attributes: Mapping[str, str], half: bool = False) -> Callable[[Path], None]:
    """``writer(path)`` that writes one LUT (H, W, K) as EXR, its header sealed by :func:`content_hash`; the
    table is checked and converted when the writer is made, so a bad table fails before any file is begun."""
    channels = _prepare(table, tuple(channel_names), half)
    attributes = {**table_attributes(attributes), "pixel_type": "half" if half else "float32"}
    attributes["content_hash"] = content_hash(attributes, channels)
    header = {
        "compression": OpenEXR.ZIP_COMPRESSION,
        "type": OpenEXR.scanlineimage,
        **{f"{ATTRIBUTE_PREFIX}{key}": value for key, value in attributes.items()},
    }
    return lambda path: OpenEXR.File(header, channels).write(str(path))


def write_lut(path, table, channel_names, attributes: Mapping[str, str], half: bool = False) -> Path:
    """Write one LUT (H, W, K) atomically; see :func:`write_luts`."""
    return write_luts([(path, table, tuple(channel_names), attributes)], half=half)[0]


#: ``fresnel:pixel_type`` → the NumPy type of the stored pixels.
PIXEL_TYPES = {"float32": np.float32, "half": np.float16}


def _check_layout(path: Path, attributes: dict[str, str], pixels: list[np.ndarray]) -> None:
    """The header's ``width``, ``height`` and ``pixel_type`` (where present) describe the stored pixels."""
    shapes = {array.shape for array in pixels}
    if len(shapes) != 1 or len(next(iter(shapes))) != 2:
        raise LutFileError(f"{path}: channels of shapes {sorted(shapes)}; a LUT's channels are one (H, W) grid")
    height, width = next(iter(shapes))
    for key, found in (("width", width), ("height", height)):
        if key in attributes and attributes[key] != str(found):
            raise LutFileError(f"{path}: header {key} {attributes[key]!r} does not match the pixels ({found})")
    if "pixel_type" in attributes:
        expected = PIXEL_TYPES.get(attributes["pixel_type"])
        if expected is None or any(array.dtype != expected for array in pixels):
            raise LutFileError(
                f"{path}: header pixel_type {attributes['pixel_type']!r} does not match the pixels "
                f"({sorted({array.dtype.name for array in pixels})})"
            )


def read_lut(path, channel_names=None) -> tuple[np.ndarray, dict[str, str]]:
    """Read a LUT written by :func:`write_lut`: (table (H, W, K) float64, this project's attributes).

    ``channel_names`` defaults to the order stored in the header (``fresnel:channels``).
    """
    if not isinstance(path, (str, os.PathLike)) or str(path) == "":
        raise LutFileError(f"path must name an EXR file (text or a path), got {type(path).__name__} {str(path)[:60]!r}")
    path = Path(path)
    with reading_folder(path.parent):  # a build renaming its set into this folder finishes first
        if unfinished_group(path) is not None:  # a reader never renames or removes: it refuses a mixed set
            raise LutFileError(
                f"{path} belongs to a group of files that a killed write left half-renamed in "
                f"{path.parent} ({JOURNAL}); the set may mix two builds: rerun the build into that "
                "folder (its first step finishes the group)"
            )
        check_regular_file(path, "LUT file", MAX_TABLE_BYTES, LutFileError)  # a FIFO or a device would hang OpenEXR
        try:
            image = OpenEXR.File(str(path), separate_channels=True)  # else R,G,B,A come back merged as "RGBA"
            header = image.header()
            channels = image.channels()
        except Exception as error:  # the bindings raise bare RuntimeError/OSError on bad files
            raise LutFileError(f"cannot read EXR {path} (truncated or not an EXR?): {error}") from None
    attributes = {
        key[len(ATTRIBUTE_PREFIX) :]: str(value) for key, value in header.items() if key.startswith(ATTRIBUTE_PREFIX)
    }
    if "channels" not in attributes:
        raise LutFileError(f"{path} is not a fresnel-basis LUT (no {ATTRIBUTE_PREFIX}channels attribute)")
    stored = {name: channel.pixels for name, channel in channels.items()}
    if attributes.get("content_hash") != content_hash(attributes, stored):
        raise LutFileError(
            f"{path}: content hash {attributes.get('content_hash')!r} does not match its header and pixels "
            f"({content_hash(attributes, stored)}): the file is corrupt or was edited"
        )
    names = attributes["channels"].split(",") if channel_names is None else list(channel_names)
    missing = [name for name in names if name not in channels]
    if missing:
        raise LutFileError(f"{path} lacks channels {missing}; it has {sorted(channels)}")
    _check_layout(path, attributes, [np.asarray(channels[name].pixels) for name in names])
    table = np.stack([np.asarray(channels[name].pixels, dtype=np.float64) for name in names], axis=-1)
    if not np.all(np.isfinite(table)):
        raise LutFileError(f"{path} contains NaN or inf texels")
    if np.max(np.abs(table), initial=0.0) > MAX_TEXEL_MAGNITUDE:
        raise LutFileError(
            f"{path} holds a texel of {np.max(np.abs(table)):.3g}: a table of this project holds albedos and normalised "
            f"LTC matrices, within {MAX_TEXEL_MAGNITUDE:g} in magnitude"
        )
    return table, attributes
