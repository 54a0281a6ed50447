"""The engines' Hammersley Monte-Carlo LUT estimator (preintegrate.estimators) and report study 1
(fresnel_lut.report.lut_error).

References: (1) the base-2 radical inverse written digit by digit with exact fractions; (2) a literal,
one-sample-at-a-time transcription of Karis 2013's ``IntegrateBRDF`` (3-vectors, ``ImportanceSampleGGX``'s
cos θ formula, reflect, N·L test) with the tan-form G2 of tests/references/integration.py, and the same loop
with Heitz 2018's VNDF weight; (3) the deterministic quadrature table (preintegrate.lut.build_table at
order 64, itself checked against Monte Carlo and scipy cubature in test_quadrature.py).
"""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest

from basis.validation import ParameterError
from fresnel_lut.report.lut_error import lut_error_table_markdown, lut_error_vs_time, plot_lut_error
from preintegrate.channels import basis_channels, combine, schlick_channels
from preintegrate.estimators import hammersley_points, radical_inverse_base2
from preintegrate.ggx import g1, sample_vndf
from preintegrate.lut import LutGrid, build_table
from preintegrate.quadrature import QuadratureOrder
from tests.references.integration import g2_reference

SIX = combine(basis_channels(), schlick_channels())


@pytest.fixture(scope="module")
def quadrature_16():
    """16 × 16 table of the six channels at order 64 (converged to ~1e-9 at this size)."""
    return build_table(SIX, LutGrid.centred(16), order=QuadratureOrder.uniform(64))


def _errors(table, reference):
    difference = np.abs(table - reference)
    return difference.max(), np.sqrt(np.mean(difference**2))


# ----------------------------------------------------------------------------- (1) the point set
def test_radical_inverse_first_values_exact():
    """Φ₂(0 … 8) = 0, 1/2, 1/4, 3/4, 1/8, 5/8, 3/8, 7/8, 1/16 exactly; Φ₂(2³¹) = 2⁻³², Φ₂(2³² − 1) = 1 − 2⁻³²."""
    expected = [0.0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875, 0.0625]
    assert radical_inverse_base2(np.arange(9)).tolist() == expected
    assert radical_inverse_base2(2**31) == 2.0**-32
    assert radical_inverse_base2(2**32 - 1) == 1.0 - 2.0**-32


def test_radical_inverse_matches_digit_expansion():
    """Φ₂(i) = Σ d_k 2^−(k+1) for the binary digits d_k of i, exact, for i < 4096 and a few large i."""
    indices = list(range(4096)) + [123_456_789, 2**32 - 2, 0xDEADBEEF]

    def digits(i):
        value, scale = Fraction(0), Fraction(1, 2)
        while i:
            value += scale * (i & 1)
            i >>= 1
            scale /= 2
        return float(value)

    assert radical_inverse_base2(np.array(indices)).tolist() == [digits(i) for i in indices]


def test_hammersley_points():
    """N = 4: (i/N) = 0, 1/4, 1/2, 3/4 and Φ₂ = 0, 1/2, 1/4, 3/4; N = 1024 fills every 1/N stratum once in both."""
    fraction, radical = hammersley_points(4)
    assert fraction.tolist() == [0.0, 0.25, 0.5, 0.75]
    assert radical.tolist() == [0.0, 0.5, 0.25, 0.75]
    fraction, radical = hammersley_points(1024)
    assert sorted(radical.tolist()) == fraction.tolist()


# ----------------------------------------------------------------------------- (2) literal IntegrateBRDF
def _literal_integrate_brdf(mu_o, alpha, samples, sampling):
    """Karis 2013 IntegrateBRDF, one sample at a time (Schlick channels: A = ∫(1 − Fc), B = ∫Fc)."""
    view = np.array([np.sqrt(1.0 - mu_o * mu_o), 0.0, mu_o])
    scale = bias = 0.0
    for i in range(samples):
        xi = (i / samples, int(format(i, "032b")[::-1], 2) / 2.0**32)  # Hammersley(i, N)
        if sampling == "ndf":  # ImportanceSampleGGX(Xi, Roughness, N) with a = α
            phi = 2.0 * np.pi * xi[0]
            cos_theta = np.sqrt((1.0 - xi[1]) / (1.0 + (alpha * alpha - 1.0) * xi[1]))
            sin_theta = np.sqrt(1.0 - cos_theta * cos_theta)
            h = np.array([sin_theta * np.cos(phi), sin_theta * np.sin(phi), cos_theta])
        else:
            h = sample_vndf(view, alpha, np.array(xi[1]), np.array(xi[0]))
        light = 2.0 * np.dot(view, h) * h - view
        n_dot_l, n_dot_h, v_dot_h = light[2], h[2], np.dot(view, h)
        if n_dot_l > 0.0:
            g = float(g2_reference(mu_o, n_dot_l, alpha))
            weight = g * v_dot_h / (n_dot_h * mu_o) if sampling == "ndf" else g / float(g1(mu_o, alpha))
            fc = (1.0 - v_dot_h) ** 5
            scale += (1.0 - fc) * weight
            bias += fc * weight
    return np.array([scale, bias]) / samples


