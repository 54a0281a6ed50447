"""Approximate Fresnel models (basis/models) against the references' closed forms and properties.

Ground truth is written out here, independently of the module: Schlick 1994 eq. 15 (= Hoffman 2023 eq. 1),
Hoffman 2023 eq. 2-6 (Lazanyi, Adobe, generalized Schlick, generalized Adobe), Hoffman 2020 "2019:
Reparameterized Lazanyi" (F82), the corrected Cook-Torrance colour interpolation and "External Media
Adjustment", and the dielectric Fresnel equations in their textbook form (rs, rp with Snell's law), which share
no code with the library's conductor kernel. Where the reference is the exact Fresnel equations of a complex
IOR, ``fresnel_conductor`` (tested on its own in test_fresnel.py) is the comparison.

Tolerances: 1e-15 or exact equality where the module and the closed form perform the same arithmetic,
1e-14 where they differ by a few roundings, 1e-12 where the Fresnel equations are involved.
"""

import re

import numpy as np
import pytest

from basis.fresnel import fresnel_conductor, fresnel_dielectric
from basis.gulbrandsen import gulbrandsen_to_nk
from basis.models import FRESNEL_MODELS, fresnel_model, metal_external_f0, schlick_external_f0
from basis.validation import ParameterError

#: θ_max = arccos(1/(β + 1)) with β = 6 (Hoffman 2023, footnote 1): the extremum of the dip term.
MU_82 = 1.0 / 7.0
MU = np.concatenate([np.linspace(0.0, 1.0, 257), [MU_82]])

#: The channel column of the module docstring's table (the split-sum LUT channel count of each linear model).
CHANNELS = {
    "schlick": 2,
    "generalized-schlick": 2,
    "lazanyi": 3,
    "f82": 3,
    "adobe": 3,
    "generalized-adobe": 3,
    "cook-torrance": 2,
    "schlick-external": 2,
    "schlick-external-metal": 2,
    "fresnel-blend": 2,
}
NON_LINEAR = {"exact-external", "gulbrandsen"}
CLAMPED = {"lazanyi", "f82", "adobe", "generalized-adobe"}


# --- independent closed forms ------------------------------------------------------------------------------


def schlick(mu, f0):
    """Schlick 1994 eq. 15 = Hoffman 2023 eq. 1."""
    return f0 + (1.0 - f0) * (1.0 - mu) ** 5


def generalized_schlick(mu, r0, r90, exponent):
    """Hoffman 2023 eq. 4."""
    return r0 + (r90 - r0) * (1.0 - mu) ** exponent


def dip(mu, beta=6.0):
    """The Lazanyi term cos θ (1 - cos θ)^β (Hoffman 2023 eq. 2)."""
    return mu * (1.0 - mu) ** beta


def f82_curve(mu, f0, f82):
    """Hoffman 2020, "2019: Reparameterized Lazanyi": a = 823543/46656 (F0 - F82) + 49/6 (1 - F0), unclamped."""
    a = 823543.0 / 46656.0 * (f0 - f82) + 49.0 / 6.0 * (1.0 - f0)
    return f0 + (1.0 - f0) * (1.0 - mu) ** 5 - a * dip(mu)


def generalized_adobe_curve(mu, r0, r90, exponent, tint):
    """Hoffman 2023 eq. 5 with a from eq. 6 (eq. 2-3 for r90 = 1, exponent 5), unclamped."""
    a = generalized_schlick(MU_82, r0, r90, exponent) * (1.0 - tint) / dip(MU_82)
    return generalized_schlick(mu, r0, r90, exponent) - a * dip(mu)


def dielectric(mu, eta):
    """Unpolarised Fresnel reflectance of a dielectric with η > 1, textbook form: Snell's law, then rs and rp."""
    cos_t = np.sqrt(1.0 - (1.0 - mu * mu) / eta**2)
    rs = ((mu - eta * cos_t) / (mu + eta * cos_t)) ** 2
    rp = ((eta * mu - cos_t) / (eta * mu + cos_t)) ** 2
    return 0.5 * (rs + rp)


def normal_reflectance(eta, kappa):
    """F(θ = 0) = ((η - 1)² + κ²) / ((η + 1)² + κ²)."""
    return ((eta - 1.0) ** 2 + kappa**2) / ((eta + 1.0) ** 2 + kappa**2)


def external_root(eta_e):
    """√F0E = (η_E - 1)/(η_E + 1) (Hoffman 2020, "External Media Adjustment")."""
    return (eta_e - 1.0) / (eta_e + 1.0)


def dielectric_external(f0, eta_e):
    """Hoffman 2020, "External Media Adjustment": F0' = ((√F0 - √F0E) / (1 - √F0 √F0E))²."""
    root, root_e = np.sqrt(f0), external_root(eta_e)
    return ((root - root_e) / (1.0 - root * root_e)) ** 2


def metal_external(f0, eta_e):
    """Hoffman 2020, metal variant: (√F0 - √F0E)² if F0 < F0E, else ((√F0 - √F0E) / (1 - √F0E))²."""
    root, root_e = np.sqrt(f0), external_root(eta_e)
    return np.where(f0 < root_e**2, (root - root_e) ** 2, ((root - root_e) / (1.0 - root_e)) ** 2)


