"""EXR LUT I/O (handoff.exr): exact round trips, headers, refusal of bad data, atomic writes.

References: numpy's own float32/float16 casts (IEEE round-to-nearest-even), the raw OpenEXR bindings,
and byte comparison of files.
"""

from __future__ import annotations

import os

import numpy as np
import OpenEXR
import pytest

from basis.validation import ParameterError
from handoff import exr
from handoff.exr import LutFileError, read_lut, write_lut, write_luts

RGBA = ("R", "G", "B", "A")
RG = ("R", "G")


def _table(height=16, width=24, channels=4, seed=0):
    rng = np.random.default_rng(seed)
    # values of a LUT's range plus awkward ones: negatives, subnormal-ish, exact 0 and 1, many digits
    table = rng.uniform(-0.5, 1.5, size=(height, width, channels))
    table[0, 0] = 0.0
    table[0, 1] = 1.0
    table[1, 0] = 1e-30
    table[1, 1] = np.pi
    return table


def _attributes(names, **extra):
    return {"channels": ",".join(names), "convention": "column i <-> mu_o = (i + 0.5) / width", **extra}


def _leftovers(folder):
    return sorted(p.name for p in folder.iterdir() if p.name.endswith(".tmp") or p.name.startswith("."))


def test_float32_round_trip_is_exact(tmp_path):
    """read_lut(write_lut(t)) == t cast to float32, bit for bit (np.array_equal), in channel order, shape (H, W, K)."""
    table = _table()
    path = write_lut(tmp_path / "lut.exr", table, RGBA, _attributes(RGBA))
    values, attributes = read_lut(path)
    assert values.shape == table.shape and values.dtype == np.float64
    assert np.array_equal(values, table.astype(np.float32).astype(np.float64))
    assert attributes["pixel_type"] == "float32"


def test_two_channel_round_trip_and_explicit_channel_order(tmp_path):
    """A 2-channel (R, G) LUT round-trips exactly; channel_names=("G", "R") returns the channels swapped (exact)."""
    table = _table(channels=2, seed=1)
    path = write_lut(tmp_path / "rg.exr", table, RG, _attributes(RG))
    values, _ = read_lut(path)
    assert np.array_equal(values, table.astype(np.float32).astype(np.float64))
    swapped, _ = read_lut(path, channel_names=("G", "R"))
    assert np.array_equal(swapped, values[:, :, ::-1])
    with pytest.raises(LutFileError, match="lacks channels"):
        read_lut(path, channel_names=("B",))


def test_non_square_orientation(tmp_path):
    """Row j / column i of the table is row j / column i of the file: a ramp table comes back identical (exact)."""
    height, width = 5, 9
    rows, cols = np.meshgrid(np.arange(height), np.arange(width), indexing="ij")
    table = np.stack([rows, cols, rows * 100 + cols, np.zeros_like(rows)], axis=-1).astype(np.float64)
    path = write_lut(tmp_path / "ramp.exr", table, RGBA, _attributes(RGBA))
    values, _ = read_lut(path)
    assert np.array_equal(values, table)
    raw = OpenEXR.File(str(path), separate_channels=True)
    np.testing.assert_array_equal(raw.channels()["B"].pixels, table[:, :, 2].astype(np.float32))


def test_half_round_trip(tmp_path):
    """half=True stores float16 (raw OpenEXR dtype) and reads back exactly numpy's float16 cast; so |Δ| ≤ 2^-11 relative."""
    table = _table(seed=2)
    path = write_lut(tmp_path / "half.exr", table, RGBA, _attributes(RGBA), half=True)
    values, attributes = read_lut(path)
    assert attributes["pixel_type"] == "half"
    assert np.array_equal(values, table.astype(np.float16).astype(np.float64))
    np.testing.assert_allclose(values, table, rtol=2.0**-11, atol=2.0**-24)
    raw = OpenEXR.File(str(path), separate_channels=True)
    assert all(raw.channels()[name].pixels.dtype == np.float16 for name in RGBA)


def test_half_refuses_values_beyond_half_range(tmp_path):
    """A value above 65504 cannot be stored as half: ParameterError, nothing written."""
    table = _table(seed=3)
    table[2, 2, 1] = 1e5
    with pytest.raises(ParameterError, match="half"):
        write_lut(tmp_path / "big.exr", table, RGBA, _attributes(RGBA), half=True)
    assert list(tmp_path.iterdir()) == []


