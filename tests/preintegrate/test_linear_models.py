"""The linear models' exact split sum (issue 39): the Schlick table's R, G and A (scale, bias and the dip
∫ μ (1 − μ)⁶) hold every model linear in 1 − (1 − μ)⁵, (1 − μ)⁵ and μ (1 − μ)⁶ — Schlick with F0 and F90, Hoffman
2019's F82, Adobe's F82 tint (OpenPBR ``specular_color``), Hoffman 2023's generalised Adobe with p = 5 — exactly.

Independent checks: F̄ of random materials of each model from the shipped table's texels and the model registry's
weights, against an adaptive cubature of the model's own curve (tests/references/integration.py: no channel, no
weight, no quadrature of the library), within 1e-6; F_avg against the closed form r0 + (r90 − r0)/21 − a/126.
"""

import numpy as np
import pytest

from basis.models import fresnel_model
from handoff.exr import read_lut
from handoff.shipped import SCHLICK_LUT, shipped_lut
from preintegrate.channels import schlick_table_weights
from preintegrate.multiple_scattering import linear_model_albedo, schlick_table_averages
from tests.conftest import linear_model_materials
from tests.references.integration import reference_albedo_adaptive

TABLE = read_lut(shipped_lut(SCHLICK_LUT))[0]  # (128, 128, 4)
SIZE = TABLE.shape[0]
#: Texels (column i, row j) over the table: both ends of both axes (μo = 0 and 1; r = 1 and the first row above
#: the mirror, r = 1/127, α = 6.2e-5) and texels between. Not μo = 0 with α < 0.016: the cubature reads μo = 0 as
#: 1e-9, where a lobe that narrow already differs from μo = 0 by 3e-6 (E = 0.999996), and at 1e-12 its own
#: error at grazing is 4e-8 per channel; the quadrature's μo → 0 limit is tested in tests/fresnel_lut/test_cli.py.
TEXELS = [(i, j) for i in (57, 88, 127) for j in (1, 6, 40, 90, 127)] + [(0, 40), (0, 90), (0, 127)]
TEXELS += [(30, 1), (30, 40), (30, 90), (30, 127)]


def _texel(i, j):
    return (i / (SIZE - 1)) ** 2, (j / (SIZE - 1)) ** 2  # (μo, α): √μo = i/(W − 1), α = r², r = j/(H − 1)


def test_the_table_holds_the_linear_models_split_sums_to_an_independent_cubature():
    """Max |F̄_table − F̄_cubature| over 22 texels × 24 materials ≤ 1e-6 (float32 storage times weights up to 17.6,
    and the quadrature's 5e-8 per channel; measured 5.4e-8); α < 0.05 through the half-vector cubature, μo = 0 as
    μo = 1e-9 (tolerances of tests/fresnel_lut/test_cli.py there). Every texel, through the channels:
    tests/preintegrate/test_every_texel.py."""
    materials = linear_model_materials(np.random.default_rng(39), 6)
    weights = np.concatenate([schlick_table_weights(model, **parameters) for model, parameters in materials])

    def curves(x):  # (N,) → (N, materials): the models' own curves, not their channels
        x = np.asarray(x)[..., None]
        return np.concatenate([fresnel_model(m).evaluate(x, **p) for m, p in materials], axis=-1)

    worst = 0.0
    for i, j in TEXELS:
        mu_o, alpha = _texel(i, j)
        expected = reference_albedo_adaptive(curves, mu_o, alpha)
        worst = max(worst, float(np.max(np.abs(weights @ TABLE[j, i] - expected))))
    assert worst <= 1e-6, worst


def test_weights_are_the_models_channels_and_other_shapes_are_refused():
    """Each model's weights reproduce its curve from the table's own functions; an exponent other than 5 (the
    generalised models) or a dip exponent other than 6 (Lazányi) has no column in the table: None."""
    from preintegrate.channels import schlick_table_channels

    mu = np.linspace(0.0, 1.0, 101)
    functions = schlick_table_channels().functions(mu)  # (101, 4)
    for model, parameters in linear_model_materials(np.random.default_rng(7), 3):
        weights = schlick_table_weights(model, **parameters)  # (3, 4)
        expected = fresnel_model(model).evaluate(mu[:, None], **parameters)
        np.testing.assert_allclose(functions @ weights.T, expected, rtol=0, atol=1e-14)
        assert np.all(weights[..., 2] == 0.0)  # no weight on E
    assert schlick_table_weights("generalized-adobe", r0=0.5, r90=1.0, tint=0.5, exponent=4.0) is None
    assert schlick_table_weights("lazanyi", f0=0.5, a=1.0, alpha=7.0) is None
    assert schlick_table_weights("gulbrandsen", reflectivity=0.5, edge_tint=0.5) is None


def test_the_average_is_openpbrs_closed_form():
    """F_avg = 2 ∫ F μ dμ = r0 + (r90 − r0)/21 − a/126 (OpenPBR's form for the F82 family) from the averages of the
    table's functions, within 1e-15."""
    r0, r90, tint = 0.7, 0.95, 0.4
    weights = schlick_table_weights("generalized-adobe", r0=r0, r90=r90, tint=tint, exponent=5.0)
    a = -weights[3]
    assert weights @ schlick_table_averages() == pytest.approx(r0 + (r90 - r0) / 21 - a / 126, abs=1e-15)


def test_linear_model_albedo_is_the_table_read_as_a_gpu_reads_it_and_loses_no_energy_in_the_furnace():
    """At texels the API returns weights · texel; a white material (Schlick with F0 = F90 = 1) with multiple
    scattering returns 1 everywhere (the furnace), to 1e-6."""
    weights = schlick_table_weights("adobe", f0=[0.9, 0.6, 0.3], tint=[0.8, 0.7, 0.9])  # (3, 4)
    mu_o, roughness = (57 / 127) ** 2, 40 / 127
    np.testing.assert_allclose(
        linear_model_albedo(weights, mu_o, roughness, TABLE, multiple_scattering=False),
        weights @ TABLE[40, 57],
        rtol=0,
        atol=1e-12,
    )
    white = schlick_table_weights("generalized-schlick", r0=1.0, r90=1.0, exponent=5.0)
    mu, r = np.meshgrid(np.linspace(0.0, 1.0, 17), np.linspace(0.0, 1.0, 17))
    furnace = linear_model_albedo(np.broadcast_to(white, mu.shape + (1, 4)), mu, r, TABLE)
    np.testing.assert_allclose(furnace, 1.0, rtol=0, atol=1e-6)
