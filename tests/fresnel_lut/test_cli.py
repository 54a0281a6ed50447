"""The ``fresnel-lut`` command (fresnel_lut.cli): LUT contents against an independent integration,
headers, coefficients, one-line errors with exit status 2, and Ctrl-C atomicity.

References: adaptive scipy cubature over ω_i (tests/references/integration.py) for texels with α ≳ 0.02,
cubature over the half vector and the α → 0 limit for the first row, the library's documented Python API
(coefficients_from_nk / coefficients_from_gulbrandsen) for ``coeffs``, byte comparison for atomicity.
"""

from __future__ import annotations

import io
import json
import os
import sys
from pathlib import Path

import numpy as np
import OpenEXR
import pytest

from basis import coefficients_from_gulbrandsen, coefficients_from_nk, coefficients_from_samples, default_basis
from basis.eigenbasis import shipped_basis_path
from fresnel_lut import cli
from fresnel_lut.progress import Progress
from handoff import exr, tables
from handoff.exr import read_lut
from handoff.shipped import BASIS_LUT, SCHLICK_LUT, SHIPPED_LUTS
from handoff.tables import DEFAULT_BUILD_FILES
from preintegrate.channels import basis_channels, schlick_table_channels
from preintegrate.lut import PIXEL_CONVENTION
from tests.conftest import assert_one_line_error, fail_on_call, run, run_subprocess
from tests.references.integration import reference_albedo, reference_albedo_half_vector

SIZE = 32
#: The basis channels of the default basis, then Schlick's scale and bias: the 6 LUT channels.
_BASIS = basis_channels().functions
_SCHLICK = schlick_table_channels().functions  # R = scale, G = bias, B = E (the albedo without Fresnel), A = dip


def build_channels(x):
    """The eight functions of the default build: b0 … b3, then Schlick's 1 − (1 − x)^5, (1 − x)^5, 1 and the dip
    x (1 − x)^6."""
    return np.concatenate([_BASIS(x), _SCHLICK(x)], axis=-1)


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """One in-process ``build --size 32`` shared by the content tests: (folder, stdout)."""
    out = tmp_path_factory.mktemp("luts")
    capture = io.StringIO()
    saved = sys.stdout
    sys.stdout = capture
    try:
        status = cli.main(["build", "--size", str(SIZE), "--out", str(out)])
    finally:
        sys.stdout = saved
    assert status == 0
    return out, capture.getvalue()


def _texel(i, j, size=SIZE):
    """Convention: column i ↔ √μo = i/(W − 1), row j ↔ r = j/(H − 1), α = r²."""
    return (i / (size - 1)) ** 2, (j / (size - 1)) ** 2


def _reference(mu_o, alpha):
    """Adaptive cubature of the seven functions at (μo, α); the μo = 0 column by its limit, the cubature at
    μo = 1e-9 (the split sum is continuous there: it differs from the quadrature's μo = 0 by < 1e-8), to a relative
    1e-8 (tighter takes minutes at that grazing angle, and the tests allow 1e-6)."""
    if mu_o == 0.0:
        return reference_albedo(build_channels, 1e-9, alpha, rtol=1e-8, atol=1e-9, accepted_error=1e-8)
    return reference_albedo(build_channels, mu_o, alpha)


# ----------------------------------------------------------------------------- build: files and headers
def test_build_writes_both_luts_with_convention(built):
    """build --size 32 writes RGBA basis and Schlick EXRs (R = scale, G = bias, B = E = R + G, A = dip), 32×32, finite,
    header = PIXEL_CONVENTION and default basis hash (exact)."""
    out, stdout = built
    assert sorted(p.name for p in out.iterdir()) == sorted(DEFAULT_BUILD_FILES)
    basis_table, basis_attributes = read_lut(out / BASIS_LUT)
    schlick_table, schlick_attributes = read_lut(out / SCHLICK_LUT)
    assert basis_table.shape == (SIZE, SIZE, 4) and schlick_table.shape == (SIZE, SIZE, 4)
    np.testing.assert_allclose(schlick_table[..., 2], schlick_table[..., 0] + schlick_table[..., 1], rtol=0, atol=1e-7)
    assert np.all(np.isfinite(basis_table)) and np.all(np.isfinite(schlick_table))
    assert basis_attributes["channels"] == "R,G,B,A" and schlick_attributes["channels"] == "R,G,B,A"
    for attributes in (basis_attributes, schlick_attributes):
        assert attributes["convention"] == PIXEL_CONVENTION
        assert "sqrt(mu_o) = i / (width - 1)" in attributes["convention"] and "alpha = r^2" in attributes["convention"]
        assert attributes["width"] == attributes["height"] == str(SIZE)
        assert attributes["pixel_type"] == "float32"
    assert basis_attributes["basis_hash"] == default_basis().content_hash
    raw = OpenEXR.File(str(out / BASIS_LUT), separate_channels=True)
    assert sorted(raw.channels()) == ["A", "B", "G", "R"]
    assert all(channel.pixels.dtype == np.float32 for channel in raw.channels().values())
    assert sorted(OpenEXR.File(str(out / SCHLICK_LUT), separate_channels=True).channels()) == ["A", "B", "G", "R"]
    assert default_basis().content_hash in stdout