#: name -> p -> (F(μ = 1), F(μ = 0)) from the references.
ENDPOINTS = {
    "schlick": lambda p: (p["f0"], 1.0),
    "generalized-schlick": lambda p: (p["r0"], p["r90"]),
    "lazanyi": lambda p: (p["f0"], 1.0),
    "f82": lambda p: (p["f0"], 1.0),
    "adobe": lambda p: (p["f0"], 1.0),
    "generalized-adobe": lambda p: (p["r0"], p["r90"]),
    # F'(0°) is subtracted, F'(90°) = 1 for every real interface; the index-matched η' = 1, κ' = 0 has F' ≡ 0
    "cook-torrance": lambda p: (p["f0"], p["f0"] if (p["eta_prime"], p["kappa_prime"]) == (1.0, 0.0) else 1.0),
    "schlick-external": lambda p: (dielectric_external(p["f0"], p["eta_e"]), 1.0),
    "schlick-external-metal": lambda p: (metal_external(p["f0"], p["eta_e"]), 1.0),
    "exact-external": lambda p: (normal_reflectance(p["eta"] / p["eta_e"], p["kappa"] / p["eta_e"]), 1.0),
    "gulbrandsen": lambda p: (p["reflectivity"], 1.0),
    "fresnel-blend": lambda p: (p["rs"], 1.0),
}


# --- registry ------------------------------------------------------------------------------------------------


def test_registry_matches_the_documented_table():
    """The registry holds the models of the module docstring's table; linear/clamped flags and sweeps as documented."""
    assert set(FRESNEL_MODELS) == set(ENDPOINTS) == set(CHANNELS) | NON_LINEAR
    for name, model in FRESNEL_MODELS.items():
        assert fresnel_model(name) is model and model.name == name
        assert model.linear == (name not in NON_LINEAR)
        assert model.clamp == (name in CLAMPED)
        assert len(model.sweep) > 0


@pytest.mark.parametrize("name", sorted(CHANNELS))
def test_channel_count_matches_the_table(name):
    """channel_functions(**p)(μ) has the documented number of channels (the table's last column)."""
    model = fresnel_model(name)
    for point in model.sweep:
        assert model.channel_functions(**point)(MU).shape == (MU.size, CHANNELS[name])
        assert model.channel_weights(**point).shape == (CHANNELS[name],)


# --- end points and reference angle ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(FRESNEL_MODELS))
def test_normal_and_grazing_values(name):
    """F(μ = 1) and F(μ = 0) on every sweep point equal the references' values (ENDPOINTS; atol 1e-12).

    Schlick (eq. 1), Lazanyi, F82, Adobe (eq. 2-3): F(1) = F0, F(0) = 1; generalized Schlick/Adobe (eq. 4-6):
    r0 and r90; Cook-Torrance: F0 and 1; external media: the adjusted F0 and 1; exact-external: the
    closed-form normal reflectance of (η/η_E, κ/η_E); Gulbrandsen: r (eq. 7-9 are built for that).
    """
    model = fresnel_model(name)
    for point in model.sweep:
        normal, grazing = ENDPOINTS[name](point)
        np.testing.assert_allclose(model.evaluate(1.0, **point), normal, rtol=0, atol=1e-12, err_msg=str(point))
        np.testing.assert_allclose(model.evaluate(0.0, **point), grazing, rtol=0, atol=1e-12, err_msg=str(point))


def test_f82_passes_through_f82_at_arccos_one_seventh():
    """Hoffman 2020 "2019: Reparameterized Lazanyi": F(μ = 1/7) = F82 on every sweep point (atol 1e-13)."""
    model = fresnel_model("f82")
    for point in model.sweep:
        np.testing.assert_allclose(model.evaluate(MU_82, **point), point["f82"], rtol=0, atol=1e-13, err_msg=str(point))


def test_f82_matches_the_closed_form_where_unclamped():
    """The F82 model equals Hoffman 2020's formula (a from F0 and F82), clipped to [0, 1], on the μ grid (1e-14)."""
    model = fresnel_model("f82")
    for point in model.sweep:
        np.testing.assert_allclose(
            model.evaluate(MU, **point),
            np.clip(f82_curve(MU, **point), 0.0, 1.0),
            rtol=0,
            atol=1e-14,
            err_msg=str(point),
        )


def test_adobe_at_theta_max_is_tint_times_schlick():
    """Hoffman 2023 eq. 3 chooses a so that F(θ_max) = t · Schlick(θ_max), μ = 1/7 (atol 1e-14)."""
    model = fresnel_model("adobe")
    for point in model.sweep:
        np.testing.assert_allclose(
            model.evaluate(MU_82, **point),
            point["tint"] * schlick(MU_82, point["f0"]),
            rtol=0,
            atol=1e-14,
            err_msg=str(point),
        )


def test_adobe_with_white_tint_is_schlick_exactly():
    """Hoffman 2023: t = 1 gives a = 0 (eq. 3), so the Adobe model is Schlick's (eq. 1) bit for bit, and the
    closed form of eq. 1 within 1e-15."""
    f0 = np.array([0.0, 0.02, 0.04, 0.3, 0.6, 0.9, 1.0])
    mu = MU[:, None]
    adobe = fresnel_model("adobe").evaluate(mu, f0=f0, tint=1.0)
    np.testing.assert_array_equal(adobe, fresnel_model("schlick").evaluate(mu, f0=f0))
    np.testing.assert_allclose(adobe, schlick(mu, f0), rtol=0, atol=1e-15)


