"""LUT files for engines that do not read EXR: 16-bit PNG and a C/C++ header. (EXR is :mod:`preintegrate.exr`.)

Public objects: ``FORMATS``, ``png16_encoding``, ``png16_bytes``, ``c_header``.

* **16-bit PNG** (``png16``): each channel is stored as round((value − offset) / scale · 65535), with
  offset and scale per channel chosen from the table's own range, so a signed channel (the basis table's
  A, b̄3 from −0.64 to 1) survives where a unorm texture would clip it. The engine recovers
  value = offset + scale · texel (texel in [0, 1] as a unorm read returns it); the file states offset and
  scale in a ``tEXt`` chunk (``fresnel:encoding``), beside the convention and the content description.
  Precision: scale / 65535 / 2, 1.5e-5 for the basis table.
* **C/C++ header** (``header``): ``static const float`` arrays in file order (row 0 first, channels
  interleaved), the size, the channel names and the convention in a comment: a table compiled into the
  binary, exact in float32.

A table is always written through :func:`basis.storage.write_together` (atomic, one transaction).

References
----------
:cite:`PNG2003` W3C, "Portable Network Graphics (PNG) Specification (Second Edition)", 2003: chunks
    IHDR (bit depth 16, colour types 0, 4, 2, 6), IDAT (zlib), tEXt, IEND; CRC-32 over type and data.
"""

from __future__ import annotations

import json
import re
import struct
import zlib

import numpy as np

from basis.validation import ParameterError

__all__ = ["FORMATS", "c_header", "png16_bytes", "png16_encoding"]

#: File formats of ``fresnel-lut build --format`` beside ``exr``: name → file suffix.
FORMATS = {"exr": ".exr", "png16": ".png", "header": ".h"}

#: PNG colour type by channel count: grey, grey + alpha, RGB, RGBA.
_COLOUR_TYPE = {1: 0, 2: 4, 3: 2, 4: 6}


def png16_encoding(table: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(offset, scale) per channel: value = offset + scale · texel, texel in [0, 1]; channels that stay in
    [0, 1] keep offset 0 and scale 1 (a plain unorm read is then the value itself)."""
    low, high = table.min(axis=(0, 1)), table.max(axis=(0, 1))
    inside = (low >= 0.0) & (high <= 1.0)
    offset = np.where(inside, 0.0, low)
    scale = np.where(inside, 1.0, np.maximum(high - low, np.finfo(np.float64).tiny))
    return offset, scale


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def png16_bytes(table: np.ndarray, attributes: dict[str, str]) -> bytes:
    """A 16-bit PNG of a table (H, W, K ≤ 4), rows in file order, with its encoding and attributes in tEXt."""
    table = np.asarray(table, dtype=np.float64)
    if table.ndim != 3 or table.shape[2] not in _COLOUR_TYPE or not np.all(np.isfinite(table)):
        raise ParameterError(f"a 16-bit PNG holds a finite table of 1 to 4 channels, got shape {table.shape}")
    height, width, channels = table.shape
    offset, scale = png16_encoding(table)
    texels = np.round(np.clip((table - offset) / scale, 0.0, 1.0) * 65535.0).astype(">u2")
    rows = b"".join(b"\x00" + row.tobytes() for row in texels.reshape(height, width * channels))  # filter 0
    encoding = {"offset": offset.tolist(), "scale": scale.tolist(),
                "rule": "value = offset[c] + scale[c] * texel / 65535 for channel c"}
    text = {**{f"fresnel:{key}": value for key, value in attributes.items()}, "fresnel:encoding": json.dumps(encoding)}
    chunks = [_chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 16, _COLOUR_TYPE[channels], 0, 0, 0))]
    chunks += [_chunk(b"tEXt", key.encode("latin-1") + b"\x00" + value.encode("latin-1", "replace"))
               for key, value in text.items()]
    chunks += [_chunk(b"IDAT", zlib.compress(rows, 9)), _chunk(b"IEND", b"")]
    return b"\x89PNG\r\n\x1a\n" + b"".join(chunks)


def c_header(table: np.ndarray, name: str, channel_names, attributes: dict[str, str]) -> str:
    """A C/C++ header with the table as ``static const float NAME[H * W * K]`` (row 0 first, channels
    interleaved) and its size, channels and convention."""
    table = np.asarray(table, dtype=np.float64)
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
        raise ParameterError(f"a C name must be an identifier, got {name!r}")
    height, width, channels = table.shape
    values = table.astype(np.float32).ravel()
    body = ",\n".join("    " + ", ".join(f"{float(v)!r}f" for v in values[i:i + 8]) for i in range(0, values.size, 8))
    upper = name.upper()
    notes = "\n".join(f" * {key}: {value}".replace("*/", "* /") for key, value in attributes.items())
    return (f"/* fresnel-basis LUT {name}: {height} rows x {width} columns x {channels} channels "
            f"({', '.join(channel_names)}), float32.\n * Element [j][i][c] = {name}[(j * {width} + i) * {channels} + c].\n"
            f"{notes}\n */\n#ifndef {upper}_H\n#define {upper}_H\n\n"
            f"#define {upper}_WIDTH {width}\n#define {upper}_HEIGHT {height}\n#define {upper}_CHANNELS {channels}\n\n"
            f"static const float {name}[{values.size}] = {{\n{body}\n}};\n\n#endif\n")
