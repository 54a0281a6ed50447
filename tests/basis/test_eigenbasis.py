"""The Basis data type and basis.json (basis.eigenbasis): round trip, corruption, atomic write, shipped file."""

import hashlib
import json
import os

import numpy as np
import pytest

from basis.eigenbasis import FORMAT, Basis, BasisFileError, default_basis, shipped_basis_path
from basis.validation import ParameterError


@pytest.fixture(scope="module")
def shipped():
    return default_basis()


@pytest.fixture()
def small_basis():
    """A hand-made 3-term basis on a 32-point grid (no training needed)."""
    theta = np.linspace(0.0, 0.5 * np.pi, 32)
    x = theta / (0.5 * np.pi)
    curves = np.array([np.ones_like(theta), x**4, np.sin(np.pi * x) ** 2])
    return Basis(theta, curves, np.array([0.0, 0.5 * np.pi, 1.3]), {"note": "test", "count": 3})


def write_json(path, data):
    path.write_text(json.dumps(data, indent=1), encoding="utf-8")
    return path


# ----------------------------------------------------------------------------- round trip
def test_write_read_round_trip_is_exact(small_basis, tmp_path):
    """Basis.read(write(b)) has np.array_equal theta, curves, fit angles, equal training dict and content hash."""
    path = small_basis.write(tmp_path / "basis.json")
    loaded = Basis.read(path)
    assert np.array_equal(loaded.theta, small_basis.theta)
    assert np.array_equal(loaded.curves, small_basis.curves)
    assert np.array_equal(loaded.fit_angles, small_basis.fit_angles)
    assert loaded.training == small_basis.training
    assert loaded.content_hash == small_basis.content_hash


def test_shipped_basis_round_trip_is_exact(shipped, tmp_path):
    """The shipped basis survives write/read bit for bit (np.array_equal) with the same hash."""
    loaded = Basis.read(shipped.write(tmp_path / "sub" / "basis.json"))
    assert np.array_equal(loaded.curves, shipped.curves)
    assert np.array_equal(loaded.theta, shipped.theta)
    assert np.array_equal(loaded.fit_angles, shipped.fit_angles)
    assert loaded.content_hash == shipped.content_hash


def test_content_hash_is_sha256_of_the_numbers(small_basis):
    """content_hash == first 16 hex digits of SHA-256 over little-endian float64 theta, curves, fit angles (hashlib)."""
    digest = hashlib.sha256()
    for array in (small_basis.theta, small_basis.curves, small_basis.fit_angles):
        digest.update(np.asarray(array, dtype="<f8").tobytes())
    assert small_basis.content_hash == digest.hexdigest()[:16]
    changed = Basis(small_basis.theta, small_basis.curves + 1e-16, small_basis.fit_angles)
    assert changed.content_hash != small_basis.content_hash


def test_evaluate_reproduces_grid_samples(small_basis, shipped):
    """evaluate(theta_j) == curves[:, j] at the grid nodes (spline interpolates; atol 1e-12) and has shape (..., K)."""
    np.testing.assert_allclose(small_basis.evaluate(small_basis.theta), small_basis.curves.T, rtol=0, atol=1e-12)
    np.testing.assert_allclose(shipped.evaluate(shipped.theta), shipped.curves.T, rtol=0, atol=1e-12)
    assert shipped.evaluate(np.zeros((2, 3))).shape == (2, 3, 4)
    np.testing.assert_allclose(shipped.evaluate_mu(np.cos(0.7)), shipped.evaluate(0.7), rtol=0, atol=1e-12)
    with pytest.raises(ParameterError, match=r"^theta"):
        shipped.evaluate(2.0)
    with pytest.raises(ParameterError, match=r"^mu"):
        shipped.evaluate_mu(-0.1)


# ----------------------------------------------------------------------------- atomic write
def test_write_leaves_no_temporary_file(small_basis, tmp_path):
    """After a successful write the folder holds only basis.json: no '.basis.json.*.tmp' left behind."""
    small_basis.write(tmp_path / "basis.json")
    small_basis.write(tmp_path / "basis.json")  # overwrite, too
    assert list(tmp_path.glob(".basis.json.*.tmp")) == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["basis.json"]


def test_failed_write_keeps_old_file_and_cleans_up(small_basis, tmp_path, monkeypatch):
    """If the final rename fails, the previous file is untouched and the temporary file is removed."""
    path = small_basis.write(tmp_path / "basis.json")
    before = path.read_bytes()
    other = Basis(
        small_basis.theta,
        small_basis.curves,
        small_basis.fit_angles - np.r_[0.0, 0.0, [0.05] * (small_basis.n_terms - 2)],
    )

    def failing_replace(source, destination):
        raise OSError("simulated failure")

    monkeypatch.setattr(os, "replace", failing_replace)
    with pytest.raises(OSError, match="simulated failure"):
        other.write(path)
    monkeypatch.undo()
    assert path.read_bytes() == before
    assert list(tmp_path.glob(".basis.json.*.tmp")) == []


