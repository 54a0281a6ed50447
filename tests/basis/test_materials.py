"""What a material is (basis/materials.py): every kind gives the curve and coefficients of the function it names,
conflicting or unknown keys are refused, and a tint at 82° is not an absolute F82."""

import numpy as np
import pytest

from basis import coefficients_from_gulbrandsen, coefficients_from_nk, material_coefficients
from basis.coefficients import coefficients_from_model
from basis.fresnel import fresnel_conductor
from basis.materials import MATERIAL_KINDS, material_from_mapping
from basis.models import fresnel_model
from basis.presets import material_preset
from basis.validation import ParameterError

MU = np.linspace(0.0, 1.0, 101)


def test_each_kind_gives_its_curve_and_coefficients():
    eta, kappa = [0.18, 0.42, 1.37], [3.42, 2.35, 1.77]
    nk = material_from_mapping({"eta": eta, "kappa": kappa})
    np.testing.assert_allclose(nk.curve(MU), fresnel_conductor(MU[:, None], eta, kappa), rtol=0, atol=1e-15)
    np.testing.assert_allclose(nk.coefficients(), coefficients_from_nk(eta, kappa), rtol=0, atol=1e-15)
    rg = material_from_mapping({"reflectivity": 0.9, "edge_tint": [0.1, 0.5, 0.9]})
    np.testing.assert_allclose(
        rg.coefficients(), coefficients_from_gulbrandsen(np.full(3, 0.9), [0.1, 0.5, 0.9]), atol=1e-15
    )
    assert material_from_mapping({"preset": "gold"}).description == {"preset": "Gold"}
    np.testing.assert_array_equal(
        material_from_mapping({"preset": "Gold"}).coefficients(), material_coefficients("Gold")
    )
    f82 = material_from_mapping({"f0": [0.9, 0.7, 0.4], "f82": [0.85, 0.7, 0.5]})
    assert f82.kind == "f82" and f82.description["model"] == "f82"
    expected, _ = coefficients_from_model(
        "f82", "four-point", None, f0=np.array([0.9, 0.7, 0.4]), f82=np.array([0.85, 0.7, 0.5])
    )
    np.testing.assert_allclose(f82.coefficients(), expected, atol=1e-15)
    assert material_from_mapping({"f0": 0.04}).curve(1.0).tolist() == [0.04, 0.04, 0.04]
    assert sorted(MATERIAL_KINDS) == ["f82", "gulbrandsen", "model", "nk", "preset", "schlick"]


@pytest.mark.parametrize(
    "mapping, fragment",
    [
        ({"preset": "Gold", "eta": 1.5}, "takes only preset"),
        ({"preset": "Gold", "space": "sRGB"}, "takes only preset"),
        ({"preset": 3}, "preset must be a material's name"),
        ({"eta": 1.5}, "give one of"),
        ({"eta": 1.5, "kappa": 0.0, "f0": 0.04}, "give one of"),
        ({"f0": [0.1, 0.2]}, "f0 must be a number or 3 numbers"),
        ({"f0": True}, "f0 must be a number"),
        ({"model": "f82", "f0": 0.5, "f82": 0.4, "tint": 0.3}, "unknown"),
        ({"model": "nope"}, "model must be one of"),
        ({"eta": -1.0, "kappa": 0.0}, "eta must be in"),
        ({"reflectivity": 1.0, "edge_tint": 0.0}, "reflectivity"),
        ([1, 2], "a material must be a table"),
    ],
)
def test_conflicting_unknown_and_bad_keys_are_refused(mapping, fragment):
    with pytest.raises(ParameterError, match=fragment):
        material_from_mapping(mapping)


def test_a_tint_at_82_degrees_is_not_an_absolute_f82():
    """MaterialX's color82 and OpenPBR's specular_color are a tint on Schlick at arccos(1/7) (the adobe model);
    Hoffman 2019's F82 is the reflectance there. For measured gold (ACEScg), read as each other they miss the
    curve by 0.21 and 0.31 (max |ΔF| over θ), read rightly by 4e-4."""
    preset = material_preset("Gold")
    f0, f82 = preset["f0"], preset["f82"]
    tint = f82 / (f0 + (1.0 - f0) * (1.0 - 1.0 / 7.0) ** 5)
    mu = np.linspace(0.0, 1.0, 2001)[:, None]
    absolute = fresnel_model("f82").evaluate(mu, f0=f0, f82=f82)
    as_tint = fresnel_model("adobe").evaluate(mu, f0=f0, tint=np.clip(tint, 0.0, 1.0))
    assert np.max(np.abs(as_tint - absolute)) < 5e-4
    assert np.max(np.abs(fresnel_model("adobe").evaluate(mu, f0=f0, tint=f82) - absolute)) == pytest.approx(
        0.2116, abs=1e-3
    )
    assert np.max(
        np.abs(fresnel_model("f82").evaluate(mu, f0=f0, f82=np.clip(tint, 0.0, 1.0)) - as_tint)
    ) == pytest.approx(0.3078, abs=1e-3)