@pytest.mark.parametrize("sampling", ["ndf", "vndf"])
def test_matches_literal_integrate_brdf(sampling):
    """3 × 3 Schlick table with 64 points equals the sample-by-sample IntegrateBRDF loop to 1e-13."""
    grid = LutGrid.centred(3)
    table = build_table(schlick_channels(), grid, method="hammersley", samples=64, sampling=sampling, max_samples=50)
    mu_axis, roughness_axis = grid.mu_o, grid.roughness
    for j, roughness in enumerate(roughness_axis):
        for i, mu_o in enumerate(mu_axis):
            expected = _literal_integrate_brdf(mu_o, roughness**2, 64, sampling)
            np.testing.assert_allclose(table[j, i], expected, rtol=0, atol=1e-13)


def test_chunking_does_not_change_the_result():
    """Chunks of 7 texel-sample pairs (splitting the samples of a texel) give the same table as one chunk, to 1e-14."""
    whole = build_table(SIX, LutGrid.centred(4, 5), method="hammersley", samples=32)
    chunked = build_table(SIX, LutGrid.centred(4, 5), method="hammersley", samples=32, max_samples=7)
    assert whole.shape == (5, 4, 6)
    np.testing.assert_allclose(chunked, whole, rtol=0, atol=1e-14)


# ----------------------------------------------------------------------------- (3) against the quadrature
def test_ndf_converges_to_quadrature(quadrature_16):
    """NDF sampling, 16 × 16, six channels: error falls from 64 to 4096 spp; max at 4096 spp < 1e-2.

    Measured: max 5.6e-2 at 64 spp, 4.5e-3 at 4096 spp.
    """
    max_64, rms_64 = _errors(build_table(SIX, LutGrid.centred(16), method="hammersley", samples=64), quadrature_16)
    max_4096, rms_4096 = _errors(
        build_table(SIX, LutGrid.centred(16), method="hammersley", samples=4096), quadrature_16
    )
    assert max_4096 < max_64 and rms_4096 < rms_64
    assert max_4096 < 1e-2, max_4096


def test_vndf_converges_to_quadrature(quadrature_16):
    """VNDF sampling, 16 × 16, six channels: max at 4096 spp < 1e-3 (measured 3.1e-4; 1.6e-2 at 64)."""
    max_64, rms_64 = _errors(
        build_table(SIX, LutGrid.centred(16), method="hammersley", samples=64, sampling="vndf"), quadrature_16
    )
    max_4096, rms_4096 = _errors(
        build_table(SIX, LutGrid.centred(16), method="hammersley", samples=4096, sampling="vndf"), quadrature_16
    )
    assert max_4096 < max_64 and rms_4096 < rms_64
    assert max_4096 < 1e-3, max_4096


@pytest.mark.parametrize("samples", [64, 1024])
def test_vndf_more_accurate_than_ndf(quadrature_16, samples):
    """Same table, same points: VNDF's max and RMS errors are below NDF's (measured ≥ 3× lower at 64 and 1024 spp)."""
    ndf = _errors(
        build_table(SIX, LutGrid.centred(16), method="hammersley", samples=samples, sampling="ndf"), quadrature_16
    )
    vndf = _errors(
        build_table(SIX, LutGrid.centred(16), method="hammersley", samples=samples, sampling="vndf"), quadrature_16
    )
    assert vndf[0] < ndf[0] and vndf[1] < ndf[1], (ndf, vndf)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"grid": 1},
        {"grid": 2.5},
        {"grid": 8, "height": 0},
        {"grid": LutGrid.centred(8), "samples": 0},
        {"grid": LutGrid.centred(8), "samples": True},
        {"grid": LutGrid.centred(8), "sampling": "uniform"},
        {"grid": LutGrid.centred(8), "max_samples": 0},
        {"grid": LutGrid.centred(8), "progress": 3},
    ],
)
def test_invalid_input(kwargs):
    with pytest.raises(ParameterError):
        build_table(SIX, method="hammersley", **kwargs)