# ----------------------------------------------------------------------------- corrupt files
def test_truncated_json(small_basis, tmp_path):
    """A truncated file -> BasisFileError mentioning 'not valid JSON'."""
    path = small_basis.write(tmp_path / "basis.json")
    text = path.read_text()
    path.write_text(text[: len(text) // 2])
    with pytest.raises(BasisFileError, match="not valid JSON"):
        Basis.read(path)


def test_edited_number_fails_hash(small_basis, tmp_path):
    """Changing one curve sample in the file -> BasisFileError mentioning the content 'hash'."""
    path = small_basis.write(tmp_path / "basis.json")
    data = json.loads(path.read_text())
    data["curves"][1][5] += 1e-9
    write_json(path, data)
    with pytest.raises(BasisFileError, match=r"content hash .* does not match"):
        Basis.read(path)


def test_edited_theta_fails_hash(small_basis, tmp_path):
    """Changing one theta value (still increasing) -> BasisFileError 'hash'."""
    path = small_basis.write(tmp_path / "basis.json")
    data = json.loads(path.read_text())
    data["theta"][3] += 1e-6
    write_json(path, data)
    with pytest.raises(BasisFileError, match="hash"):
        Basis.read(path)


def test_missing_hash_fails(small_basis, tmp_path):
    """A file without content_hash -> BasisFileError 'hash'."""
    path = small_basis.write(tmp_path / "basis.json")
    data = json.loads(path.read_text())
    del data["content_hash"]
    write_json(path, data)
    with pytest.raises(BasisFileError, match="hash"):
        Basis.read(path)


@pytest.mark.parametrize("value", ["fresnel-basis/basis@0", None, 1])
def test_wrong_format(small_basis, tmp_path, value):
    """A foreign or missing 'format' tag -> BasisFileError naming 'format' and the expected tag."""
    path = small_basis.write(tmp_path / "basis.json")
    data = json.loads(path.read_text())
    if value is None:
        del data["format"]
    else:
        data["format"] = value
    write_json(path, data)
    with pytest.raises(BasisFileError, match=rf"format .*expected '{FORMAT}'"):
        Basis.read(path)


def test_not_a_json_object(tmp_path):
    """A JSON list instead of an object -> BasisFileError 'not a fresnel-basis basis file'."""
    path = write_json(tmp_path / "basis.json", [1, 2, 3])
    with pytest.raises(BasisFileError, match="not a fresnel-basis basis file"):
        Basis.read(path)


@pytest.mark.parametrize("field", ["theta", "curves", "fit_angles"])
def test_missing_field(small_basis, tmp_path, field):
    """A file lacking theta / curves / fit_angles -> BasisFileError 'lacks the field <name>'."""
    path = small_basis.write(tmp_path / "basis.json")
    data = json.loads(path.read_text())
    del data[field]
    write_json(path, data)
    with pytest.raises(BasisFileError, match=rf"lacks the field '{field}'"):
        Basis.read(path)


@pytest.mark.parametrize(
    "field, index, match",
    [("curves", (1, 4), "NaN"), ("theta", (4,), "finite"), ("fit_angles", (2,), "fit_angles")],
)
def test_nan_inside(small_basis, tmp_path, field, index, match):
    """NaN written into curves / theta / fit_angles (json allows 'NaN') -> BasisFileError describing it."""
    path = small_basis.write(tmp_path / "basis.json")
    data = json.loads(path.read_text())
    target = data[field]
    for i in index[:-1]:
        target = target[i]
    target[index[-1]] = float("nan")
    path.write_text(json.dumps(data))  # writes the bare token NaN
    assert "NaN" in path.read_text()
    with pytest.raises(BasisFileError, match=match):
        Basis.read(path)


def test_malformed_numbers(small_basis, tmp_path):
    """Strings or ragged rows where numbers belong -> BasisFileError (not a bare ValueError/TypeError)."""
    path = small_basis.write(tmp_path / "basis.json")
    data = json.loads(path.read_text())
    data["curves"][0] = data["curves"][0][:-1]
    write_json(path, data)
    with pytest.raises(BasisFileError):
        Basis.read(path)
    data = json.loads(small_basis.write(tmp_path / "b2.json").read_text())
    data["theta"][0] = "zero"
    write_json(tmp_path / "b2.json", data)
    with pytest.raises(BasisFileError):
        Basis.read(tmp_path / "b2.json")


def test_nonexistent_path(tmp_path):
    """A missing file -> BasisFileError 'does not exist' with the path."""
    path = tmp_path / "nowhere" / "basis.json"
    with pytest.raises(BasisFileError, match="does not exist") as info:
        Basis.read(path)
    assert str(path) in str(info.value)


def test_directory_instead_of_file(tmp_path):
    """A directory at the path -> BasisFileError naming it a folder, refused unread."""
    with pytest.raises(BasisFileError, match="is a folder, not a regular file"):
        Basis.read(tmp_path)


def test_basis_file_error_is_a_parameter_error():
    """BasisFileError is a ParameterError (and so a ValueError)."""
    assert issubclass(BasisFileError, ParameterError) and issubclass(BasisFileError, ValueError)


@pytest.mark.parametrize(
    "theta, curves, fit_angles, match",
    [
        (np.linspace(0, 0.5 * np.pi, 8), np.ones((2, 8)), [0.0, 1.0], "at least 16"),
        (np.linspace(0, 1.5, 32), np.ones((2, 32)), [0.0, 1.0], "span"),
        (np.linspace(0, 0.5 * np.pi, 32)[::-1], np.ones((2, 32)), [0.0, 1.0], "increasing"),
        (np.linspace(0, 0.5 * np.pi, 32), np.ones((2, 31)), [0.0, 1.0], "curves must have shape"),
        (np.linspace(0, 0.5 * np.pi, 32), np.ones((1, 32)), [0.0], "curves must have shape"),
        (np.linspace(0, 0.5 * np.pi, 32), np.full((2, 32), np.inf), [0.0, 1.0], "NaN or inf"),
        (np.linspace(0, 0.5 * np.pi, 32), np.ones((2, 32)), [0.0, 1.0, 1.2], "fit_angles must have shape"),
        (np.linspace(0, 0.5 * np.pi, 32), np.ones((2, 32)), [0.0, 2.0], "fit_angles must be in"),
    ],
)
def test_constructor_validation(theta, curves, fit_angles, match):
    """Basis(...) rejects short/unsorted/partial grids, wrong shapes, inf and out-of-range fit angles."""
    with pytest.raises(ParameterError, match=match):
        Basis(theta, curves, fit_angles)


# ----------------------------------------------------------------------------- shipped basis
def test_shipped_basis_layout(shipped):
    """Shipped basis: 4 terms, theta 0..pi/2 with >= 512 samples, fit angles [0, pi/2, theta2 in (1.35, 1.56), theta3 in (1.0, theta2)]."""
    assert shipped.n_terms == 4
    assert shipped.theta.size >= 512
    assert shipped.theta[0] == 0.0
    np.testing.assert_allclose(shipped.theta[-1], 0.5 * np.pi, rtol=0, atol=1e-15)
    assert np.all(np.diff(shipped.theta) > 0)
    assert shipped.curves.shape == (4, shipped.theta.size)
    np.testing.assert_array_equal(shipped.curves[0], 1.0)
    fit = shipped.fit_angles
    assert fit[0] == 0.0
    np.testing.assert_allclose(fit[1], 0.5 * np.pi, rtol=0, atol=1e-15)
    assert 1.35 < fit[2] < 1.56
    assert 1.0 < fit[3] < fit[2]


def test_shipped_basis_hash_matches_file(shipped):
    """The content_hash recomputed from the numbers equals the 'content_hash' stored in luts/basis.json."""
    data = json.loads(shipped_basis_path().read_text(encoding="utf-8"))
    assert data["format"] == FORMAT
    assert data["n_terms"] == 4
    assert isinstance(data["content_hash"], str) and len(data["content_hash"]) == 16
    assert shipped.content_hash == data["content_hash"]


def test_shipped_basis_end_points(shipped):
    """Shipped curves: b1(0) = 0, b1(pi/2) = 1, b_k(0) = b_k(pi/2) = 0 for k >= 2 (atol 1e-10, as for a fresh build)."""
    np.testing.assert_allclose(shipped.curves[1, [0, -1]], [0.0, 1.0], rtol=0, atol=1e-10)
    np.testing.assert_allclose(shipped.curves[2:, [0, -1]], 0.0, rtol=0, atol=1e-10)


def test_default_basis_is_cached(shipped):
    """default_basis() returns the same object each call (read once)."""
    assert default_basis() is shipped


@pytest.mark.parametrize("value", [1e308, -1e300, 1e4])
def test_a_huge_curve_value_is_one_error_and_no_warning(value, tmp_path, recwarn):
    """A basis file whose curve holds a huge (finite) number, with a matching hash, is refused before any
    spline is built: one BasisFileError, and no SciPy overflow warning printed before it."""
    data = json.loads(shipped_basis_path().read_text())
    data["curves"][2][100] = value
    digest = hashlib.sha256()
    for key in ("theta", "curves", "fit_angles"):
        digest.update(np.ascontiguousarray(np.array(data[key], dtype="<f8")).tobytes())
    data["content_hash"] = digest.hexdigest()[:16]
    path = tmp_path / "basis.json"
    path.write_text(json.dumps(data))
    with pytest.raises(BasisFileError, match="curves must stay within"):
        Basis.read(path)
    assert not [warning for warning in recwarn if issubclass(warning.category, RuntimeWarning)]
