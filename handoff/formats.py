"""LUT files for engines that do not read EXR: KTX2, 16-bit PNG and a C/C++ header. (EXR is :mod:`handoff.exr`.)

Public objects: ``FORMATS``, ``MAX_HEADER_VALUES``, ``Format``, ``check_formats``, ``file_family``, ``payload_hash``, ``ktx2_bytes``, ``png16_encoding``, ``png16_bytes``, ``c_identifier``, ``c_header``.

* **KTX2** (``ktx2``): one level, no supercompression, ``VK_FORMAT_R32G32B32A32_SFLOAT`` (or
  ``R16G16B16A16_SFLOAT`` with ``--half``), rows in file order; a table of fewer channels is padded with
  zeros and A = 1 (no GPU API samples three-channel float textures everywhere; WebGPU has none): the
  Schlick table is (scale, bias, E, 1), the one-column E_avg table (Y, 0, 0, 1). The data format
  descriptor is the one libktx derives from that format (RGBSDA, BT.709 primaries, linear transfer,
  signed float samples with bounds −1.0f and 1.0f); the attributes are key/value pairs (``fresnel:…``)
  beside ``KTXorientation`` = ``rd`` and ``KTXwriter``. ``ktx validate`` notes each ``fresnel:`` key with
  warning 7010 (a key outside the KTX namespace, allowed by the specification, §3.10): expected, not a defect.
* **16-bit PNG** (``png16``): each channel is stored as round((value − offset) / scale · 65535), with
  offset and scale per channel chosen from the table's own range, so a signed channel (the basis table's
  A, b̄3 from −0.64 to 1) survives where a unorm texture would clip it. The engine recovers
  value = offset + scale · texel (texel in [0, 1] as a unorm read returns it); the file states offset and
  scale in a ``tEXt`` chunk (``fresnel:encoding``), beside the convention and the content description.
  Precision: scale / 65535 / 2, 1.5e-5 for the basis table. The image is **greyscale**, the K channels stacked
  top to bottom (channel c in rows c·H … (c + 1)·H − 1 of a W × K·H image): no alpha for a reader to premultiply by
  (OpenImageIO's default does), and a 16-bit grey image is what Pillow and imageio decode at 16 bits (they reduce
  16-bit RGB and RGBA to 8).
* **C/C++ header** (``header``): ``static const float`` arrays in file order (row 0 first, channels
  interleaved), the size, the channel names and the convention in a comment: a table compiled into the
  binary, exact in float32.

Every file states ``fresnel:pixel_type`` (``float32``, ``half`` or ``uint16``) and ``fresnel:content_hash``, the
:func:`payload_hash` of its attributes (the PNG's ``encoding`` among them) and its texel bytes as stored (KTX2: the level data; PNG: the 16-bit big-endian
samples before filtering, row 0 first; header: the float32 values, little-endian): a reader recomputes it to refuse a
damaged file. A table is always written through :func:`basis.storage.write_together` (atomic, one transaction).

References
----------
:cite:`KTX2` Khronos, "KTX File Format Specification, version 2.0": Sections 3 (header, index, level
    index), 3.10 (key/value data, sorted keys, 4-byte padding), 3.9 (level alignment lcm(texel size, 4)).
:cite:`KDFS` Khronos, "Data Format Specification 1.3", Section 5 (basic descriptor block, sample words).
:cite:`PNG2003` W3C, "Portable Network Graphics (PNG) Specification (Second Edition)", 2003: chunks
    IHDR (bit depth 16, colour type 0), IDAT (zlib), tEXt, IEND; CRC-32 over type and data.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import re
import struct
import zlib
from collections.abc import Callable
from pathlib import Path

import numpy as np

from basis.validation import ParameterError, as_float_array

from .exr import exr_writer, stored_values, table_attributes

__all__ = [
    "FORMATS",
    "MAX_HEADER_VALUES",
    "Format",
    "c_header",
    "c_identifier",
    "check_formats",
    "file_family",
    "payload_hash",
    "ktx2_bytes",
    "png16_bytes",
    "png16_encoding",
]


@dataclasses.dataclass(frozen=True)
class Format:
    """A file format of a table: its suffix and ``writer(table, channel_names, attributes, name, half)``, which
    checks the table at once and returns what writes the file to a path (:func:`basis.storage.write_together`)."""

    name: str
    suffix: str
    writer: Callable[[np.ndarray, tuple[str, ...], dict[str, str], str, bool], Callable[[Path], None]]
    description: str


def _bytes_writer(data: bytes) -> Callable[[Path], None]:
    return lambda path: path.write_bytes(data)


def _half_rounded(table, half: bool) -> np.ndarray:
    """The table as a ``--half`` build stores it (:func:`handoff.exr.stored_values`), so that every format of
    one build holds the same values."""
    return stored_values(table, True).astype(np.float64) if half else table


#: Registry: the formats of ``fresnel-lut build --format`` and ``fresnel-lut scene --format``.
FORMATS = {
    fmt.name: fmt
    for fmt in (
        Format(
            "exr",
            ".exr",
            lambda table, names, attributes, name, half: exr_writer(table, names, attributes, half),
            "OpenEXR, ZIP scanlines, float32 (half with --half)",
        ),
        Format(
            "ktx2",
            ".ktx2",
            lambda table, names, attributes, name, half: _bytes_writer(ktx2_bytes(table, attributes, half)),
            "KTX2, RGBA32F (RGBA16F with --half)",
        ),
        Format(
            "png16",
            ".png",
            lambda table, names, attributes, name, half: _bytes_writer(
                png16_bytes(_half_rounded(table, half), attributes)
            ),
            "16-bit PNG, offset and scale per channel in the file",
        ),
        Format(
            "header",
            ".h",
            lambda table, names, attributes, name, half: _bytes_writer(
                c_header(_half_rounded(table, half), name, names, attributes).encode("utf-8")
            ),
            "C/C++ header of float arrays",
        ),
    )
}


#: Most values a C header holds: each is written as text (about 16 bytes), so 2^22 floats make a 64 MiB source file,
#: what a compiler still swallows; a larger table belongs in a binary format (KTX2, EXR).
MAX_HEADER_VALUES = 1 << 22


def check_formats(formats) -> list[str]:
    """The formats asked for (``"exr,ktx2"`` or a sequence of names), each of :data:`FORMATS`, at least one, in order."""
    names = [name.strip() for name in str(formats).split(",")] if isinstance(formats, str) else list(formats)
    names = [name for name in names if name != ""]
    if not names or any(not isinstance(name, str) or name not in FORMATS for name in names):
        raise ParameterError(f"formats must list formats of {list(FORMATS)} separated by commas, got {formats!r}")
    return list(dict.fromkeys(names))


def file_family(stems) -> str:
    """A regular expression of the files the tables ``stems`` are, in every format of :data:`FORMATS`: the set
    a build owns in its folder (:func:`basis.storage.write_together`'s ``owned``)."""
    return (
        f"(?:{'|'.join(re.escape(stem) for stem in sorted(set(stems)))})"
        f"(?:{'|'.join(re.escape(fmt.suffix) for fmt in FORMATS.values())})"
    )


KTX2_IDENTIFIER = b"\xabKTX 20\xbb\r\n\x1a\n"
#: VkFormat of an RGBA float table by bytes per channel.
KTX2_FORMATS = {4: 109, 2: 97}  # VK_FORMAT_R32G32B32A32_SFLOAT, VK_FORMAT_R16G16B16A16_SFLOAT
_FLOAT_SIGNED = 0x80 | 0x40  # KHR_DF_SAMPLE_DATATYPE_FLOAT | KHR_DF_SAMPLE_DATATYPE_SIGNED
_ALPHA = 15  # KHR_DF_CHANNEL_RGBSDA_ALPHA


def _checked_table(what: str, table, attributes) -> tuple[np.ndarray, dict[str, str]]:
    """A non-empty (H, W, 1…4) float table and text attributes, or an error naming the format."""
    table = as_float_array("table", table, finite=False)
    if table.ndim != 3 or table.shape[0] < 1 or table.shape[1] < 1 or not 1 <= table.shape[2] <= 4:
        raise ParameterError(f"{what} holds a non-empty table of 1 to 4 channels, got shape {table.shape}")
    return table, table_attributes(attributes)


def payload_hash(attributes: dict[str, str], payload: bytes) -> str:
    """SHA-256 (first 16 hex digits) of a file's ``fresnel:`` attributes (``key=value`` lines in sorted key order,
    ``content_hash`` left out) and then its texel bytes as stored: the ``fresnel:content_hash`` of a KTX2, PNG or
    C header, which a reader recomputes to refuse a file that was damaged or edited."""
    digest = hashlib.sha256()
    for key in sorted(attributes):
        if key != "content_hash":
            digest.update(f"{key}={attributes[key]}\n".encode("utf-8"))
    digest.update(payload)
    return digest.hexdigest()[:16]


def _sealed(attributes: dict[str, str], pixel_type: str, payload: bytes) -> dict[str, str]:
    """``attributes`` with the stored ``pixel_type`` and the :func:`payload_hash` of ``payload``."""
    attributes = {**attributes, "pixel_type": pixel_type}
    return {**attributes, "content_hash": payload_hash(attributes, payload)}


def _ktx2_descriptor(bytes_per_channel: int) -> bytes:
    """The data format descriptor of RGBA signed float: total size, then one basic block (KDFS §5)."""
    samples = b"".join(
        struct.pack(
            "<HBB4xff",
            8 * bytes_per_channel * channel,
            8 * bytes_per_channel - 1,
            (_ALPHA if channel == 3 else channel) | _FLOAT_SIGNED,
            -1.0,
            1.0,
        )
        for channel in range(4)
    )
    block = (
        struct.pack(
            "<IHHBBBB4B8B", 0, 2, 24 + len(samples), 1, 1, 1, 0, 0, 0, 0, 0, 4 * bytes_per_channel, 0, 0, 0, 0, 0, 0, 0
        )
        + samples
    )
    return struct.pack("<I", 4 + len(block)) + block


def _ktx2_key_values(attributes: dict[str, str], writer: str) -> bytes:
    pairs = {
        "KTXorientation": "rd",
        "KTXwriter": writer,
        **{f"fresnel:{key}": value for key, value in attributes.items()},
    }
    data = b""
    for key in sorted(pairs, key=lambda name: name.encode("utf-8")):
        entry = key.encode("utf-8") + b"\x00" + pairs[key].encode("utf-8") + b"\x00"
        data += struct.pack("<I", len(entry)) + entry + b"\x00" * (-len(entry) % 4)
    return data


def ktx2_bytes(table: np.ndarray, attributes: dict[str, str], half: bool = False) -> bytes:
    """A KTX2 file of a table (H, W, K ≤ 4) as RGBA float (module docstring), rows in file order."""
    table, attributes = _checked_table("a KTX2 LUT", table, attributes)
    height, width, channels = table.shape
    size = 2 if half else 4
    rgba = np.concatenate(
        [table, np.zeros((height, width, max(0, 3 - channels))), np.ones((height, width, 4 - max(channels, 3)))], axis=2
    )
    texels = stored_values(rgba, half).astype("<f2" if half else "<f4").tobytes()
    attributes = _sealed(attributes, "half" if half else "float32", texels)
    descriptor = _ktx2_descriptor(size)
    key_values = _ktx2_key_values(attributes, attributes.get("generator", "fresnel-basis"))
    header_size = 80 + 24  # header and index, one level
    key_values_offset = header_size + len(descriptor)
    end = key_values_offset + len(key_values)
    level_offset = end + (-end % (4 * size))  # lcm(texel size, 4)
    header = KTX2_IDENTIFIER + struct.pack("<9I", KTX2_FORMATS[size], size, width, height, 0, 0, 1, 1, 0)
    index = struct.pack("<4I2Q", header_size, len(descriptor), key_values_offset, len(key_values), 0, 0)
    levels = struct.pack("<3Q", level_offset, len(texels), len(texels))
    return header + index + levels + descriptor + key_values + b"\x00" * (level_offset - end) + texels


#: How far past [0, 1] a channel may go and still be stored as it is (offset 0, scale 1): half a 16-bit step.
PNG16_SLACK = 0.5 / 65535.0


def png16_encoding(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(offset, scale) per channel: value = offset + scale · texel, texel in [0, 1]; channels that stay in
    [0, 1] keep offset 0 and scale 1 (a plain unorm read is then the value itself), also when they pass 0 or 1 by
    less than half a 16-bit step (the quadrature's 2e-8 overshoot of b̄0, Schlick's scale and E near normal
    incidence: clamping them costs less than the rounding does)."""
    table, _ = _checked_table("a 16-bit PNG", table, {})
    if not np.all(np.isfinite(table)):
        raise ParameterError("table contains NaN or inf; a PNG cannot hold it")
    low, high = table.min(axis=(0, 1)), table.max(axis=(0, 1))
    inside = (low >= -PNG16_SLACK) & (high <= 1.0 + PNG16_SLACK)
    offset = np.where(inside, 0.0, low)
    scale = np.where(inside, 1.0, np.maximum(high - low, np.finfo(np.float64).tiny))
    return offset, scale


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png16_bytes(table: np.ndarray, attributes: dict[str, str]) -> bytes:
    """A 16-bit greyscale PNG of a table (H, W, K ≤ 4): channel c in rows c·H … (c + 1)·H − 1, each channel's rows in
    file order (module docstring), with its encoding and attributes in tEXt."""
    table, attributes = _checked_table("a 16-bit PNG", table, attributes)
    if not np.all(np.isfinite(table)):
        raise ParameterError("table contains NaN or inf; refusing to write it")
    height, width, channels = table.shape
    offset, scale = png16_encoding(table)
    texels = np.round(np.clip((table - offset) / scale, 0.0, 1.0) * 65535.0).astype(">u2")
    stacked = np.ascontiguousarray(np.moveaxis(texels, 2, 0).reshape(channels * height, width))
    rows = b"".join(b"\x00" + row.tobytes() for row in stacked)  # filter 0
    encoding = {
        "offset": offset.tolist(),
        "scale": scale.tolist(),
        "rule": "value = offset[c] + scale[c] * texel / 65535 for channel c",
        "layout": f"greyscale, the {channels} channels stacked: channel c in image rows c * {height} to "
        f"c * {height} + {height - 1}",
        "rows_per_channel": height,
    }
    # the encoding is sealed with the texels: a scale edited in the file changes the hash a reader recomputes
    attributes = _sealed({**attributes, "encoding": json.dumps(encoding)}, "uint16", stacked.tobytes())
    chunks = [_chunk(b"IHDR", struct.pack(">IIBBBBB", width, channels * height, 16, 0, 0, 0, 0))]
    chunks += [  # every text is ASCII (table_attributes): Latin-1, as tEXt requires, is then the same bytes
        _chunk(b"tEXt", f"fresnel:{key}".encode("latin-1") + b"\x00" + value.encode("latin-1"))
        for key, value in attributes.items()
    ]
    chunks += [_chunk(b"IDAT", zlib.compress(rows, 9)), _chunk(b"IEND", b"")]
    return b"\x89PNG\r\n\x1a\n" + b"".join(chunks)


def c_identifier(name) -> str:
    """A table's name as a C identifier (module docstring: ``header``); refused where nothing of it is one.

    >>> c_identifier("ggx_generalized-schlick_p5")
    'ggx_generalized_schlick_p5'
    """
    if not isinstance(name, str) or not name.isascii() or not re.search(r"[A-Za-z]", name):
        raise ParameterError(f"a table's name must be ASCII with a letter to be a C name, got {str(name)[:60]!r}")
    identifier = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return identifier if not identifier[0].isdigit() else "_" + identifier


def c_header(table: np.ndarray, name: str, channel_names, attributes: dict[str, str]) -> str:
    """A C/C++ header with the table as ``static const float NAME[H * W * K]`` (row 0 first, channels
    interleaved) and its size, channels and convention. NAME is the table's name as a C identifier (every character
    but letters, digits and ``_`` becomes ``_``: ``ggx_generalized-schlick`` is ``ggx_generalized_schlick``)."""
    table, attributes = _checked_table("a C header", table, attributes)
    name = c_identifier(name)
    height, width, channels = table.shape
    values = table.astype(np.float32).ravel()
    attributes = _sealed(attributes, "float32", values.astype("<f4").tobytes())
    body = ",\n".join("    " + ", ".join(f"{float(v)!r}f" for v in values[i : i + 8]) for i in range(0, values.size, 8))
    upper = name.upper()
    notes = "\n".join(f" * {key}: {value}" for key, value in attributes.items())  # inert lines (table_attributes)
    return (
        f"/* fresnel-basis LUT {name}: {height} rows x {width} columns x {channels} channels "
        f"({', '.join(channel_names)}), float32.\n * Element [j][i][c] = {name}[(j * {width} + i) * {channels} + c].\n"
        f"{notes}\n */\n#ifndef {upper}_H\n#define {upper}_H\n\n"
        f"#define {upper}_WIDTH {width}\n#define {upper}_HEIGHT {height}\n#define {upper}_CHANNELS {channels}\n\n"
        f"static const float {name}[{values.size}] = {{\n{body}\n}};\n\n#endif\n"
    )
