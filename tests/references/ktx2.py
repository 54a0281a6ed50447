"""A KTX2 reader typed from the specification alone (KTX 2.0 §3; Khronos Data Format 1.3 §5), checking
every rule a validator checks for an uncompressed, single-level 2-D float texture, independent of
handoff.formats. No maintained KTX2 reader installs here: libktx's Python binding (pyktx) builds
only against an installed libktx, and pyktx2 0.3.1 computes key/value padding modulo 8 instead of 4.
"""

import struct

import numpy as np

IDENTIFIER = bytes([0xAB, 0x4B, 0x54, 0x58, 0x20, 0x32, 0x30, 0xBB, 0x0D, 0x0A, 0x1A, 0x0A])
#: VkFormat → (NumPy type, channels) for the formats a LUT may use.
FLOAT_FORMATS = {109: ("<f4", 4), 97: ("<f2", 4), 106: ("<f4", 3), 90: ("<f2", 3)}


class KTX2Error(ValueError):
    pass


def _require(condition, message):
    if not condition:
        raise KTX2Error(message)


def read_ktx2(data: bytes) -> dict:
    """{'format', 'width', 'height', 'key_values', 'descriptor', 'texels' (H, W, C) float64}."""
    _require(data[:12] == IDENTIFIER, "bad identifier")
    (vk_format, type_size, width, height, depth, layers, faces, levels, scheme) = struct.unpack_from("<9I", data, 12)
    dfd_offset, dfd_length, kvd_offset, kvd_length, sgd_offset, sgd_length = struct.unpack_from("<4I2Q", data, 48)
    _require(vk_format in FLOAT_FORMATS, f"unexpected vkFormat {vk_format}")
    dtype, channels = FLOAT_FORMATS[vk_format]
    _require(type_size == np.dtype(dtype).itemsize, "typeSize is not the channel size")
    _require(width > 0 and height > 0 and depth == 0 and layers == 0 and faces == 1, "not a plain 2-D texture")
    _require(levels == 1 and scheme == 0, "expected one level, no supercompression")
    _require(sgd_offset == 0 and sgd_length == 0, "global data without supercompression")
    level_offset, level_length, level_uncompressed = struct.unpack_from("<3Q", data, 80)
    # data format descriptor: right after the level index
    _require(dfd_offset == 80 + 24 * levels, "descriptor not after the level index")
    (total,) = struct.unpack_from("<I", data, dfd_offset)
    _require(total == dfd_length, "dfdTotalSize differs from dfdByteLength")
    word0, version, block_size = struct.unpack_from("<IHH", data, dfd_offset + 4)
    _require(word0 == 0 and version == 2, "not a Khronos basic descriptor block, version 1.3")
    _require(block_size == 24 + 16 * channels and total == 4 + block_size, "descriptor size does not fit the samples")
    model, primaries, transfer, flags = data[dfd_offset + 12 : dfd_offset + 16]
    _require(model == 1 and transfer == 1, "expected RGBSDA with a linear transfer")
    planes = data[dfd_offset + 20 : dfd_offset + 28]
    _require(planes[0] == type_size * channels and not any(planes[1:]), "bytesPlane0 is not the texel size")
    samples = []
    for index in range(channels):
        offset, length, channel_type, lower, upper = struct.unpack_from("<HBB4xff", data, dfd_offset + 28 + 16 * index)
        _require(offset == 8 * type_size * index and length == 8 * type_size - 1, "sample bit layout")
        _require(channel_type & 0xC0 == 0xC0, "samples must be signed float")
        _require((channel_type & 0x0F) == (15 if index == 3 else index), "channel order must be R, G, B, A")
        _require((lower, upper) == (-1.0, 1.0), "float sample bounds must be -1.0 and 1.0")
        samples.append(channel_type)
    # key/value data: 4-byte aligned entries, keys sorted, NUL-terminated
    _require(kvd_offset == dfd_offset + dfd_length, "key/value data not after the descriptor")
    key_values, cursor, end = {}, kvd_offset, kvd_offset + kvd_length
    while cursor < end:
        (length,) = struct.unpack_from("<I", data, cursor)
        entry = data[cursor + 4 : cursor + 4 + length]
        key, _, value = entry.partition(b"\x00")
        _require(value.endswith(b"\x00"), f"value of {key!r} is not NUL-terminated")
        key_values[key.decode("utf-8")] = value[:-1].decode("utf-8")
        cursor += 4 + length
        cursor += -cursor % 4
    _require(cursor == end, "key/value data does not end on its length")
    keys = [key.encode("utf-8") for key in key_values]
    _require(keys == sorted(keys), "keys are not sorted")
    # level data
    texel = type_size * channels
    alignment = np.lcm(texel, 4)
    _require(level_offset % alignment == 0 and level_offset >= end, "level data misaligned")
    _require(level_length == level_uncompressed == width * height * texel, "level size")
    _require(level_offset + level_length == len(data), "trailing bytes")
    texels = np.frombuffer(data, dtype=dtype, count=width * height * channels, offset=level_offset)
    return {
        "format": vk_format,
        "width": width,
        "height": height,
        "key_values": key_values,
        "primaries": primaries,
        "flags": flags,
        "samples": samples,
        "texels": texels.astype(np.float64).reshape(height, width, channels),
    }