def test_adobe_matches_eq_2_and_3():
    """The Adobe model equals eq. 2 with β = 6 and a from eq. 3, clipped to [0, 1], on a (f0, tint) grid (1e-14)."""
    f0, tint = np.meshgrid([0.0, 0.04, 0.3, 0.6, 0.9, 1.0], [0.0, 0.1, 0.5, 0.9, 1.0], indexing="ij")
    mu = MU[:, None, None]
    expected = np.clip(generalized_adobe_curve(mu, f0, 1.0, 5.0, tint), 0.0, 1.0)
    np.testing.assert_allclose(fresnel_model("adobe").evaluate(mu, f0=f0, tint=tint), expected, rtol=0, atol=1e-14)


def test_adobe_and_f82_are_the_same_family():
    """Eq. 3 and Hoffman 2020's a agree: F82 = t · Schlick(1/7) makes the F82 model the Adobe model (1e-13).

    Both are eq. 2 with β = 6 and one constraint at μ = 1/7, so they coincide where the constraints do.
    """
    f0, tint = np.meshgrid([0.04, 0.3, 0.6, 0.9], [0.0, 0.3, 0.7, 1.0], indexing="ij")
    mu = MU[:, None, None]
    f82 = tint * schlick(MU_82, f0)
    np.testing.assert_allclose(
        fresnel_model("f82").evaluate(mu, f0=f0, f82=f82),
        fresnel_model("adobe").evaluate(mu, f0=f0, tint=tint),
        rtol=0,
        atol=1e-13,
    )


def test_generalized_adobe_at_theta_max_is_tint_times_generalized_schlick():
    """Hoffman 2023 eq. 6 makes F(θ_max) = t · (r0 + (r90 - r0)(6/7)^p) on every sweep point (atol 1e-14)."""
    model = fresnel_model("generalized-adobe")
    for point in model.sweep:
        expected = point["tint"] * generalized_schlick(MU_82, point["r0"], point["r90"], point["exponent"])
        np.testing.assert_allclose(model.evaluate(MU_82, **point), expected, rtol=0, atol=1e-14, err_msg=str(point))


def test_generalized_adobe_matches_eq_5_and_6():
    """The generalized Adobe model equals eq. 5 with a from eq. 6, clipped, on every sweep point (1e-14)."""
    model = fresnel_model("generalized-adobe")
    for point in model.sweep:
        np.testing.assert_allclose(
            model.evaluate(MU, **point),
            np.clip(generalized_adobe_curve(MU, **point), 0, 1),
            rtol=0,
            atol=1e-14,
            err_msg=str(point),
        )


@pytest.mark.parametrize("exponent", [0.5, 1.0, 2.0, 5.0, 8.0, 50.0])
def test_generalized_adobe_with_white_tint_is_generalized_schlick(exponent):
    """Hoffman 2023: t = 1 makes a = 0 in eq. 6, so eq. 5 is eq. 4 (the models agree bit for bit)."""
    r0 = np.array([0.0, 0.04, 0.6, 0.9])
    r90 = np.array([1.0, 0.5, 0.8, 0.2])
    mu = MU[:, None]
    adobe = fresnel_model("generalized-adobe").evaluate(mu, r0=r0, r90=r90, exponent=exponent, tint=1.0)
    np.testing.assert_array_equal(
        adobe, fresnel_model("generalized-schlick").evaluate(mu, r0=r0, r90=r90, exponent=exponent)
    )
    np.testing.assert_allclose(adobe, generalized_schlick(mu, r0, r90, exponent), rtol=0, atol=1e-15)


def test_generalized_adobe_with_r90_one_and_exponent_five_is_adobe():
    """Eq. 5-6 with r90 = 1, α = 5 reduce to eq. 2-3 (atol 1e-15)."""
    f0, tint = np.meshgrid([0.04, 0.3, 0.9], [0.0, 0.5, 1.0], indexing="ij")
    mu = MU[:, None, None]
    np.testing.assert_allclose(
        fresnel_model("generalized-adobe").evaluate(mu, r0=f0, r90=1.0, exponent=5.0, tint=tint),
        fresnel_model("adobe").evaluate(mu, f0=f0, tint=tint),
        rtol=0,
        atol=1e-15,
    )


def test_generalized_schlick_with_white_r90_and_exponent_five_is_schlick():
    """Eq. 4 with r90 = 1, α = 5 is eq. 1 (atol 1e-15: a float exponent 5.0 against an integer 5)."""
    f0 = np.array([0.0, 0.02, 0.04, 0.5, 0.98, 1.0])
    mu = MU[:, None]
    np.testing.assert_allclose(
        fresnel_model("generalized-schlick").evaluate(mu, r0=f0, r90=1.0, exponent=5.0),
        schlick(mu, f0),
        rtol=0,
        atol=1e-15,
    )


def test_generalized_schlick_default_exponent_is_five():
    """The exponent defaults to Schlick's 5 (its Parameter.default); omitted and explicit agree exactly."""
    model = fresnel_model("generalized-schlick")
    np.testing.assert_array_equal(
        model.evaluate(MU, r0=0.3, r90=0.8), model.evaluate(MU, r0=0.3, r90=0.8, exponent=5.0)
    )


@pytest.mark.parametrize("name", ["schlick", "fresnel-blend"])
def test_schlick_and_fresnel_blend_are_eq_1(name):
    """Schlick and pbrt's FresnelBlend SchlickFresnel are eq. 1 (atol 1e-15) on every sweep point."""
    model = fresnel_model(name)
    for point in model.sweep:
        (value,) = point.values()
        np.testing.assert_allclose(model.evaluate(MU, **point), schlick(MU, value), rtol=0, atol=1e-15)