# Texels (column i, row j) with α ≥ 0.016, spread over the table incl. first (μo = 0) and last column and last row.
REFERENCE_TEXELS = [(0, 31), (31, 31), (15, 31), (0, 16), (31, 16), (10, 8), (20, 24), (5, 12), (27, 4)]


@pytest.mark.parametrize("i, j", REFERENCE_TEXELS)
def test_build_values_match_independent_integration(built, i, j):
    """LUT texel (i, j) equals adaptive scipy cubature over (θi, φi) of the same 7 functions at the convention's (μo, α); atol 1e-6."""
    out, _ = built
    mu_o, alpha = _texel(i, j)
    lut = np.concatenate([read_lut(out / BASIS_LUT)[0][j, i], read_lut(out / SCHLICK_LUT)[0][j, i]])
    np.testing.assert_allclose(lut, _reference(mu_o, alpha), rtol=0, atol=1e-6)


def test_build_first_row_is_the_mirror(built):
    """Row 0 is r = 0, the mirror: every texel is its functions at μo itself, b_k(μo) and Schlick's
    (1 − (1 − μo)^5, (1 − μo)^5, 1), μo = 0 and 1 included (float32 storage: atol 1e-7)."""
    out, _ = built
    mu_o = _texel(np.arange(SIZE), 0)[0]
    lut = np.concatenate([read_lut(out / BASIS_LUT)[0][0], read_lut(out / SCHLICK_LUT)[0][0]], axis=-1)
    np.testing.assert_allclose(lut, build_channels(mu_o), rtol=0, atol=1e-7)


@pytest.mark.parametrize("i", [2, 15, 31])
def test_build_second_row_matches_half_vector_integration(built, i):
    """Row 1 (α = (1/31)² ≈ 1.0e-3, too sharp for cubature in ω_i) equals adaptive cubature over the half vector; atol 1e-6.

    (VNDF Monte Carlo is no reference here: 1 − F̄ comes from reflections below the horizon with tiny
    probability, so millions of samples see few of them.)
    """
    out, _ = built
    mu_o, alpha = _texel(i, 1)
    lut = np.concatenate([read_lut(out / BASIS_LUT)[0][1, i], read_lut(out / SCHLICK_LUT)[0][1, i]])
    np.testing.assert_allclose(lut, reference_albedo_half_vector(build_channels, mu_o, alpha), rtol=0, atol=1e-6)


def test_build_second_row_small_alpha_limit(built):
    """Row 1: basis channel k ≈ b_k(μo)·(R + G of the Schlick LUT = no-Fresnel albedo); |Δ| ≤ 2(α/μo)² ln(1/α) + 1e-6
    where α < μo (the columns from 4 on: the bound says nothing closer to grazing)."""
    out, _ = built
    basis_table, schlick_table = read_lut(out / BASIS_LUT)[0], read_lut(out / SCHLICK_LUT)[0]
    columns = np.arange(4, SIZE)
    mu_o, alpha = _texel(columns, 1)
    albedo = schlick_table[1, columns, 0] + schlick_table[1, columns, 1]
    limit = default_basis().evaluate_mu(mu_o) * albedo[:, None]
    bound = 2.0 * (alpha / mu_o) ** 2 * np.log(1.0 / alpha) + 1e-6
    assert np.all(np.abs(basis_table[1, columns] - limit) <= bound[:, None])
    assert np.all(albedo <= 1.0 + 1e-6) and np.all(1.0 - albedo <= bound)


def test_build_orientation(built):
    """Row 0 is the smoothest row (the mirror): Schlick bias G(row 0, col i) = (1 − μo)^5 (atol 1e-7); μo grows
    with column."""
    out, _ = built
    schlick = read_lut(out / SCHLICK_LUT)[0]
    mu_o = _texel(np.arange(SIZE), 0)[0]
    np.testing.assert_allclose(schlick[0, :, 1], (1.0 - mu_o) ** 5, rtol=0, atol=1e-7)
    assert np.all(np.diff(schlick[0, :, 1]) < 0)  # bias falls as μo grows along a row


