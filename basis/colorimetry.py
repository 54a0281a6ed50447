"""Working colour spaces, spectral → RGB weights and CIE ΔE2000 for Fresnel curves.

Public objects: ``WorkingSpace``, ``WORKING_SPACES``, ``working_space``, ``WAVELENGTHS``,
``spectral_to_rgb_weights``, ``rgb_to_Lab``, ``delta_E_2000``, ``delta_E_2000_Lab``,
``delta_E_2000_components``, ``rgb_to_rgb_matrix``.

Hoffman's procedure for RGB parameters from spectral data (Hoffman 2020, "Computing RGB Parameter
Values From Spectral IOR Data"): the spectral reflectance at an angle is lit by the working space's
reference-white illuminant, integrated against the CIE 1931 2° observer, chromatically adapted to the
space's white point where the two differ (ACEScg: CIE D60 → the ACES white, TB-2018-001; Bradford),
converted by the space's matrix, and normalised so that a perfect reflector is exactly (1, 1, 1) (his
"extra normalization step to account for rounding errors in the RGB matrix"). Every step is linear,
so the whole procedure is one (3, N) matrix of weights over the wavelength samples.

ΔE2000 compares two RGB colours of the same space: RGB → XYZ with the space's matrix → CIE L*a*b*
relative to the space's white (Y = 1 ↦ L* = 100) → CIEDE2000 (colour-science).

References
----------
:cite:`Hoffman2020` N. Hoffman, "Fresnel Equations Considered Harmful"/"Thoughts on Fresnel", SIGGRAPH
    2020 Physically Based Shading course notes, sections "Full procedure" and "Computing RGB Parameter
    Values From Spectral IOR Data".
:cite:`CIE2018` CIE 015:2018 Colorimetry, 4th ed. (1931 2° observer; CIEDE2000 via colour-science).
:cite:`AMPAS2018` TB-2018-001, Derivation of the ACES White Point Chromaticity Coordinates.
:cite:`Sharma2005` G. Sharma, W. Wu, E. N. Dalal, "The CIEDE2000 Color-Difference Formula: Implementation
    Notes, Supplementary Test Data, and Mathematical Observations", Color Res. Appl. 30(1), 2005, eq. 1–22.
"""

from __future__ import annotations

import dataclasses
import functools

import colour
import numpy as np

from .validation import ParameterError, as_float_array, check_choice, check_shape_last

__all__ = [
    "WAVELENGTHS",
    "WORKING_SPACES",
    "WorkingSpace",
    "delta_E_2000",
    "delta_E_2000_Lab",
    "delta_E_2000_components",
    "rgb_to_Lab",
    "rgb_to_rgb_matrix",
    "spectral_to_rgb_weights",
    "working_space",
]

#: Wavelength samples (nm) of the spectral procedure: the CIE 5 nm tables over 360–830 nm.
WAVELENGTHS = np.arange(360.0, 830.0 + 0.5, 5.0)
_SHAPE = colour.SpectralShape(360, 830, 5)
_OBSERVER = "CIE 1931 2 Degree Standard Observer"


@dataclasses.dataclass(frozen=True)
class WorkingSpace:
    """An RGB working space of the spectral procedure.

    Attributes
    ----------
    name : str
        Registry key (``"ACEScg"``, ``"sRGB"``).
    colourspace : str
        colour-science ``RGB_COLOURSPACES`` key: primaries, white point and matrices.
    illuminant : str or None
        colour-science ``SDS_ILLUMINANTS`` key of the reference-white illuminant; ``None`` for a space
        that is only a conversion target (AP0), not a place where spectra are integrated.
    """

    name: str
    colourspace: str
    illuminant: str | None

    @property
    def rgb_colourspace(self) -> colour.RGB_Colourspace:
        return colour.RGB_COLOURSPACES[self.colourspace]


#: Registry: name → working space. ACEScg is lit by CIE D60 and adapted (Bradford) to the ACES white;
#: linear Rec.709/sRGB is lit by D65, its own white. AP0 (ACES2065-1) is a gamut-conversion target only.
WORKING_SPACES: dict[str, WorkingSpace] = {
    "ACEScg": WorkingSpace("ACEScg", "ACEScg", "D60"),
    "sRGB": WorkingSpace("sRGB", "sRGB", "D65"),
    "AP0": WorkingSpace("AP0", "ACES2065-1", None),
}