def test_lazanyi_matches_eq_2():
    """The Lazanyi model is eq. 2 (with α as the dip exponent β), clipped to [0, 1]; a = 0 is Schlick (1e-14)."""
    model = fresnel_model("lazanyi")
    for point in model.sweep:
        expected = schlick(MU, point["f0"]) - point["a"] * dip(MU, point["alpha"])
        np.testing.assert_allclose(model.evaluate(MU, **point), np.clip(expected, 0.0, 1.0), rtol=0, atol=1e-14)
        if point["a"] == 0.0:
            np.testing.assert_allclose(model.evaluate(MU, **point), schlick(MU, point["f0"]), rtol=0, atol=1e-15)
    np.testing.assert_allclose(model.evaluate(1.0, f0=0.3, a=2.0), 0.3, rtol=0, atol=1e-15)  # alpha defaults to 6
    np.testing.assert_allclose(
        model.evaluate(MU, f0=0.3, a=2.0), model.evaluate(MU, f0=0.3, a=2.0, alpha=6.0), rtol=0, atol=0
    )


# --- Cook-Torrance colour interpolation --------------------------------------------------------------------


@pytest.mark.parametrize("eta", [1.2, 1.5, 2.0, 2.5, 3.5])
def test_cook_torrance_with_a_matching_dielectric_is_that_dielectric(eta):
    """Hoffman 2020's interpolation F = F0 + (1 - F0)(F' - F'0)/(1 - F'0) is F' itself when F0 = F'0 and F' ≥ F'0.

    For these η the unpolarised dielectric reflectance never falls below its normal value (checked on the
    closed form), so the model equals the textbook dielectric Fresnel equations at every μ (atol 1e-12).
    """
    f0 = ((eta - 1.0) / (eta + 1.0)) ** 2
    exact = dielectric(MU, eta)
    assert np.all(exact >= f0 - 1e-15)
    curve = fresnel_model("cook-torrance").evaluate(MU, f0=f0, eta_prime=eta, kappa_prime=0.0)
    np.testing.assert_allclose(curve, exact, rtol=0, atol=1e-12)
    np.testing.assert_allclose(curve, fresnel_dielectric(MU, eta), rtol=0, atol=1e-12)


@pytest.mark.parametrize("eta", [4.0, 10.0, 100.0])
def test_cook_torrance_with_a_high_index_dielectric_clips_the_dip(eta):
    """For η ≳ 3.7 the unpolarised reflectance dips below F0 (Rp falls faster than Rs rises): there
    max(0, F' - F'0) = 0 and the model is F0; elsewhere it is F' (Hoffman 2020, corrected interpolation; 1e-12)."""
    f0 = ((eta - 1.0) / (eta + 1.0)) ** 2
    exact = dielectric(MU, eta)
    below = exact < f0
    assert below.any() and not below.all()
    curve = fresnel_model("cook-torrance").evaluate(MU, f0=f0, eta_prime=eta, kappa_prime=0.0)
    np.testing.assert_allclose(curve[~below], exact[~below], rtol=0, atol=1e-12)
    np.testing.assert_allclose(curve[below], f0, rtol=0, atol=1e-12)


def test_cook_torrance_matches_the_interpolation_formula():
    """On every sweep point and for RGB F0: F = F0 + (1 - F0) max(0, F' - F'(0°)) / (1 - F'(0°)) with F' the
    exact Fresnel equations of (η', κ') (Hoffman 2020; atol 1e-12)."""
    model = fresnel_model("cook-torrance")
    f0 = np.array([0.9, 0.6, 0.3])  # gold-like RGB
    for point in model.sweep:
        eta, kappa = point["eta_prime"], point["kappa_prime"]
        f_prime = fresnel_conductor(MU, eta, kappa)
        f_normal = normal_reflectance(eta, kappa)
        g = np.maximum(0.0, f_prime - f_normal) / (1.0 - f_normal)
        np.testing.assert_allclose(
            model.evaluate(MU, **point), point["f0"] + (1.0 - point["f0"]) * g, rtol=0, atol=1e-12, err_msg=str(point)
        )
        np.testing.assert_allclose(
            model.evaluate(MU[:, None], f0=f0, eta_prime=eta, kappa_prime=kappa),
            f0 + (1.0 - f0) * g[:, None],
            rtol=0,
            atol=1e-12,
            err_msg=str(point),
        )


# --- external media ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("eta_e", [1.0, 1.33, 1.5, 2.0, 2.42, 10.0])
def test_schlick_external_f0_is_exact_for_dielectrics(eta_e):
    """Hoffman 2020, "External Media Adjustment": for a dielectric of index η ≥ 1 (F0 = ((η-1)/(η+1))²)
    the adjusted F0 is ((η - η_E)/(η + η_E))², the normal reflectance of η/η_E (atol 1e-14)."""
    eta = np.linspace(1.0, 10.0, 451)
    f0 = ((eta - 1.0) / (eta + 1.0)) ** 2
    np.testing.assert_allclose(schlick_external_f0(f0, eta_e), ((eta - eta_e) / (eta + eta_e)) ** 2, rtol=0, atol=1e-14)