def test_header_attributes(tmp_path):
    """Every attribute given comes back under fresnel: (convention, channels, basis_hash), plus pixel_type; raw header agrees."""
    attributes = _attributes(RGBA, basis_hash="35e880f1f7f0f6c1", channel_set="basis")
    path = write_lut(tmp_path / "lut.exr", _table(), RGBA, attributes)
    _, read = read_lut(path)
    for key, value in attributes.items():
        assert read[key] == value
    header = OpenEXR.File(str(path)).header()
    assert header["fresnel:basis_hash"] == "35e880f1f7f0f6c1"
    assert header["fresnel:convention"] == attributes["convention"]
    assert header["compression"] == OpenEXR.ZIP_COMPRESSION


@pytest.mark.parametrize("bad", [np.nan, np.inf, -np.inf])
def test_non_finite_table_is_refused_and_existing_file_untouched(tmp_path, bad):
    """Writing a table with NaN/±inf raises ParameterError and leaves the existing file byte-identical; no temporaries."""
    path = write_lut(tmp_path / "lut.exr", _table(), RGBA, _attributes(RGBA))
    before = path.read_bytes()
    table = _table(seed=4)
    table[3, 4, 2] = bad
    with pytest.raises(ParameterError, match="NaN or inf"):
        write_lut(path, table, RGBA, _attributes(RGBA))
    assert path.read_bytes() == before
    assert _leftovers(tmp_path) == []


def test_wrong_shape_is_refused(tmp_path):
    """A table whose last axis does not match the channel names, or that is not 3-D, raises ParameterError; nothing written."""
    with pytest.raises(ParameterError, match="shape"):
        write_lut(tmp_path / "a.exr", _table(channels=3), RGBA, _attributes(RGBA))
    with pytest.raises(ParameterError, match="shape"):
        write_lut(tmp_path / "b.exr", np.zeros((4, 4)), RG, _attributes(RG))
    assert list(tmp_path.iterdir()) == []


def test_write_luts_is_all_or_nothing_on_bad_table(tmp_path):
    """write_luts validates every table before writing: one NaN table → ParameterError, neither file created nor replaced."""
    first = tmp_path / "a.exr"
    write_lut(first, _table(), RGBA, _attributes(RGBA))
    before = first.read_bytes()
    bad = _table(channels=2)
    bad[0, 0, 0] = np.nan
    with pytest.raises(ParameterError):
        write_luts([(first, _table(seed=9), RGBA, _attributes(RGBA)), (tmp_path / "b.exr", bad, RG, _attributes(RG))])
    assert first.read_bytes() == before
    assert not (tmp_path / "b.exr").exists()
    assert _leftovers(tmp_path) == []


def test_interrupted_write_leaves_existing_files(tmp_path, monkeypatch):
    """KeyboardInterrupt inside the 2nd OpenEXR write: both existing files byte-identical, no .tmp left, the interrupt propagates."""
    paths = [tmp_path / "a.exr", tmp_path / "b.exr"]
    write_luts([(paths[0], _table(), RGBA, _attributes(RGBA)), (paths[1], _table(channels=2), RG, _attributes(RG))])
    before = [p.read_bytes() for p in paths]
    original = OpenEXR.File.write
    calls = []

    def interrupted(self, filename):
        calls.append(filename)
        if len(calls) == 2:
            with open(filename, "wb") as stream:  # a half-written temporary
                stream.write(b"v/1\x01partial")
            raise KeyboardInterrupt
        return original(self, filename)

    monkeypatch.setattr(exr.OpenEXR.File, "write", interrupted)
    with pytest.raises(KeyboardInterrupt):
        write_luts(
            [
                (paths[0], _table(seed=5), RGBA, _attributes(RGBA)),
                (paths[1], _table(channels=2, seed=6), RG, _attributes(RG)),
            ]
        )
    assert [p.read_bytes() for p in paths] == before
    assert _leftovers(tmp_path) == []


def test_missing_file_raises(tmp_path):
    """read_lut of a path that does not exist raises LutFileError (a ParameterError)."""
    with pytest.raises(LutFileError, match="does not exist"):
        read_lut(tmp_path / "nope.exr")
    assert issubclass(LutFileError, ParameterError)


@pytest.mark.parametrize("fraction", [0.0, 0.01, 0.25, 0.5, 0.9, 0.999])
def test_truncated_file_raises(tmp_path, fraction):
    """An EXR cut to a fraction of its bytes raises LutFileError (never returns garbage, never another exception)."""
    path = write_lut(tmp_path / "lut.exr", _table(64, 64), RGBA, _attributes(RGBA))
    data = path.read_bytes()
    truncated = tmp_path / "truncated.exr"
    truncated.write_bytes(data[: int(len(data) * fraction)])
    with pytest.raises(LutFileError):
        read_lut(truncated)