def working_space(name: str) -> WorkingSpace:
    """Look up a working space; the error lists the valid names."""
    return WORKING_SPACES[check_choice("colour space", name, sorted(WORKING_SPACES))]


@functools.cache
def spectral_to_rgb_weights(space: str) -> np.ndarray:
    """(3, N) weights W with RGB = W @ R(λ) for a reflectance R sampled at :data:`WAVELENGTHS`.

    W = normalise(M_XYZ→RGB · A_Bradford(illuminant white → space white) · [x̄ ȳ z̄]ᵀ diag(S) Δλ), each
    row scaled so that W @ 1 = 1: a perfect reflector is exactly white (Hoffman 2020).
    """
    space = working_space(space)
    if space.illuminant is None:
        raise ParameterError(
            f"colour space {space.name!r} is a conversion target; spectra are integrated in "
            f"{sorted(name for name, s in WORKING_SPACES.items() if s.illuminant)}"
        )
    cmfs = colour.MSDS_CMFS[_OBSERVER].copy().align(_SHAPE).values  # (N, 3)
    illuminant = colour.SDS_ILLUMINANTS[space.illuminant].copy().align(_SHAPE).values  # (N,)
    tristimulus = (cmfs * illuminant[:, None]).T  # (3, N), XYZ of each wavelength's share
    tristimulus = tristimulus / tristimulus[1].sum()
    white = colour.xy_to_XYZ(space.rgb_colourspace.whitepoint)
    adaptation = colour.adaptation.matrix_chromatic_adaptation_VonKries(
        tristimulus.sum(axis=1), white, transform="Bradford"
    )
    weights = space.rgb_colourspace.matrix_XYZ_to_RGB @ adaptation @ tristimulus
    weights = weights / weights.sum(axis=1, keepdims=True)
    weights.setflags(write=False)
    return weights


@functools.cache
def _white_XYZ(space: str) -> np.ndarray:
    return working_space(space).rgb_colourspace.matrix_RGB_to_XYZ.sum(axis=1)


def rgb_to_Lab(rgb, space: str) -> np.ndarray:
    """CIE L*a*b* of linear RGB colours (..., 3) of ``space``; RGB (1, 1, 1) is L* = 100, a* = b* = 0.

    The reference white is the XYZ of RGB white through the space's published matrix, not its nominal
    chromaticity: the rounding of the published matrices (sRGB's 4 decimals) would otherwise tint white
    by Δa* ≈ 0.008.
    """
    definition = working_space(space)
    rgb = check_shape_last("rgb", as_float_array("rgb", rgb), 3)
    white = _white_XYZ(definition.name)
    xyz = rgb @ definition.rgb_colourspace.matrix_RGB_to_XYZ.T / white[1]
    return colour.XYZ_to_Lab(xyz, colour.XYZ_to_xy(white))


def delta_E_2000_Lab(lab_a: np.ndarray, lab_b: np.ndarray) -> np.ndarray:
    """CIEDE2000 between CIE L*a*b* colours (..., 3) (unchecked; colour-science's implementation)."""
    lab_a, lab_b = np.broadcast_arrays(lab_a, lab_b)
    return np.asarray(colour.delta_E(lab_a, lab_b, method="CIE 2000"), dtype=np.float64)


def delta_E_2000(rgb_a, rgb_b, space: str) -> np.ndarray:
    """CIEDE2000 difference between linear RGB colours (..., 3) of ``space`` (broadcast) → (...)."""
    return delta_E_2000_Lab(rgb_to_Lab(rgb_a, space), rgb_to_Lab(rgb_b, space))


@functools.cache
def rgb_to_rgb_matrix(source: str, target: str) -> np.ndarray:
    """(3, 3) matrix taking linear RGB of ``source`` to ``target`` (Bradford adaptation between whites)."""
    matrix = colour.matrix_RGB_to_RGB(
        working_space(source).rgb_colourspace,
        working_space(target).rgb_colourspace,
        chromatic_adaptation_transform="Bradford",
    )
    matrix.setflags(write=False)
    return matrix