def test_build_half(tmp_path, capsys):
    """build --half stores float16 channels (raw OpenEXR dtype) and agrees with the float32 build within half precision
    (rtol 2^-10), except that magnitudes below half's smallest normal 2^-14 are stored as 0 (absolute error < 2^-14)."""
    assert run(["build", "--size", 8, "--out", tmp_path / "f"]) == 0
    assert run(["build", "--size", 8, "--half", "--out", tmp_path / "h"]) == 0
    assert "half" in capsys.readouterr().out
    for name in SHIPPED_LUTS:
        raw = OpenEXR.File(str(tmp_path / "h" / name), separate_channels=True)
        assert all(channel.pixels.dtype == np.float16 for channel in raw.channels().values())
        half, attributes = read_lut(tmp_path / "h" / name)
        full, _ = read_lut(tmp_path / "f" / name)
        assert attributes["pixel_type"] == "half"
        tiny = np.abs(full) < 2.0**-14
        np.testing.assert_allclose(half[~tiny], full[~tiny], rtol=2.0**-10, atol=2.0**-24)
        assert np.all(half[tiny] == 0.0)


def test_build_is_deterministic(tmp_path):
    """Two builds with the same arguments give byte-identical EXR files."""
    assert run(["build", "--size", 8, "--out", tmp_path / "a"]) == 0
    assert run(["build", "--size", 8, "--out", tmp_path / "b"]) == 0
    for name in SHIPPED_LUTS:
        assert (tmp_path / "a" / name).read_bytes() == (tmp_path / "b" / name).read_bytes()


