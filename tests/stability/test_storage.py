"""Storage error of the real LUTs in float32 and half EXR, against the float64 table they are written from.

References: IEEE 754 round-to-nearest bounds (float32: |δ| ≤ 2^-24 |x| for normal x, ≤ 2^-150 below 2^-126; half:
|δ| ≤ 2^-11 |x| for |x| ≥ 2^-14, the smallest normal half), the raw half bits as OpenEXR stores them, and a fresh
float64 build of the 128 × 128 table (preintegrate.lut.build_table, the six channels of ``fresnel-lut build``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import OpenEXR
import pytest

from basis.eigenbasis import shipped_basis_path
from basis.validation import ParameterError
from handoff.exr import read_lut, write_lut
from preintegrate.channels import basis_channels, combine, schlick_table_channels
from preintegrate.lut import build_table

SIZE = 128
NAMES = ("R", "G", "B", "A", "S", "T", "E", "D")  # four basis channels, Schlick scale and bias, the albedo E, the dip
ATTRIBUTES = {"channels": ",".join(NAMES), "convention": "test table"}
HALF_MIN_NORMAL = 2.0**-14
HALF_MAX = 65504.0
SHIPPED = Path(shipped_basis_path()).parent


@pytest.fixture(scope="module")
def table64():
    """The 128 × 128 × 8 float64 table of ``fresnel-lut build`` (basis RGBA + Schlick RGBA)."""
    return build_table(combine(basis_channels(), schlick_table_channels()), SIZE)


@pytest.fixture(scope="module")
def stored(table64, tmp_path_factory):
    """{"float32": (values read back, raw channel arrays), "half": (…)} written through write_lut."""
    folder = tmp_path_factory.mktemp("storage")
    result = {}
    for name, half in (("float32", False), ("half", True)):
        path = write_lut(folder / f"{name}.exr", table64, NAMES, ATTRIBUTES, half=half)
        raw = OpenEXR.File(str(path), separate_channels=True).channels()
        result[name] = (read_lut(path)[0], np.stack([raw[channel].pixels for channel in NAMES], axis=-1))
    return result


def test_float64_table_is_finite_and_bounded(table64):
    """The table written is finite and |x| ≤ 1 + 2^-24 (albedos of functions bounded by 1; ≤ half a float32 ulp
    of overshoot from the quadrature): no texel can overflow float32 or half."""
    assert table64.shape == (SIZE, SIZE, 8) and np.all(np.isfinite(table64))
    assert np.max(np.abs(table64)) <= 1.0 + 2.0**-24


def test_float32_storage_error(table64, stored):
    """float32 EXR: raw dtype float32; |stored − x| ≤ 2^-24 |x| (|x| ≥ 2^-126) or ≤ 2^-150 (below): round to nearest."""
    values, raw = stored["float32"]
    assert raw.dtype == np.float32
    error = np.abs(values - table64)
    normal = np.abs(table64) >= 2.0**-126
    assert np.all(error[normal] <= 2.0**-24 * np.abs(table64[normal]))
    assert np.all(error[~normal] <= 2.0**-150)


def test_half_storage_error(table64, stored):
    """half EXR: raw dtype float16; |stored − x| ≤ 2^-11 |x| for |x| ≥ 2^-14 (half an ulp), and texels below 2^-14
    are stored as 0, an error < 2^-14 (6.1e-5, below half's step of 4.9e-4 near 1)."""
    values, raw = stored["half"]
    assert raw.dtype == np.float16
    error = np.abs(values - table64)
    normal = np.abs(table64) >= HALF_MIN_NORMAL
    assert np.all(error[normal] <= 2.0**-11 * np.abs(table64[normal]))
    assert np.all(values[~normal] == 0.0)
    assert np.all(error[~normal] < HALF_MIN_NORMAL)


def test_half_has_no_subnormal_and_no_overflow(table64, stored):
    """The raw half texels hold no inf/NaN and no subnormal (0 < |h| < 2^-14) — although a plain cast of this table
    would give subnormals (the flush is exercised) — and signs of normal texels are kept."""
    _, raw = stored["half"]
    plain_cast = table64.astype(np.float16)
    assert np.count_nonzero((plain_cast != 0) & (np.abs(plain_cast) < HALF_MIN_NORMAL)) > 0
    assert np.all(np.isfinite(raw))
    assert np.count_nonzero((raw != 0) & (np.abs(raw) < HALF_MIN_NORMAL)) == 0
    normal = np.abs(table64) >= HALF_MIN_NORMAL
    assert np.all(np.sign(raw[normal]) == np.sign(table64[normal]))


def test_half_flush_boundaries(tmp_path):
    """Edge values in half: 2^-14 and −2^-14 kept exactly; the next doubles below (±) and ±1e-6, ±1e-30 stored as 0;
    65504 (half's max) kept; 1 kept; no subnormal in the raw bits."""
    below = float(np.nextafter(HALF_MIN_NORMAL, 0.0))
    values = np.array([HALF_MIN_NORMAL, -HALF_MIN_NORMAL, below, -below, 1e-6, -1e-6, 1e-30, -1e-30, HALF_MAX, 1.0])
    path = write_lut(tmp_path / "edges.exr", values.reshape(1, -1, 1), ("R",), {"channels": "R"}, half=True)
    raw = OpenEXR.File(str(path), separate_channels=True).channels()["R"].pixels.ravel()
    expected = np.array([HALF_MIN_NORMAL, -HALF_MIN_NORMAL, 0, 0, 0, 0, 0, 0, HALF_MAX, 1.0])
    np.testing.assert_array_equal(raw.astype(np.float64), expected)
    assert np.count_nonzero((raw != 0) & (np.abs(raw) < HALF_MIN_NORMAL)) == 0


@pytest.mark.skipif(not (SHIPPED / "ggx_basis_rgba.exr").exists(), reason="no shipped LUTs in luts/")
def test_shipped_luts_are_the_float32_rounding_of_a_fresh_build(table64):
    """luts/ggx_basis_rgba.exr and ggx_schlick_rgba.exr equal a fresh float64 build cast to float32, bit for bit (so
    their storage error is ≤ 2^-24 relative and the shipped files are reproducible)."""
    basis_lut, _ = read_lut(SHIPPED / "ggx_basis_rgba.exr")
    schlick_lut, _ = read_lut(SHIPPED / "ggx_schlick_rgba.exr")
    shipped = np.concatenate([basis_lut, schlick_lut], axis=-1)
    assert shipped.shape == table64.shape
    np.testing.assert_array_equal(shipped, table64.astype(np.float32).astype(np.float64))


@pytest.mark.filterwarnings("ignore:overflow encountered in cast:RuntimeWarning")
def test_float32_refuses_values_beyond_float32_range(tmp_path):
    """A texel of 1e39 (finite in float64, inf in float32): ParameterError naming the range, nothing written."""
    table = np.full((2, 2, 1), 0.5)
    table[1, 1, 0] = 1e39
    with pytest.raises(ParameterError, match="float32"):
        write_lut(tmp_path / "big.exr", table, ("R",), {"channels": "R"})
    assert list(tmp_path.iterdir()) == []