def delta_E_2000_components(lab_a, lab_b) -> np.ndarray:
    """(…, 3) residuals r whose squares sum to CIEDE2000² exactly, for least squares on ΔE2000.

    CIEDE2000 (Sharma et al. 2005, eq. 1–22; k_L = k_C = k_H = 1) is
    ΔE² = (ΔL′/S_L)² + (ΔC′/S_C)² + (ΔH′/S_H)² + R_T (ΔC′/S_C)(ΔH′/S_H); completing the square in the
    cross term gives r = (ΔL′/S_L, ΔC′/S_C + ½ R_T ΔH′/S_H, √(1 − R_T²/4) ΔH′/S_H), real since
    |R_T| = |sin 2Δθ| R_C ≤ 2. Unlike ΔE itself, r is smooth where the colours meet, which is what a
    Gauss–Newton (Levenberg–Marquardt) fit needs. Unchecked; ``delta_E_2000_Lab`` is the norm of r.
    """
    lab_a, lab_b = np.broadcast_arrays(np.asarray(lab_a, dtype=np.float64), np.asarray(lab_b, dtype=np.float64))
    L1, a1, b1 = np.moveaxis(lab_a, -1, 0)
    L2, a2, b2 = np.moveaxis(lab_b, -1, 0)
    chroma_mean7 = (0.5 * (np.hypot(a1, b1) + np.hypot(a2, b2))) ** 7
    g = 0.5 * (1.0 - np.sqrt(chroma_mean7 / (chroma_mean7 + 25.0**7)))  # eq. 4
    a1p, a2p = (1.0 + g) * a1, (1.0 + g) * a2  # eq. 5
    c1p, c2p = np.hypot(a1p, b1), np.hypot(a2p, b2)  # eq. 6
    h1p = np.where((a1p == 0.0) & (b1 == 0.0), 0.0, np.mod(np.degrees(np.arctan2(b1, a1p)), 360.0))  # eq. 7
    h2p = np.where((a2p == 0.0) & (b2 == 0.0), 0.0, np.mod(np.degrees(np.arctan2(b2, a2p)), 360.0))
    product = c1p * c2p
    dh = h2p - h1p
    dh = np.where(
        product == 0.0, 0.0, np.where(dh > 180.0, dh - 360.0, np.where(dh < -180.0, dh + 360.0, dh))
    )  # eq. 10
    d_lightness = L2 - L1  # eq. 8
    d_chroma = c2p - c1p  # eq. 9
    d_hue = 2.0 * np.sqrt(product) * np.sin(np.radians(0.5 * dh))  # eq. 11
    lightness_mean = 0.5 * (L1 + L2)  # eq. 12
    chroma_mean = 0.5 * (c1p + c2p)  # eq. 13
    hue_sum = h1p + h2p
    hue_mean = np.where(
        product == 0.0,
        hue_sum,
        np.where(
            np.abs(h1p - h2p) <= 180.0,
            0.5 * hue_sum,
            np.where(hue_sum < 360.0, 0.5 * (hue_sum + 360.0), 0.5 * (hue_sum - 360.0)),
        ),
    )  # eq. 14
    t = (
        1.0
        - 0.17 * np.cos(np.radians(hue_mean - 30.0))
        + 0.24 * np.cos(np.radians(2.0 * hue_mean))
        + 0.32 * np.cos(np.radians(3.0 * hue_mean + 6.0))
        - 0.20 * np.cos(np.radians(4.0 * hue_mean - 63.0))
    )  # eq. 15
    d_theta = 30.0 * np.exp(-(((hue_mean - 275.0) / 25.0) ** 2))  # eq. 16
    r_c = 2.0 * np.sqrt(chroma_mean**7 / (chroma_mean**7 + 25.0**7))  # eq. 17
    offset = (lightness_mean - 50.0) ** 2
    s_l = 1.0 + 0.015 * offset / np.sqrt(20.0 + offset)  # eq. 18
    s_c = 1.0 + 0.045 * chroma_mean  # eq. 19
    s_h = 1.0 + 0.015 * chroma_mean * t  # eq. 20
    r_t = -np.sin(np.radians(2.0 * d_theta)) * r_c  # eq. 21
    lightness, chroma, hue = d_lightness / s_l, d_chroma / s_c, d_hue / s_h
    return np.stack(
        [lightness, chroma + 0.5 * r_t * hue, np.sqrt(np.maximum(1.0 - 0.25 * r_t * r_t, 0.0)) * hue], axis=-1
    )
