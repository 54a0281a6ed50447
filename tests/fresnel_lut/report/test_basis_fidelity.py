"""The basis-fidelity section (issue 14): the shipped basis against the group targets on the fixed
validation draw, six terms against the same targets, and the study's numbers against direct computations.

Independent checks: max |ΔF| recomputed through the engine API (``coefficients_from_nk``, the four-point
fit) and the exact Fresnel equations; max |ΔF̄| of the Figure 2 material integrated directly
(:func:`preintegrate.quadrature.directional_albedo` of the error curve) instead of through texel weights.
"""

import numpy as np
import pytest

from basis import coefficients_from_nk
from basis.angles import cos_theta
from basis.eigenbasis import default_basis
from basis.fresnel import fresnel_conductor
from basis.gulbrandsen import gulbrandsen_to_nk
from basis.training import FIGURE_2, build_basis, validation_groups
from fresnel_lut.report.basis_fidelity import TARGETS, fidelity_markdown, fidelity_study, group_errors, plot_fidelity
from preintegrate.ggx import roughness_to_alpha
from preintegrate.lut import LutGrid
from preintegrate.quadrature import directional_albedo, texel_weights

THETA = np.linspace(0.0, 0.5 * np.pi, 2049)
SIZE = 64


@pytest.fixture(scope="module")
def weights():
    mu_o, roughness = LutGrid.centred(SIZE).mu_o, LutGrid.centred(SIZE).roughness
    return texel_weights(THETA, mu_o[None, :], roughness_to_alpha(roughness)[:, None]).reshape(-1, THETA.size)


@pytest.fixture(scope="module")
def shipped(weights):
    return group_errors(default_basis(), validation_groups(), THETA, weights, fits=("four-point",))["four-point"]


def test_curve_errors_agree_with_the_engine_api(shipped):
    eta, kappa = gulbrandsen_to_nk(np.array(FIGURE_2["reflectivity"]), np.array(FIGURE_2["edge_tint"]))
    fitted = coefficients_from_nk(eta, kappa) @ default_basis().evaluate(THETA).T
    exact = fresnel_conductor(cos_theta(THETA)[None, :], eta[:, None], kappa[:, None])
    assert np.max(np.abs(fitted - exact)) == pytest.approx(shipped["figure 2"]["curve"], rel=1e-9)


def test_preintegrated_error_agrees_with_direct_integration(shipped):
    """F̄ of the Figure 2 error curve, integrated directly on the 64 × 64 texel centres."""
    basis = default_basis()
    eta, kappa = gulbrandsen_to_nk(np.array(FIGURE_2["reflectivity"]), np.array(FIGURE_2["edge_tint"]))
    coefficients = coefficients_from_nk(eta, kappa)  # (3, 4)

    def error(x):
        return basis.evaluate_mu(np.clip(x, 0, 1)) @ coefficients.T - fresnel_conductor(x[..., None], eta, kappa)

    mu_o, roughness = LutGrid.centred(SIZE).mu_o, LutGrid.centred(SIZE).roughness
    direct = directional_albedo(error, mu_o[None, :], roughness_to_alpha(roughness)[:, None])
    assert np.max(np.abs(direct)) == pytest.approx(shipped["figure 2"]["preintegrated"], abs=2e-6)


def test_what_the_shipped_basis_holds(shipped):
    """The four-term default, four-point coefficients, on the fixed validation draw (report/fidelity.md)."""
    assert shipped["dielectrics"]["curve"] <= TARGETS["dielectrics"][1]  # 0.0030: the one target it meets
    assert shipped["metals"]["curve"] <= 0.014  # measured 0.0132
    assert shipped["measured metals"]["curve"] <= 0.006  # measured 0.0057
    assert shipped["figure 2"]["preintegrated"] <= 0.019  # measured 0.0185
    assert shipped["gulbrandsen"]["curve"] <= 0.30  # measured 0.29: r near 0.9 with a low g (a Brewster dip)


@pytest.mark.xfail(
    strict=True,
    reason="issue 14: out of reach for four terms: a basis trained on these very curves "
    "ends 1.54x above the targets at once (report/fidelity.md, bounds)",
)
@pytest.mark.parametrize("group", ["figure 2", "measured metals", "metals"])
def test_the_targets_the_four_term_default_misses(shipped, group):
    measure, bound = TARGETS[group]
    assert shipped[group][measure] <= bound


def test_six_terms_meet_every_target(weights):
    """The default domain's build with six terms (two RGBA fetches) meets all four targets (measured: Figure 2
    0.0039 in F̄, measured metals 0.0023, dielectrics 0.0025, metals 0.0034 in F)."""
    errors = group_errors(build_basis(n_terms=6), validation_groups(), THETA, weights, fits=("four-point",))[
        "four-point"
    ]
    for group, (measure, bound) in TARGETS.items():
        assert errors[group][measure] <= bound, group


@pytest.fixture(scope="module")
def quick_study():
    return fidelity_study(quick=True)


def test_a_bound_is_what_its_basis_measures(quick_study):
    """A bound's worst error / tolerance, measured on the study's grid (513 θ), agrees within 5 % with what the
    refinement saw on its coarser grid (257 θ; a finer grid finds slightly higher peaks), and it is well
    below the shipped basis' own ratio, from which it starts: the optimiser improved on its start."""
    bound = quick_study["bounds"]["bound: issue targets"]
    assert bound["trained_ratio"] <= bound["worst_ratio"] <= 1.05 * bound["trained_ratio"]
    shipped = max(
        quick_study["errors"]["shipped"]["four-point"][group][measure] / bound["tolerances"][group]
        for group, (measure, _) in TARGETS.items()
    )
    assert bound["worst_ratio"] < 0.6 * shipped


def test_quick_study_writes_its_section(tmp_path, quick_study):
    result = quick_study
    markdown = fidelity_markdown(result)
    for name in ("notebook-style", "shipped", "refined: issue targets", "bound: issue targets", "| 6 |"):
        assert name in markdown
    scene = result["terms"]["scene"]
    assert max(scene[6].values()) < 0.2 * max(scene[4].values())  # more terms: the showcase scene held far better
    assert plot_fidelity(result, tmp_path / "fidelity.png").stat().st_size > 10_000


@pytest.mark.parametrize("call", [1, 2], ids=["first rename", "second rename"])
def test_the_fidelity_report_is_written_whole_or_not_at_all(quick_study, tmp_path, monkeypatch, call):
    """Issue 26 item 14: on a full disk `report --fidelity --quick` left fidelity.md without its plot; the Markdown and
    the plot are one transaction now (a failure at either rename leaves the folder as it was)."""
    import os

    from fresnel_lut.report import basis_fidelity
    from tests.conftest import fail_on_call

    monkeypatch.setattr(basis_fidelity, "fidelity_study", lambda quick=False, progress=None: quick_study)

    def disk_full(source, target):
        raise OSError(28, "No space left on device")

    fail_on_call(monkeypatch, os, "replace", call, disk_full)
    out = tmp_path / "report"
    with pytest.raises(OSError, match="No space left"):
        basis_fidelity.write_fidelity_report(out, quick=True)
    assert not out.exists() or list(out.iterdir()) == []
