"""Working spaces, spectral → RGB weights and ΔE2000 (basis/colorimetry.py).

The weights are checked against colour-science's own path (``sd_to_XYZ`` → ``XYZ_to_RGB`` with a
Bradford adaptation), a computation that shares nothing with ours but the CIE tables.
"""

import colour
import numpy as np
import pytest

from basis.colorimetry import (
    WAVELENGTHS,
    WORKING_SPACES,
    delta_E_2000,
    rgb_to_Lab,
    rgb_to_rgb_matrix,
    spectral_to_rgb_weights,
    working_space,
)
from basis.validation import ParameterError

SPACES = ["ACEScg", "sRGB"]


@pytest.mark.parametrize("space", SPACES)
def test_perfect_reflector_is_white(space):
    np.testing.assert_allclose(spectral_to_rgb_weights(space).sum(axis=1), 1.0, atol=1e-15)


@pytest.mark.parametrize("space", SPACES)
def test_weights_match_colour_science_path(space):
    """A smooth reflectance through colour's sd_to_XYZ + XYZ_to_RGB, normalised by the white's RGB."""
    reflectance = 0.3 + 0.5 * np.exp(-(((WAVELENGTHS - 600.0) / 60.0) ** 2))
    definition = WORKING_SPACES[space]
    shape = colour.SpectralShape(360, 830, 5)
    illuminant = colour.SDS_ILLUMINANTS[definition.illuminant].copy().align(shape)
    cmfs = colour.MSDS_CMFS["CIE 1931 2 Degree Standard Observer"].copy().align(shape)

    def rgb(values):
        distribution = colour.SpectralDistribution(dict(zip(WAVELENGTHS, values)))
        xyz = colour.sd_to_XYZ(distribution, cmfs, illuminant, method="Integration") / 100.0
        source_white = colour.XYZ_to_xy(colour.sd_to_XYZ(colour.sd_ones(shape), cmfs, illuminant, method="Integration"))
        return colour.XYZ_to_RGB(
            xyz, definition.colourspace, illuminant=source_white, chromatic_adaptation_transform="Bradford"
        )

    expected = rgb(reflectance) / rgb(np.ones_like(reflectance))
    np.testing.assert_allclose(spectral_to_rgb_weights(space) @ reflectance, expected, rtol=1e-6)


def test_acescg_white_is_d60_adapted_to_aces_white():
    """ACEScg's white point is the ACES white (TB-2018-001), not CIE D60's chromaticity."""
    assert working_space("ACEScg").illuminant == "D60"
    np.testing.assert_allclose(working_space("ACEScg").rgb_colourspace.whitepoint, [0.32168, 0.33767])


def test_white_is_lightness_100_and_grey_neutral():
    for space in SPACES:
        lab = rgb_to_Lab([[1.0, 1.0, 1.0], [0.18, 0.18, 0.18]], space)
        np.testing.assert_allclose(lab[0], [100.0, 0.0, 0.0], atol=1e-9)
        np.testing.assert_allclose(lab[1, 1:], 0.0, atol=1e-9)


def test_delta_e_2000_published_pair():
    """Sharma, Wu, Dalal (2005) test data, pair 1: ΔE00 = 2.0425 (checked through Lab→RGB→Lab)."""
    lab_a, lab_b = np.array([50.0, 2.6772, -79.7751]), np.array([50.0, 0.0, -82.7485])
    space = WORKING_SPACES["ACEScg"].rgb_colourspace

    def to_rgb(lab):
        return colour.XYZ_to_RGB(
            colour.Lab_to_XYZ(lab, space.whitepoint),
            space,
            illuminant=space.whitepoint,
            chromatic_adaptation_transform=None,
        )

    assert delta_E_2000(to_rgb(lab_a), to_rgb(lab_b), "ACEScg") == pytest.approx(2.0425, abs=1e-4)


def test_rgb_to_rgb_round_trip_and_identity():
    # the published 4-decimal matrices of the spaces round-trip to 5e-5, not to machine precision
    np.testing.assert_allclose(
        rgb_to_rgb_matrix("ACEScg", "sRGB") @ rgb_to_rgb_matrix("sRGB", "ACEScg"), np.eye(3), atol=5e-5
    )
    np.testing.assert_allclose(rgb_to_rgb_matrix("ACEScg", "AP0") @ [1.0, 1.0, 1.0], 1.0, atol=1e-6)


def test_errors_name_the_choices():
    with pytest.raises(ParameterError, match=r"colour space must be one of .*'ACEScg'.*got 'XYZ'"):
        spectral_to_rgb_weights("XYZ")
    with pytest.raises(ParameterError, match="conversion target"):
        spectral_to_rgb_weights("AP0")
    with pytest.raises(ParameterError, match="rgb"):
        rgb_to_Lab([1.0, 2.0], "sRGB")
    with pytest.raises(ParameterError, match="rgb"):
        delta_E_2000([np.nan, 0.0, 0.0], [0.0, 0.0, 0.0], "sRGB")


def test_n_dimensional():
    rgb = np.random.default_rng(1).uniform(0.0, 1.0, (2, 3, 3))
    values = delta_E_2000(rgb, rgb[::-1], "sRGB")
    assert values.shape == (2, 3)
    np.testing.assert_allclose(values[0, 1], delta_E_2000(rgb[0, 1], rgb[1, 1], "sRGB"))


def test_delta_E_2000_components_square_sum_is_ciede2000():
    """Σ r² of the three residual components equals CIEDE2000² of colour-science's independent implementation
    (atol 1e-10 on ΔE), for random pairs far apart and close together, achromatic colours (C = 0, where the
    hue is undefined) and pairs across the hue wrap at 0°/360°."""
    from basis.colorimetry import delta_E_2000_components

    rng = np.random.default_rng(2005)
    near = rng.uniform([0.0, -100.0, -100.0], [100.0, 100.0, 100.0], (5000, 3))
    far = rng.uniform([0.0, -100.0, -100.0], [100.0, 100.0, 100.0], (5000, 3))
    first = np.concatenate([near, near, [[50.0, 0.0, 0.0], [50.0, 2.49, -0.001], [60.0, 10.0, -0.1]]])
    second = np.concatenate(
        [near + rng.normal(0.0, 2.0, near.shape), far, [[50.0, 0.0, 0.0], [50.0, -2.49, 0.001], [61.0, 10.0, 0.1]]]
    )
    components = delta_E_2000_components(first, second)
    assert components.shape == first.shape
    np.testing.assert_allclose(
        np.sqrt(np.sum(components**2, axis=-1)), colour.delta_E(first, second, method="CIE 2000"), rtol=0, atol=1e-10
    )