def test_external_adjustments_hand_values():
    """η_E = 1.5 gives √F0E = 0.2, F0E = 0.04; hand-computed F0' (Hoffman 2020's two formulas; atol 1e-15).

    Dielectric: F0 = 0.64 -> (0.6/0.84)², 0.01 -> (0.1/0.98)², 0.04 -> 0, 0 -> 0.04, 1 -> 1.
    Metal: 0.64 -> (0.6/0.8)² = 0.5625, 0.01 -> (0.1 - 0.2)² = 0.01, 0.04 -> 0, 0 -> 0.04, 1 -> 1.
    """
    f0 = np.array([0.64, 0.01, 0.04, 0.0, 1.0])
    np.testing.assert_allclose(
        schlick_external_f0(f0, 1.5), [(0.6 / 0.84) ** 2, (0.1 / 0.98) ** 2, 0.0, 0.04, 1.0], rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(metal_external_f0(f0, 1.5), [0.5625, 0.01, 0.0, 0.04, 1.0], rtol=0, atol=1e-15)


def test_external_adjustments_leave_f0_unchanged_in_air():
    """η_E = 1 makes √F0E = 0: both formulas return F0 (atol 1e-15, the rounding of (√F0)²)."""
    f0 = np.linspace(0.0, 1.0, 101)
    np.testing.assert_allclose(schlick_external_f0(f0, 1.0), f0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(metal_external_f0(f0, 1.0), f0, rtol=0, atol=1e-15)


@pytest.mark.parametrize("eta_e", [1.0, 1.33, 1.6, 2.42, 10.0])
def test_metal_external_f0_branches(eta_e):
    """The metal variant picks (√F0 - √F0E)² below F0E and ((√F0 - √F0E)/(1 - √F0E))² from F0E on, for
    scalars and for an RGB F0 straddling F0E (Hoffman 2020; atol 1e-15); it is continuous (0) at F0 = F0E."""
    f0e = external_root(eta_e) ** 2
    f0 = np.linspace(0.0, 1.0, 201)
    np.testing.assert_allclose(metal_external_f0(f0, eta_e), metal_external(f0, eta_e), rtol=0, atol=1e-15)
    rgb = np.array([0.5 * f0e, f0e, 0.5 * (1.0 + f0e)])
    adjusted = metal_external_f0(rgb, eta_e)
    assert adjusted.shape == (3,)
    np.testing.assert_allclose(adjusted[0], (np.sqrt(rgb[0]) - np.sqrt(f0e)) ** 2, rtol=0, atol=1e-15)
    np.testing.assert_allclose(adjusted[1], 0.0, rtol=0, atol=1e-15)
    np.testing.assert_allclose(
        adjusted[2], ((np.sqrt(rgb[2]) - np.sqrt(f0e)) / (1.0 - np.sqrt(f0e))) ** 2, rtol=0, atol=1e-15
    )
    np.testing.assert_allclose(metal_external_f0(1.0, eta_e), 1.0, rtol=0, atol=1e-15)  # white stays white


@pytest.mark.parametrize(
    ("name", "adjust"), [("schlick-external", dielectric_external), ("schlick-external-metal", metal_external)]
)
def test_external_models_are_schlick_with_the_adjusted_f0(name, adjust):
    """schlick-external(-metal) = eq. 1 with F0' from Hoffman 2020's formula, every sweep point and RGB (1e-15)."""
    model = fresnel_model(name)
    for point in model.sweep:
        np.testing.assert_allclose(
            model.evaluate(MU, **point),
            schlick(MU, adjust(point["f0"], point["eta_e"])),
            rtol=0,
            atol=1e-15,
            err_msg=str(point),
        )
    f0 = np.array([0.95, 0.64, 0.54])
    np.testing.assert_allclose(
        model.evaluate(MU[:, None], f0=f0, eta_e=1.33), schlick(MU[:, None], adjust(f0, 1.33)), rtol=0, atol=1e-15
    )


def test_exact_external_divides_eta_and_kappa_by_the_external_index():
    """Hoffman 2020: the exact curve in a medium η_E is the Fresnel equations of (η/η_E, κ/η_E) (atol 1e-15)."""
    model = fresnel_model("exact-external")
    for point in model.sweep:
        expected = fresnel_conductor(MU, point["eta"] / point["eta_e"], point["kappa"] / point["eta_e"])
        np.testing.assert_allclose(model.evaluate(MU, **point), expected, rtol=0, atol=1e-15, err_msg=str(point))


@pytest.mark.parametrize("eta_e", [1.0, 1.33, 2.0])
def test_exact_external_dielectric_agrees_with_textbook_and_schlick_external(eta_e):
    """A dielectric η = 2.5 under η_E: exact-external equals the textbook Fresnel equations of η/η_E (1e-12),
    and its F(0°) is the dielectric adjustment of F0 = ((η-1)/(η+1))² (Hoffman 2020: exact for dielectrics; 1e-14)."""
    eta = 2.5
    curve = fresnel_model("exact-external").evaluate(MU, eta=eta, kappa=0.0, eta_e=eta_e)
    np.testing.assert_allclose(curve, dielectric(MU, eta / eta_e), rtol=0, atol=1e-12)
    f0 = ((eta - 1.0) / (eta + 1.0)) ** 2
    np.testing.assert_allclose(curve[MU == 1.0], schlick_external_f0(f0, eta_e), rtol=0, atol=1e-14)


# --- Gulbrandsen -------------------------------------------------------------------------------------------


def test_gulbrandsen_model_is_fresnel_of_gulbrandsen_to_nk():
    """The gulbrandsen model is fresnel_conductor(μ, *gulbrandsen_to_nk(r, g)) (Gulbrandsen 2014 eq. 7-9) on every
    sweep point and for RGB (r, g) (atol 1e-15)."""
    model = fresnel_model("gulbrandsen")
    for point in model.sweep:
        expected = fresnel_conductor(MU, *gulbrandsen_to_nk(point["reflectivity"], point["edge_tint"]))
        np.testing.assert_allclose(model.evaluate(MU, **point), expected, rtol=0, atol=1e-15, err_msg=str(point))
    r, g = np.array([0.95, 0.64, 0.54]), np.array([0.1, 0.5, 0.9])
    expected = fresnel_conductor(MU[:, None], *gulbrandsen_to_nk(r, g))
    np.testing.assert_allclose(model.evaluate(MU[:, None], reflectivity=r, edge_tint=g), expected, rtol=0, atol=1e-15)


@pytest.mark.parametrize("r", [0.04, 0.3, 0.9])
def test_gulbrandsen_zero_edge_tint_is_the_dielectric_with_that_f0(r):
    """g = 0 gives n_max = (1 + √r)/(1 - √r), κ = 0 (Gulbrandsen 2014 eq. 8): the textbook dielectric (1e-12)."""
    eta = (1.0 + np.sqrt(r)) / (1.0 - np.sqrt(r))
    np.testing.assert_allclose(
        fresnel_model("gulbrandsen").evaluate(MU, reflectivity=r, edge_tint=0.0),
        dielectric(MU, eta),
        rtol=0,
        atol=1e-12,
    )


# --- linear structure and the clamp ---------------------------------------------------------------------------


@pytest.mark.parametrize("name", sorted(CHANNELS))
def test_channels_times_weights_reproduce_the_curve(name):
    """F = Σ w_n t_n(μ): channel_functions(**p)(μ) @ channel_weights(**p) equals the unclamped curve on every sweep
    point (atol 1e-14), which is what makes the split sums exact with one LUT channel per t_n."""
    model = fresnel_model(name)
    for point in model.sweep:
        linear = model.channel_functions(**point)(MU) @ model.channel_weights(**point)
        np.testing.assert_allclose(
            linear, model.curve(MU, model.check(**point)), rtol=0, atol=1e-14, err_msg=str(point)
        )


@pytest.mark.parametrize("name", sorted(CHANNELS))
def test_channels_with_rgb_weights(name):
    """RGB parameters give (3, n) weights; t(μ) @ wᵀ is the (M, 3) unclamped curve (atol 1e-14)."""
    model = fresnel_model(name)
    params = rgb_parameters(model)
    weights = model.channel_weights(**params)
    assert weights.shape == (3, CHANNELS[name])
    linear = model.channel_functions(**params)(MU) @ weights.T
    np.testing.assert_allclose(linear, model.curve(MU[:, None], model.check(**params)), rtol=0, atol=1e-14)


@pytest.mark.parametrize("name", sorted(FRESNEL_MODELS))
def test_evaluate_is_the_curve_unless_clamped(name):
    """Where clamp_is_inactive(**p) holds, evaluate equals the unclamped curve exactly; where it does not (clamped
    models only), the unclamped curve leaves [0, 1] and evaluate is its clip to [0, 1]. The flag is checked against
    a denser μ grid (20001 points) than the module's."""
    model = fresnel_model(name)
    dense = np.linspace(0.0, 1.0, 20001)
    for point in model.sweep:
        checked = model.check(**point)
        inactive = bool(model.clamp_is_inactive(**point))
        curve = model.curve(MU, checked)
        dense_curve = model.curve(dense, checked)
        if inactive:
            np.testing.assert_array_equal(model.evaluate(MU, **point), curve, err_msg=str(point))
            assert dense_curve.min() >= -1e-9 and dense_curve.max() <= 1.0 + 1e-9, point
        else:
            assert model.clamp, point
            assert dense_curve.min() < 0.0 or dense_curve.max() > 1.0, point
            np.testing.assert_array_equal(model.evaluate(MU, **point), np.clip(curve, 0.0, 1.0), err_msg=str(point))


def test_f82_clamp_is_active_for_a_dark_f82():
    """F0 = 0.2, F82 = 0: Hoffman 2020 warns such extremes leave [0, 1]; the closed form goes below 0, the flag is
    False, and evaluate stays in [0, 1], equal to the clipped closed form (atol 1e-14) and still F82 at μ = 1/7."""
    model = fresnel_model("f82")
    closed = f82_curve(MU, 0.2, 0.0)
    assert closed.min() < -0.05
    assert not model.clamp_is_inactive(f0=0.2, f82=0.0)
    values = model.evaluate(MU, f0=0.2, f82=0.0)
    assert values.min() >= 0.0 and values.max() <= 1.0
    np.testing.assert_allclose(values, np.clip(closed, 0.0, 1.0), rtol=0, atol=1e-14)
    np.testing.assert_allclose(model.evaluate(MU_82, f0=0.2, f82=0.0), 0.0, rtol=0, atol=1e-14)
    # per channel for RGB: only the dark channel is clamped
    np.testing.assert_array_equal(model.clamp_is_inactive(f0=[0.2, 0.9, 0.5], f82=[0.0, 0.9, 0.6]), [False, True, True])


# --- broadcasting ------------------------------------------------------------------------------------------


def rgb_parameters(model, shape=(3,)):
    """Colour parameters as arrays of ``shape`` taken from spread sweep points; scalar ones from the first point."""
    size = int(np.prod(shape))
    points = [model.sweep[i] for i in np.linspace(0, len(model.sweep) - 1, size).round().astype(int)]
    return {
        parameter.name: (
            np.reshape([p[parameter.name] for p in points], shape)
            if parameter.colour
            else model.sweep[0][parameter.name]
        )
        for parameter in model.parameters
    }


def scalar_at(params, index):
    return {name: (value[index] if np.ndim(value) else value) for name, value in params.items()}


@pytest.mark.parametrize("name", sorted(FRESNEL_MODELS))
def test_rgb_parameters_broadcast_against_mu(name):
    """(3,) colour parameters with μ of shape (5, 1) give (5, 3); each column is the scalar evaluation (1e-15)."""
    model = fresnel_model(name)
    params = rgb_parameters(model)
    mu = np.linspace(0.0, 1.0, 5)[:, None]
    values = model.evaluate(mu, **params)
    assert values.shape == (5, 3)
    for j in range(3):
        np.testing.assert_allclose(values[:, j], model.evaluate(mu[:, 0], **scalar_at(params, j)), rtol=0, atol=1e-15)
    assert np.shape(model.clamp_is_inactive(**params)) == (3,)


@pytest.mark.parametrize("name", sorted(FRESNEL_MODELS))
def test_matrix_parameters_broadcast_against_scalar_and_array_mu(name):
    """(2, 3) colour parameters: scalar μ gives (2, 3), μ of shape (4, 1, 1) gives (4, 2, 3); elementwise equal to
    scalar evaluations (atol 1e-15)."""
    model = fresnel_model(name)
    params = rgb_parameters(model, (2, 3))
    at_scalar = model.evaluate(0.3, **params)
    assert at_scalar.shape == (2, 3)
    mu = np.array([0.0, 0.3, MU_82, 1.0])
    values = model.evaluate(mu[:, None, None], **params)
    assert values.shape == (4, 2, 3)
    np.testing.assert_array_equal(values[1], at_scalar)
    for index in np.ndindex(2, 3):
        np.testing.assert_allclose(
            values[(slice(None),) + index], model.evaluate(mu, **scalar_at(params, index)), rtol=0, atol=1e-15
        )


# --- errors --------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["nope", "Schlick", "", None, ["schlick"]])
def test_unknown_model_name_lists_the_valid_names(name):
    """fresnel_model raises ParameterError naming every registered model."""
    with pytest.raises(ParameterError) as error:
        fresnel_model(name)
    for valid in FRESNEL_MODELS:
        assert repr(valid) in str(error.value)


@pytest.mark.parametrize(
    ("name", "values", "message"),
    [
        ("schlick", {"f0": 1.5}, "f0 must be in [0, 1], got 1.5"),
        ("schlick", {"f0": -0.01}, "f0 must be in [0, 1], got -0.01"),
        ("schlick", {"f0": float("nan")}, "f0 must be in [0, 1], got nan"),
        ("schlick", {"f0": [0.1, float("inf"), 0.3]}, "f0 must be in [0, 1], got inf"),
        ("generalized-schlick", {"r0": 0.04, "r90": 1.0, "exponent": 0.0}, "exponent must be in [0.1, 50], got 0.0"),
        ("generalized-schlick", {"r0": 0.04, "r90": 1.2}, "r90 must be in [0, 1], got 1.2"),
        ("lazanyi", {"f0": 0.5, "a": 25.0}, "a must be in [-20, 20], got 25.0"),
        ("f82", {"f0": 0.5, "f82": -0.5}, "f82 must be in [0, 1], got -0.5"),
        ("adobe", {"f0": 0.5, "tint": [0.5, 1.1, 0.5]}, "tint must be in [0, 1], got 1.1"),
        ("cook-torrance", {"f0": 0.5, "eta_prime": 0.0}, "eta_prime must be in [1e-08, 1e+06], got 0.0"),
        ("schlick-external", {"f0": 0.5, "eta_e": 0.5}, "eta_e must be in [1, 10], got 0.5"),
        ("schlick-external-metal", {"f0": 0.5, "eta_e": 11.0}, "eta_e must be in [1, 10], got 11.0"),
        ("exact-external", {"eta": 1.5, "kappa": -1.0, "eta_e": 1.0}, "kappa must be in [0, 1e+06], got -1.0"),
        ("gulbrandsen", {"reflectivity": 0.5, "edge_tint": 2.0}, "edge_tint must be in [0, 1], got 2.0"),
    ],
)
def test_out_of_range_parameter_names_it_and_its_range(name, values, message):
    """evaluate, check and (for linear models) channel_weights raise ParameterError '<name> must be in [lo, hi]'."""
    model = fresnel_model(name)
    pattern = re.escape(message)
    with pytest.raises(ParameterError, match=pattern):
        model.evaluate(0.5, **values)
    with pytest.raises(ParameterError, match=pattern):
        model.check(**values)
    if model.linear:
        with pytest.raises(ParameterError, match=pattern):
            model.channel_weights(**values)


def test_gulbrandsen_rejects_unit_reflectivity():
    """r = 1 has no finite (η, κ) (η ≈ 4/(1 - r) at g = 0): ParameterError naming reflectivity."""
    with pytest.raises(ParameterError, match="reflectivity must be in"):
        fresnel_model("gulbrandsen").evaluate(0.5, reflectivity=1.0, edge_tint=0.5)


@pytest.mark.parametrize("mu", [1.5, -0.1, float("nan")])
def test_out_of_range_mu(mu):
    """μ outside [0, 1] (or NaN) raises ParameterError naming mu."""
    with pytest.raises(ParameterError, match=re.escape("mu must be in [0, 1]")):
        fresnel_model("schlick").evaluate(mu, f0=0.5)


@pytest.mark.parametrize("value", [True, "0.5", None, 0.5 + 0.1j])
def test_malformed_parameter(value):
    """Booleans, strings, complex numbers are refused with a ParameterError naming the parameter (None = missing)."""
    with pytest.raises(ParameterError, match="f0"):
        fresnel_model("schlick").evaluate(0.5, f0=value)


@pytest.mark.parametrize(
    ("name", "values", "missing"),
    [
        ("schlick", {}, "f0"),
        ("generalized-schlick", {"r0": 0.04}, "r90"),
        ("adobe", {"f0": 0.04}, "tint"),
        ("cook-torrance", {"f0": 0.04}, "eta_prime"),
        ("exact-external", {"eta": 1.5, "kappa": 0.0}, "eta_e"),
        ("gulbrandsen", {"edge_tint": 0.5}, "reflectivity"),
    ],
)
def test_missing_parameter_is_named(name, values, missing):
    """A parameter without default raises ParameterError 'model NAME needs PARAM'."""
    with pytest.raises(ParameterError, match=re.escape(f"model {name!r} needs {missing}")):
        fresnel_model(name).evaluate(0.5, **values)


def test_missing_shape_parameter_in_channel_functions():
    """channel_functions needs the shape parameters without default (η' of Cook-Torrance); κ' defaults to 0."""
    with pytest.raises(ParameterError, match="needs eta_prime"):
        fresnel_model("cook-torrance").channel_functions()
    model = fresnel_model("cook-torrance")
    np.testing.assert_array_equal(
        model.channel_functions(eta_prime=1.5)(MU), model.channel_functions(eta_prime=1.5, kappa_prime=0.0)(MU)
    )


def test_unknown_keyword_is_refused():
    """An unknown keyword raises ParameterError naming it and the accepted ones (no silent typo such as f90)."""
    with pytest.raises(ParameterError, match=re.escape("takes ['f0'], got unknown ['f90']")):
        fresnel_model("schlick").evaluate(0.5, f0=0.1, f90=1.0)
    with pytest.raises(ParameterError, match="unknown"):
        fresnel_model("adobe").check(f0=0.1, tint=1.0, exponent=5.0)


@pytest.mark.parametrize(
    ("name", "values"),
    [
        ("generalized-schlick", {"r0": 0.04, "r90": 1.0, "exponent": [1.0, 2.0, 3.0]}),
        ("generalized-adobe", {"r0": 0.04, "r90": 1.0, "exponent": [5.0], "tint": 0.5}),
        ("lazanyi", {"f0": 0.04, "a": 1.0, "alpha": [6.0, 6.0, 6.0]}),
        ("cook-torrance", {"f0": 0.04, "eta_prime": [1.5, 1.5, 1.5]}),
    ],
)
def test_array_shape_parameter_is_refused_by_check(name, values):
    """A shape parameter fixes the LUT channels and must be one number: check/evaluate raise ParameterError."""
    model = fresnel_model(name)
    (shape_name,) = (key for key in values if key in model.shape)
    with pytest.raises(ParameterError, match=f"{shape_name} fixes the LUT channels and must be one number"):
        model.check(**values)
    with pytest.raises(ParameterError, match=shape_name):
        model.evaluate(0.5, **values)
    with pytest.raises(ParameterError, match=shape_name):
        model.channel_weights(**values)


@pytest.mark.parametrize("exponent", [[1.0, 2.0, 3.0], [2.0]])
def test_array_shape_parameter_is_refused_by_channel_functions(exponent):
    """channel_functions(exponent=array) should raise ParameterError naming exponent, like check()."""
    with pytest.raises(ParameterError, match="exponent"):
        fresnel_model("generalized-schlick").channel_functions(exponent=exponent)


def test_out_of_range_shape_parameter_in_channel_functions():
    """channel_functions validates the range of the shape parameter: ParameterError naming it and its range."""
    with pytest.raises(ParameterError, match=re.escape("exponent must be in [0.1, 50], got 0.0")):
        fresnel_model("generalized-schlick").channel_functions(exponent=0.0)
    with pytest.raises(ParameterError, match="alpha must be in"):
        fresnel_model("lazanyi").channel_functions(alpha=float("nan"))


@pytest.mark.parametrize("name", sorted(NON_LINEAR))
def test_channel_functions_of_a_non_linear_model_lists_the_linear_ones(name):
    """channel_functions / channel_weights of a model without fixed channels raise ParameterError whose list of
    linear models is exactly the models with a channel count in the docstring table."""
    model = fresnel_model(name)
    point = model.sweep[0]
    for call in (lambda: model.channel_functions(**point), lambda: model.channel_weights(**point)):
        with pytest.raises(ParameterError, match="not linear") as error:
            call()
        listed = str(error.value).split("linear models:")[1]
        assert set(re.findall(r"'([^']+)'", listed)) == set(CHANNELS)