def test_invalid_channels_and_indices():
    with pytest.raises(ParameterError, match="channels"):
        build_table(lambda x: x, LutGrid.centred(8), method="hammersley")
    with pytest.raises(ParameterError, match="indices"):
        radical_inverse_base2([1.5])
    with pytest.raises(ParameterError, match="indices"):
        radical_inverse_base2([-1])


def test_progress_reports_every_texel():
    calls = []
    build_table(
        SIX,
        LutGrid.centred(4),
        method="hammersley",
        samples=16,
        max_samples=64,
        progress=lambda done, total: calls.append((done, total)),
    )
    assert calls == [(4, 16), (8, 16), (12, 16), (16, 16)]


# ----------------------------------------------------------------------------- study 1
@pytest.fixture(scope="module")
def quick_study():
    return lut_error_vs_time(quick=True, repeats=2)


def test_quick_study_rows(quick_study):
    """Quick mode, best of 2: all methods and the default schedule present, seconds and errors finite and > 0, equal-time ratios use the bracketing settings of one quadrature family."""
    rows = quick_study["rows"]
    assert quick_study["size"] == 32 and len(quick_study["channels"]) == 6 and quick_study["repeats"] == 2
    assert {row["method"] for row in rows} == {"quadrature-schedule", "quadrature", "hammersley-ndf", "hammersley-vndf"}
    for row in rows:
        for key in ("seconds", "max_abs_error", "rms_abs_error"):
            assert np.isfinite(row[key]) and row[key] > 0.0, row
        assert row["rms_abs_error"] <= row["max_abs_error"]
    assert np.isfinite(quick_study["reference_seconds"]) and quick_study["reference_seconds"] > 0.0
    quadrature = [row for row in rows if row["method"] in ("quadrature", "quadrature-schedule")]
    assert any(row["method"] == "quadrature-schedule" and row["setting"] == 1.0 for row in quadrature)
    assert len(quick_study["equal_time"]) == len(rows) - len(quadrature)
    for entry in quick_study["equal_time"]:
        if entry["ratio"] is None:
            continue
        family = sorted(
            (q for q in quadrature if q["method"] == entry["quadrature_method"]), key=lambda q: q["seconds"]
        )
        slower = [q for q in family if q["seconds"] >= entry["seconds"]]
        faster = [q for q in family if q["seconds"] <= entry["seconds"]]
        assert faster
        if not slower:  # past the family's slowest setting: its best error, a lower bound of the ratio
            assert entry["quadrature_max_abs_error"] == min(q["max_abs_error"] for q in family)
            continue
        # the interpolated quadrature error lies between those of the bracketing orders (log-log interpolation)
        low, high = slower[0]["max_abs_error"], faster[-1]["max_abs_error"]
        assert min(low, high) * (1 - 1e-12) <= entry["quadrature_max_abs_error"] <= max(low, high) * (1 + 1e-12)
        assert entry["ratio"] == pytest.approx(entry["max_abs_error"] / entry["quadrature_max_abs_error"])
    table = lut_error_table_markdown(quick_study)
    assert table.count("\n| ") == len(rows) + 1  # header + one line per row (the separator starts with "|---")


def test_quick_study_plot(quick_study, tmp_path):
    pytest.importorskip("matplotlib")
    path = plot_lut_error(quick_study, tmp_path / "lut_error.png")
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert path.stat().st_size > 10_000
    assert sorted(p.name for p in tmp_path.iterdir()) == ["lut_error.png"]  # no temporary file left


def test_study_invalid_input():
    with pytest.raises(ParameterError, match="orders"):
        lut_error_vs_time(size=8, orders=(8, 96), reference_order=96)
    with pytest.raises(ParameterError, match="samples"):
        lut_error_vs_time(size=8, samples=())
    with pytest.raises(ParameterError, match="repeats"):
        lut_error_vs_time(size=8, repeats=0)