@pytest.mark.slow
def test_build_via_subprocess(tmp_path):
    """`python -m fresnel_lut.cli build` exits 0 and writes the same files as the in-process build (byte-identical), no stderr traceback."""
    result = run_subprocess(["build", "--size", 8, "--out", tmp_path / "sub"], cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert "Traceback" not in result.stderr
    assert run(["build", "--size", 8, "--out", tmp_path / "inproc"]) == 0
    for name in SHIPPED_LUTS:
        assert (tmp_path / "sub" / name).read_bytes() == (tmp_path / "inproc" / name).read_bytes()


SHIPPED = Path(shipped_basis_path()).parent


@pytest.mark.skipif(not (SHIPPED / BASIS_LUT).exists(), reason="no shipped LUTs in luts/")
def test_shipped_luts_match_shipped_basis_and_reference():
    """The shipped luts/*.exr carry the shipped basis' hash and the convention, and 5 texels match cubature over ω_i (atol 1e-6)."""
    basis_table, basis_attributes = read_lut(SHIPPED / BASIS_LUT)
    schlick_table, schlick_attributes = read_lut(SHIPPED / SCHLICK_LUT)
    assert basis_attributes["basis_hash"] == default_basis().content_hash
    assert basis_attributes["convention"] == schlick_attributes["convention"] == PIXEL_CONVENTION
    size = basis_table.shape[1]
    assert basis_table.shape[:2] == schlick_table.shape[:2] == (size, size)
    for i, j in [
        (0, size - 1),
        (size - 1, size - 1),
        (size // 2, size // 3),
        (size // 5, size // 2),
        (size - 1, size // 4),
    ]:
        mu_o, alpha = _texel(i, j, size)
        lut = np.concatenate([basis_table[j, i], schlick_table[j, i]])
        np.testing.assert_allclose(lut, _reference(mu_o, alpha), rtol=0, atol=1e-6, err_msg=f"texel {(i, j)}")


# ----------------------------------------------------------------------------- coeffs
GOLD = ([0.18, 0.42, 1.37], [3.42, 2.35, 1.77])


def test_coeffs_json_matches_api(capsys):
    """coeffs --eta --kappa --json prints a (3, 4) list equal to basis.coefficients_from_nk (exact: JSON floats round-trip)."""
    assert run(["coeffs", "--eta", *GOLD[0], "--kappa", *GOLD[1], "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    coefficients = np.array(data["coefficients"])
    assert coefficients.shape == (3, 4)
    np.testing.assert_array_equal(coefficients, coefficients_from_nk(np.array(GOLD[0]), np.array(GOLD[1])))
    assert data["basis_hash"] == default_basis().content_hash
    assert data["material"]["eta"] == GOLD[0] and data["material"]["kappa"] == GOLD[1]


def test_coeffs_gulbrandsen(capsys):
    """coeffs --reflectivity --edge-tint --json equals basis.coefficients_from_gulbrandsen (exact); the text form prints R, G, B rows."""
    r, g = [0.9, 0.6, 0.3], [0.2, 0.5, 0.9]
    assert run(["coeffs", "--reflectivity", *r, "--edge-tint", *g, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    np.testing.assert_array_equal(
        np.array(data["coefficients"]), coefficients_from_gulbrandsen(np.array(r), np.array(g))
    )
    assert run(["coeffs", "--reflectivity", *r, "--edge-tint", *g]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert [line.split(":")[0].strip() for line in lines[1:4]] == ["R", "G", "B"]
    assert all("c3=" in line for line in lines[1:4])


def test_coeffs_material_preset(capsys):
    """coeffs --material Gold --json equals luts/materials.json (exact); --space sRGB; the text form names F0."""
    from basis.presets import material_preset

    assert run(["coeffs", "--material", "gold", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    np.testing.assert_array_equal(np.array(data["coefficients"]), material_preset("Gold")["coefficients"])
    assert data["material"]["preset"] == "Gold" and data["material"]["space"] == "ACEScg"
    assert run(["coeffs", "--material", "Gold", "--space", "sRGB"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0].startswith("Gold (sRGB, linear): F0 = ")
    assert [line.split(":")[0].strip() for line in lines[2:5]] == ["R", "G", "B"]


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--material", "Unobtainium"], "material must be one of"),
        (["--material", "Gold", "--eta", 1, 1, 1, "--kappa", 1, 1, 1], "give one of"),
        (["--eta", 1, 1, 1, "--kappa", 1, 1, 1, "--space", "sRGB"], "--space goes with --material"),
        (["--model", "f82", "--f0", 0.9, 0.6, 0.3], "needs f82"),
        (["--model", "f82", "--f0", 0.9, 0.6, 0.3, "--f82", 0.5, 0.5, 1.5], "f82 must be in [0, 1]"),
        (["--model", "schlick", "--f0", 0.5, 0.5, 0.5, "--exponent", 3], "takes ['f0']"),
        (["--model", "schlick", "--f0", 0.5, 0.5, 0.5, "--material", "Gold"], "not --material"),
    ],
)
def test_coeffs_errors(argv, message, capsys):
    assert run(["coeffs", *argv]) == 2
    err = capsys.readouterr().err
    assert_one_line_error(err)
    assert message in err


def test_build_model_table(tmp_path, capsys):
    """build --model f82 writes a 3-channel table whose texels equal the integrator's (float32), with the
    combination rule in the header; build --model generalized-schlick --exponent 2 records p and names the file by it (issue 26 item 9)."""
    from basis.models import fresnel_model
    from handoff.exr import read_lut
    from preintegrate.channels import channel_set
    from preintegrate.quadrature import directional_albedo

    assert run(["build", "--model", "f82", "--size", 8, "--out", tmp_path]) == 0
    table, header = read_lut(tmp_path / "ggx_f82.exr")
    assert table.shape == (8, 8, 3) and "x (1-x)^6" in header["combination"]
    mu_o, roughness = (5 / 7) ** 2, 2 / 7
    expected = directional_albedo(channel_set("f82").functions, mu_o, roughness**2)
    np.testing.assert_allclose(table[2, 5], expected, rtol=1e-6, atol=1e-7)
    assert run(["build", "--model", "generalized-schlick", "--exponent", 2, "--size", 4, "--out", tmp_path]) == 0
    assert read_lut(tmp_path / "ggx_generalized-schlick_exponent2.exr")[1]["model_exponent"] == "2.0"
    assert fresnel_model("f82").linear


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--model", "gulbrandsen"], "not linear"),
        (["--model", "generalized-schlick", "--alpha", 2], "takes ['--exponent']"),
        (["--model", "nope"], "model must be one of"),
        (["--model", "generalized-schlick", "--exponent", 0], "exponent must be in"),
    ],
)
def test_build_model_errors_write_nothing(argv, message, tmp_path, capsys):
    assert run(["build", *argv, "--size", 4, "--out", tmp_path / "out"]) == 2
    err = capsys.readouterr().err
    assert_one_line_error(err)
    assert message in err
    assert not (tmp_path / "out").exists()


def test_coeffs_model(capsys):
    """coeffs --model f82 --json: four-point coefficients of the model's curve, the Schlick table's weights (f0, 1, 0, -a) of R, G, B, A."""
    from basis.angles import cos_theta
    from basis.models import fresnel_model

    f0, f82 = [0.9, 0.6, 0.3], [0.85, 0.55, 0.35]
    assert run(["coeffs", "--model", "f82", "--f0", *f0, "--f82", *f82, "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    basis = default_basis()
    samples = fresnel_model("f82").evaluate(cos_theta(basis.fit_angles)[:, None], f0=f0, f82=f82)
    np.testing.assert_allclose(np.array(data["coefficients"]), coefficients_from_samples(samples.T), atol=1e-15)
    a = 823543 / 46656 * (np.array(f0) - f82) + 49 / 6 * (1 - np.array(f0))
    np.testing.assert_allclose(
        np.array(data["own_split_sum"]["weights"]), np.stack([f0, [1, 1, 1], [0, 0, 0], -a], -1), atol=1e-12
    )
    assert data["own_split_sum"]["lut"].startswith("ggx_schlick_rgba.exr")
    assert data["own_split_sum"]["exact"] is True
    assert (
        run(
            [
                "coeffs",
                "--model",
                "generalized-schlick",
                "--r0",
                0.04,
                0.04,
                0.04,
                "--r90",
                1,
                1,
                1,
                "--exponent",
                5,
                "--fit",
                "least-squares",
            ]
        )
        == 0
    )
    assert "least-squares projection" in capsys.readouterr().out


def test_render_refuses_a_file_as_output_folder(tmp_path, capsys):
    target = tmp_path / "file"
    target.write_text("x")
    assert run(["render", "--quick", "--out", target]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert target.read_text() == "x"


def test_report_and_render_write_under_build_by_default():
    """Issue 36 item 9: the defaults never overwrite the committed report/ (README suggests both commands)."""
    parser = cli.make_parser()
    assert parser.parse_args(["report", "--quick"]).out == "build/report"
    assert parser.parse_args(["render", "--quick"]).out == "build/render"


@pytest.mark.parametrize("study", ["lut_error_vs_time", "plot_model_error"])
def test_an_interrupted_report_leaves_no_folder(tmp_path, monkeypatch, capsys, study):
    """Issue 36 item 8: Ctrl-C during a study or while the plots are drawn leaves no new (empty) folder: the folder
    is made with the files, in one transaction."""
    from fresnel_lut.report import readme

    def interrupted(*arguments, **keywords):
        raise KeyboardInterrupt

    if study == "plot_model_error":  # the studies run (quick); the interrupt comes once they are done
        monkeypatch.setattr(readme, "lut_error_vs_time", lambda **keywords: {})
        monkeypatch.setattr(readme, "model_error_study", lambda **keywords: {})
        monkeypatch.setattr(readme, "basis_build_cost", lambda *arguments: {})
        monkeypatch.setattr(readme, "basis_convergence", lambda **keywords: {})
        monkeypatch.setattr(readme, "approximation_table", lambda **keywords: {})
        monkeypatch.setattr(readme, "plot_lut_error", lambda result: b"")
    monkeypatch.setattr(readme, study, interrupted)
    out = tmp_path / "new" / "report"
    assert run(["report", "--quick", "--out", out]) == 130
    assert "no file was written" in capsys.readouterr().err
    assert list(tmp_path.iterdir()) == []


def test_materials_refuses_a_folder_as_presets_before_any_work(tmp_path, capsys):
    assert run(["materials", "--presets", tmp_path]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert list(tmp_path.iterdir()) == []


# ----------------------------------------------------------------------------- errors
def _corrupt_basis(folder):
    path = folder / "corrupt_basis.json"
    data = json.loads(shipped_basis_path().read_text())
    data["curves"][2][5] += 1e-3  # numbers no longer match the content hash
    path.write_text(json.dumps(data))
    return path


def _truncated_basis(folder):
    path = folder / "truncated_basis.json"
    text = shipped_basis_path().read_text()
    path.write_text(text[: len(text) // 2])
    return path


ERROR_CASES = {
    "size_1": lambda d: ["build", "--size", 1],
    "order_1": lambda d: ["build", "--size", 8, "--order", 1],
    "negative_eta": lambda d: ["coeffs", "--eta", 1, -2, 1, "--kappa", 1, 1, 1],
    "coeffs_nothing": lambda d: ["coeffs"],
    "unknown_option": lambda d: ["build", "--bogus"],
    "no_command": lambda d: [],
    "kappa_without_eta": lambda d: ["coeffs", "--kappa", 1, 1, 1],
    "mixed_material": lambda d: ["coeffs", "--eta", 1, 1, 1, "--kappa", 1, 1, 1, "--reflectivity", 0.5, 0.5, 0.5],
    "nan_eta": lambda d: ["coeffs", "--eta", "nan", 1, 1, "--kappa", 1, 1, 1],
    "size_not_int": lambda d: ["build", "--size", "big"],
    "two_numbers": lambda d: ["coeffs", "--eta", 1, 2, "--kappa", 1, 1, 1],
    "reflectivity_one": lambda d: ["coeffs", "--reflectivity", 1, 0.5, 0.5, "--edge-tint", 0.5, 0.5, 0.5],
    "missing_basis_build": lambda d: ["build", "--size", 8, "--basis", "/nonexistent/basis.json"],
    "missing_basis_coeffs": lambda d: ["coeffs", "--eta", *GOLD[0], "--kappa", *GOLD[1], "--basis", "/nonexistent"],
    "corrupt_basis": lambda d: ["build", "--size", 8, "--basis", _corrupt_basis(d)],
    "truncated_basis": lambda d: ["coeffs", "--eta", *GOLD[0], "--kappa", *GOLD[1], "--basis", _truncated_basis(d)],
}


@pytest.mark.parametrize("case", sorted(ERROR_CASES))
def test_errors_in_process(tmp_path, capsys, case):
    """Bad arguments/inputs: status 2, stderr exactly one line starting with 'fresnel-lut', no Traceback, nothing in --out."""
    argv = ERROR_CASES[case](tmp_path)
    out = tmp_path / "out"
    if argv and argv[0] == "build":
        argv = argv + ["--out", out]
    assert run(argv) == 2
    captured = capsys.readouterr()
    assert_one_line_error(captured.err)
    assert captured.out == ""
    assert not out.exists() or list(out.iterdir()) == []


@pytest.mark.parametrize(
    "case",
    [
        "size_1",
        "negative_eta",
        "coeffs_nothing",
        "unknown_option",
        "kappa_without_eta",
        "missing_basis_build",
        "corrupt_basis",
    ],
)
def test_errors_via_subprocess(tmp_path, case):
    """Same errors through `python -m fresnel_lut.cli`: exit status 2, one stderr line 'fresnel-lut…', no Traceback, --out untouched."""
    argv = ERROR_CASES[case](tmp_path)
    out = tmp_path / "out"
    if argv and argv[0] == "build":
        argv = argv + ["--out", out]
    result = run_subprocess(argv, cwd=tmp_path)
    assert result.returncode == 2
    assert_one_line_error(result.stderr)
    assert not out.exists() or list(out.iterdir()) == []


def test_out_is_a_file(tmp_path, capsys):
    """--out naming an existing regular file: status 2, one-line error, the file unchanged."""
    blocker = tmp_path / "blocker"
    blocker.write_bytes(b"keep me")
    assert run(["build", "--size", 4, "--out", blocker]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert blocker.read_bytes() == b"keep me"


# ----------------------------------------------------------------------------- Ctrl-C atomicity
@pytest.fixture
def previous(tmp_path):
    """A folder holding a previous size-8 build: (folder, {name: bytes})."""
    out = tmp_path / "luts"
    assert run(["build", "--size", 8, "--out", out]) == 0
    return out, {name: (out / name).read_bytes() for name in DEFAULT_BUILD_FILES}


def _assert_untouched(out, before):
    assert sorted(p.name for p in out.iterdir()) == sorted(before), "temporary files left behind"
    for name, data in before.items():
        assert (out / name).read_bytes() == data, f"{name} changed"


def test_interrupt_during_exr_write(previous, monkeypatch, capsys):
    """KeyboardInterrupt inside the 2nd OpenEXR write of a new build: main returns 130, old LUTs byte-identical, no .tmp left."""
    out, before = previous

    def partial_then_interrupt(image, filename):
        Path(filename).write_bytes(b"partial")
        raise KeyboardInterrupt

    fail_on_call(monkeypatch, exr.OpenEXR.File, "write", 2, partial_then_interrupt)
    assert run(["build", "--size", 12, "--out", out]) == 130
    assert "interrupted" in capsys.readouterr().err
    _assert_untouched(out, before)


def test_interrupt_during_integration(tmp_path, monkeypatch, capsys):
    """KeyboardInterrupt while integrating: main returns 130, no Traceback, the --out folder is not created."""

    def build_table(*args, **kwargs):
        raise KeyboardInterrupt

    monkeypatch.setattr(tables, "build_table", build_table)
    assert run(["build", "--size", 8, "--out", tmp_path / "new"]) == 130
    assert "Traceback" not in capsys.readouterr().err
    assert not (tmp_path / "new").exists()


def _interrupt_replace_at(monkeypatch, call):
    def interrupt(source, destination):
        raise KeyboardInterrupt

    fail_on_call(monkeypatch, os, "replace", call, interrupt)


@pytest.mark.parametrize("call", [1, 2], ids=["at the first rename", "between the renames"])
def test_interrupt_during_the_renames(previous, monkeypatch, capsys, call):
    """KeyboardInterrupt at the 1st or 2nd os.replace: main returns 130 and, as the CLI promises, both old LUTs
    stay byte-identical, no .tmp left."""
    out, before = previous
    _interrupt_replace_at(monkeypatch, call)
    assert run(["build", "--size", 12, "--out", out]) == 130
    capsys.readouterr()
    _assert_untouched(out, before)


# ----------------------------------------------------------------------------- progress
def test_progress_silent_for_quick_work():
    """Progress prints nothing before its delay has passed (documented: nothing for work under `delay` seconds)."""
    stream = io.StringIO()
    progress = Progress("work", "items", delay=3600.0, stream=stream)
    progress(5, 10)
    progress(10, 10)
    progress.close()
    assert stream.getvalue() == ""


def test_progress_reports_on_non_tty():
    """With delay 0 on a non-terminal stream, Progress writes whole lines 'label: 50.0% (5/10 unit)' and the final 100% line."""
    stream = io.StringIO()
    progress = Progress("work", "items", delay=0.0, interval=3600.0, stream=stream)
    progress(5, 10)
    progress(7, 10)  # within the interval: suppressed
    progress(10, 10)  # final: always shown
    progress.close()
    lines = stream.getvalue().splitlines()
    assert len(lines) == 2 and "\r" not in stream.getvalue()
    assert lines[0].startswith("work:") and "50.0%" in lines[0] and "(5/10 items)" in lines[0]
    assert "100.0%" in lines[1] and "left" not in lines[1]


def test_progress_estimates_the_time_left(monkeypatch):
    """Issue 36 item 14: a long fit (``build --ltc --ltc-size 1024``, hours) says how long it has left at its rate."""
    import fresnel_lut.progress as progress_module

    clock = iter([100.0, 130.0])  # made at 100 s, a quarter done at 130 s: 90 s to go
    monkeypatch.setattr(progress_module.time, "perf_counter", lambda: next(clock))
    stream = io.StringIO()
    Progress("fitting", "rows", delay=0.0, stream=stream)(256, 1024)
    assert stream.getvalue() == "fitting:  25.0% (256/1024 rows) 30.0s, about 1.5 min left\n"


def test_an_error_is_one_line_beside_the_progress_a_loaded_machine_prints(monkeypatch):
    """A small build that runs past a second on a loaded machine reports its progress before it fails (CI, 2026-12:
    ``build --ltc`` then a refused ``build``): assert_one_line_error leaves out exactly what Progress writes, with and
    without a total and a unit, and still refuses a second line of error or a traceback."""
    import fresnel_lut.progress as progress_module
    from tests.conftest import PROGRESS_LINE

    stream = io.StringIO()
    for total, unit in ((20, "rows"), (None, "texels"), (4, "")):
        clock = iter([0.0, 2.5])  # made, then called 2.5 s later: past its one-second delay
        monkeypatch.setattr(progress_module.time, "perf_counter", lambda clock=clock: next(clock))
        Progress("fitting 6x6 LTC texels (two fits, then the choice)", unit, stream=stream)(1, total)
    written = stream.getvalue().splitlines()
    assert len(written) == 3 and all(PROGRESS_LINE.match(line) for line in written), written
    error = "fresnel-lut: error: ggx_ltc.exr was fitted for height-correlated G2 and this build is separable"
    assert_one_line_error("\n".join([*written, error]) + "\n")
    assert not PROGRESS_LINE.match(error)
    for bad in ([*written, error, error], [*written, "Traceback (most recent call last):", error]):
        with pytest.raises(AssertionError):
            assert_one_line_error("\n".join(bad))


@pytest.mark.parametrize("target", ["/dev/null", "folder"])
def test_basis_refuses_a_device_or_folder_before_training(target, tmp_path, monkeypatch, capsys):
    """basis --out /dev/null used to fail after the whole training pass."""
    monkeypatch.setattr(cli, "build_basis", lambda **keywords: pytest.fail("training started"))
    out = target if target.startswith("/") else tmp_path
    assert run(["basis", "--out", out]) == 2
    assert_one_line_error(capsys.readouterr().err)


@pytest.mark.parametrize(
    "argv, words",
    [
        (["coeffs", "--material", "Gold", "--fit", "least-squares"], "--fit goes with --model"),
        (
            ["coeffs", "--eta", 1, 1, 1, "--kappa", 1, 1, 1, "--f82", 1, 1, 1, "--exponent", 3],
            "--exponent, --f82 go with",
        ),
        (["coeffs", "--reflectivity", 0.5, 0.5, 0.5, "--edge-tint", 0, 0, 0, "--tint", 1, 1, 1], "--tint goes with"),
        (["build", "--size", "-1e-9"], "invalid int value: '-1e-9'"),
        (["coeffs", "--eta", "-inf", 1, 1, "--kappa", 0, 0, 0], "eta must be in"),
        (["coeffs", "--eta", "-1e-9", 1, 1, "--kappa", 0, 0, 0], "eta must be in"),
    ],
)
def test_options_that_do_not_apply_or_negative_values(argv, words, capsys):
    """Options the command would ignore are refused, and -1e-9 or -inf reach the range check instead of
    being taken for options ("expected one argument")."""
    assert run(argv) == 2
    error = capsys.readouterr().err
    assert_one_line_error(error)
    assert words in error


def test_list_materials(capsys):
    assert run(["coeffs", "--list-materials"]) == 0
    listing = capsys.readouterr().out
    assert "Gold" in listing and "Glass BK7" in listing and listing.count("\n") >= 30


def test_build_visibility_is_recorded_and_changes_the_table(tmp_path, capsys):
    """build --visibility separable writes tables whose header convention names the form, below the default
    height-correlated ones (the default build is unchanged: the shipped files rebuild byte for byte)."""
    assert run(["build", "--size", 8, "--visibility", "separable", "--out", tmp_path / "sep"]) == 0
    assert run(["build", "--size", 8, "--out", tmp_path / "hc"]) == 0
    separable, header = read_lut(tmp_path / "sep" / "ggx_schlick_rgba.exr")
    correlated, default_header = read_lut(tmp_path / "hc" / "ggx_schlick_rgba.exr")
    assert "separable Smith G2 = G1(omega_o) * G1(omega_i)" in header["convention"]
    assert default_header["convention"] == PIXEL_CONVENTION and "height-correlated" in PIXEL_CONVENTION
    assert np.all(separable.sum(axis=-1) <= correlated.sum(axis=-1) + 1e-6)
    assert run(["build", "--visibility", "kelemen", "--out", tmp_path / "x"]) == 2
    assert_one_line_error(capsys.readouterr().err)


def test_build_ltc_writes_the_area_light_table_with_its_set(tmp_path, capsys):
    """``build --ltc`` adds ggx_ltc (its size from ``--ltc-size``, its convention and lobe error in the header) to
    the set, and the generated includes address it at that size; a build without ``--ltc`` keeps it and addresses it
    (issue 36 item 7: ``view`` and the area-light include need it), and refuses one of another visibility."""
    assert run(["build", "--size", "8", "--ltc", "--ltc-size", "6", "--out", tmp_path]) == 0
    table, header = read_lut(tmp_path / "ggx_ltc.exr")
    assert table.shape == (6, 6, 4) and np.all(np.isfinite(table))
    assert header["channels"] == "m00,m20,m02,m22" and "sqrt(1 - mu_o) = j / (size - 1)" in header["convention"]
    assert float(header["ltc_lobe_error_max"]) < 1.0
    assert "const float FRESNEL_LTC_SIZE = 6.0;" in (tmp_path / "fresnel_basis.glsl").read_text()
    ltc = (tmp_path / "ggx_ltc.exr").read_bytes()
    assert run(["build", "--size", "8", "--out", tmp_path]) == 0
    assert (tmp_path / "ggx_ltc.exr").read_bytes() == ltc
    assert "const float FRESNEL_LTC_SIZE = 6.0;" in (tmp_path / "fresnel_basis.glsl").read_text()
    assert run(["build", "--size", "8", "--visibility", "separable", "--out", tmp_path]) == 2
    error = capsys.readouterr().err
    assert_one_line_error(error)
    assert "fitted for height-correlated G2 and this build is separable: add --ltc" in error
    assert (tmp_path / "ggx_ltc.exr").read_bytes() == ltc


@pytest.mark.parametrize(
    "argv, message",
    [
        (["--ltc-size", "8"], "--ltc-size goes with --ltc"),
        (["--ltc", "--model", "f82"], "--ltc goes with the default build"),
        (["--ltc", "--ltc-size", "1"], "--ltc-size"),
    ],
)
def test_build_ltc_errors_write_nothing(argv, message, tmp_path, capsys):
    assert run(["build", "--size", "8", "--out", tmp_path / "out", *argv]) == 2
    err = capsys.readouterr().err
    assert_one_line_error(err)
    assert message in err
    assert not (tmp_path / "out").exists() or not any((tmp_path / "out").iterdir())