@pytest.mark.parametrize(
    "content", [b"", b"hello, world\n", b"\x76\x2f\x31\x01" + b"\x00" * 40, b"\x89PNG\r\n\x1a\n" + bytes(200)]
)
def test_non_exr_file_raises(tmp_path, content):
    """A text file, an empty file, a bare EXR magic number and a PNG header raise LutFileError."""
    path = tmp_path / "fake.exr"
    path.write_bytes(content)
    with pytest.raises(LutFileError):
        read_lut(path)


def test_exr_without_project_attributes_raises(tmp_path):
    """A valid EXR written directly with OpenEXR (no fresnel: attributes) raises LutFileError naming the missing attribute."""
    path = tmp_path / "foreign.exr"
    channels = {name: np.zeros((4, 4), dtype=np.float32) for name in RGBA}
    OpenEXR.File({"compression": OpenEXR.ZIP_COMPRESSION, "type": OpenEXR.scanlineimage}, channels).write(str(path))
    with pytest.raises(LutFileError, match="fresnel:channels"):
        read_lut(path)


def test_no_temporary_files_remain(tmp_path):
    """After writes (new file, overwrite, half, a 2-file set) the folder holds exactly the LUTs: no .tmp or hidden files."""
    write_lut(tmp_path / "a.exr", _table(), RGBA, _attributes(RGBA))
    write_lut(tmp_path / "a.exr", _table(seed=1), RGBA, _attributes(RGBA))
    write_lut(tmp_path / "h.exr", _table(), RGBA, _attributes(RGBA), half=True)
    write_luts(
        [
            (tmp_path / "s" / "b.exr", _table(), RGBA, _attributes(RGBA)),
            (tmp_path / "s" / "c.exr", _table(channels=2), RG, _attributes(RG)),
        ]
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.exr", "h.exr", "s"]
    assert sorted(p.name for p in (tmp_path / "s").iterdir()) == ["b.exr", "c.exr"]


@pytest.mark.parametrize("half", [False, True])
def test_deterministic_bytes(tmp_path, half):
    """Same inputs twice → byte-identical files (no time stamps or random padding in the header)."""
    first = write_lut(tmp_path / "one.exr", _table(), RGBA, _attributes(RGBA, basis_hash="abc"), half=half)
    second = write_lut(tmp_path / "two.exr", _table(), RGBA, _attributes(RGBA, basis_hash="abc"), half=half)
    assert first.read_bytes() == second.read_bytes()


def test_overwrite_replaces_atomically(tmp_path):
    """Overwriting an existing LUT gives the new content (exact) and a new inode (rename into place, not in-place writes)."""
    path = write_lut(tmp_path / "lut.exr", _table(), RGBA, _attributes(RGBA))
    inode = os.stat(path).st_ino
    write_lut(path, _table(seed=8), RGBA, _attributes(RGBA))
    values, _ = read_lut(path)
    assert np.array_equal(values, _table(seed=8).astype(np.float32).astype(np.float64))
    assert os.stat(path).st_ino != inode


def test_written_file_mode_follows_umask(tmp_path):
    """A written LUT has the permissions of a normally created file, 0o666 & ~umask (like open(path, 'wb'))."""
    umask = os.umask(0o022)
    os.umask(umask)
    if (0o666 & ~umask) == 0o600:
        pytest.skip("with this umask 0600 is the expected mode; the test cannot tell")
    path = write_lut(tmp_path / "lut.exr", _table(), RGBA, _attributes(RGBA))
    assert (os.stat(path).st_mode & 0o777) == (0o666 & ~umask)


def test_content_hash_catches_edited_header_and_pixels(tmp_path):
    """An EXR whose fresnel: attributes or pixels change after writing (re-saved by OpenEXR, so the file itself is
    valid) is refused by read_lut: the stored content hash no longer matches (EXR has no checksum of its own)."""
    path = write_lut(
        tmp_path / "lut.exr", np.full((4, 5, 2), 0.25), ("R", "G"), {"convention": "test", "channels": "R,G"}
    )
    read_lut(path)  # the untouched file reads
    for edit in ("header", "pixels"):
        image = OpenEXR.File(str(path), separate_channels=True)
        header, channels = image.header(), image.channels()
        if edit == "header":
            header["fresnel:convention"] = "tset"
        else:
            pixels = channels["G"].pixels.copy()
            pixels[2, 3] = np.float32(0.2500001)
            channels["G"] = OpenEXR.Channel("G", pixels)
        edited = tmp_path / f"{edit}.exr"
        OpenEXR.File(header, channels).write(str(edited))
        with pytest.raises(LutFileError, match="content hash"):
            read_lut(edited)
