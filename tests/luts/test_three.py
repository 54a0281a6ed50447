"""The three.js package (``luts/three``, ``fresnel-lut build --three``) inside three.js itself: ``three`` from npm at the
pinned version, in headless Chromium (SwiftShader), through real MeshStandardMaterial and MeshPhysicalMaterial
programs (tests/luts/three_page.py).

* the package's data are the build's tables rounded to half floats, its include the generator's, its code the source's;
* a moved anchor fails loudly, naming the chunk;
* the furnace read-back (uniform white environment) equals the Python mirror of the same arithmetic on the same half
  floats to float32 precision (5e-6 here) for every model, both material kinds, roughness 0 (three.js clamps to 0.045)
  to 1 and N·V from grazing (0.02) to 1, with and without multiple scattering;
* single scattering against the exact integral (exact Fresnel, independent quadrature): within the basis' own error
  plus 3e-4 for the half floats' rounding;
* the Figure 2 material (Belcour 2020 Fig. 2: r = 0.44, edge (0, 1, 0)) shows its green rim, which stock three.js's
  F0-only Schlick cannot.
"""

import json
import subprocess
import sys

import numpy as np
import pytest

from basis.eigenbasis import resolve_basis
from basis.gulbrandsen import gulbrandsen_to_nk
from basis.presets import material_coefficients
from basis.training.holdout import FIGURE_2
from benchmarks.three_page import PACKAGE, furnace, gltf_document, load_gltf, open_page, run_module, spheres
from handoff.shaders.mirrors import (
    coefficients_per_pixel_gulbrandsen,
    coefficients_per_pixel_nk,
    direct_fresnel,
    linear_direct,
    linear_weights,
)
from handoff.shipped import shipped_tables
from handoff.three import THREE_ROLES, THREE_VERSION, read_three_atlas
from preintegrate.lut import LutGrid
from preintegrate.multiple_scattering import compensated_albedo, weigh_schlick_texels
from tests.conftest import chromium, gpu_missing
from tests.references.fresnel import fresnel_complex
from tests.references.integration import reference_albedo_grid

GOLD = {"reflectivity": [0.944, 0.776, 0.373], "edge": [0.998, 0.981, 0.751]}
THREE_MIN_ROUGHNESS = 0.045  # lights_physical_fragment: max( roughnessFactor, 0.045 )


@pytest.fixture(scope="module")
def page():
    with chromium() as browser:
        page, messages = open_page(browser, missing=gpu_missing)
        yield page
        errors = [text for kind, text in messages if kind in ("error", "pageerror")]
        assert not errors, errors


@pytest.fixture(scope="module")
def atlas_tables():
    """role → the package's table as the GPU filters it (half floats), from its rectangle of the atlas."""
    values, layout, _ = read_three_atlas(PACKAGE)
    return {role: values[y : y + h, x : x + w] for role, (x, y, w, h) in layout.rects.items()}


def test_package_is_the_build(atlas_tables):
    basis = resolve_basis(None)
    _, layout, basis_hash = read_three_atlas(PACKAGE)
    assert basis_hash == basis.content_hash and set(layout.rects) == set(THREE_ROLES)
    shipped = shipped_tables()
    for role, table in (("basis", shipped[0]), ("schlick", shipped[1])):
        np.testing.assert_array_equal(atlas_tables[role], table.astype(np.float16).astype(np.float64))
    data = (PACKAGE / "data.js").read_text(encoding="utf-8")
    include = json.loads(data.split("export const INCLUDE = ", 1)[1].rstrip().rstrip(";"))
    maps = {role: layout.uv_map(role) for role in layout.rects}
    # generated as the command does, with its pinned numeric kernels (the constants' last digits depend on them)
    generate = (
        "from fresnel_lut.kernels import pin_numeric_kernels; pin_numeric_kernels(); import sys, json; "
        "from handoff.shaders import shader_includes; "
        f"sys.stdout.write(dict(shader_includes(None, 'fresnel-lut build --three', ltc_size=64, atlas={maps!r}, "
        "pixel_tables=False))['fresnel_basis_atlas.glsl'])"
    )
    completed = subprocess.run([sys.executable, "-c", generate], capture_output=True, text=True, timeout=120)
    assert completed.returncode == 0, completed.stderr
    assert include == completed.stdout
    source = (PACKAGE.parents[1] / "handoff" / "three" / "index.js").read_text(encoding="utf-8")
    assert (PACKAGE / "index.js").read_text(encoding="utf-8") == source
    manifest = json.loads((PACKAGE / "package.json").read_text(encoding="utf-8"))
    assert manifest["peerDependencies"] == {"three": THREE_VERSION} and manifest["type"] == "module"


def test_a_moved_anchor_fails_loudly(page):
    message = page.evaluate(
        """import('fresnel-basis-three').then(async (m) => {
             const THREE = await import('three');
             const chunks = Object.assign({}, THREE.ShaderChunk);
             chunks.lights_fragment_begin = chunks.lights_fragment_begin.replace('material.dfg =', 'material.dfg=');
             try { m.patchChunks(chunks); return 'patched'; } catch (error) { return error.name + ': ' + error.message; }
           })"""
    )
    assert message.startswith("FresnelBasisError: three.js r187's lights_fragment_begin holds 0 copies")
    assert page.evaluate("import('fresnel-basis-three').then((m) => Object.keys(m.patchChunks()).length)") == 2


def _cases():
    rng = np.random.default_rng(40)
    figure_eta, figure_kappa = gulbrandsen_to_nk(np.array(FIGURE_2["reflectivity"]), np.array(FIGURE_2["edge_tint"]))
    materials = [
        ({"model": "gulbrandsen", "edge": GOLD["edge"]}, GOLD["reflectivity"], 1.0),
        ({"model": "gulbrandsen", "edge": list(FIGURE_2["edge_tint"])}, list(FIGURE_2["reflectivity"]), 1.0),
        ({"model": "gulbrandsen", "edge": rng.uniform(0, 1, 3).tolist()}, rng.uniform(0.02, 0.98, 3).tolist(), 1.0),
        ({"model": "nk", "eta": figure_eta.tolist(), "kappa": figure_kappa.tolist()}, [0.0, 0.0, 0.0], 1.0),
        ({"model": "f82-tint", "tint": [0.9, 0.6, 0.3]}, [0.95, 0.64, 0.54], 1.0),
        ({"model": "coefficients", "coefficients": material_coefficients("Copper", "sRGB").tolist()}, [0.0] * 3, 1.0),
        ({"model": "gulbrandsen"}, [0.0, 0.0, 0.0], 0.0),  # the dielectric lobe: Schlick F0 0.04, exactly integrated
    ]
    cases = []
    for options, color, metalness in materials:
        for physical in (False, True):
            for multiple in (True, False):
                for roughness in (0.0, 0.3, 0.7, 1.0):
                    for mu in (0.02, 0.2, 0.6, 1.0):
                        basis = dict(options, multipleScattering=multiple)
                        cases.append(
                            {"mu": mu, "roughness": roughness, "metalness": metalness, "color": color,
                             "physical": physical, "basis": basis}
                        )  # fmt: skip
    return cases


def _fresnel(case):
    """("linear", weights (3, 3)) or ("basis", coefficients (3, 4)) of a case's metal (metalness 1) or black
    dielectric (metalness 0: Schlick with F0 0.04), as the package's fresnelThreeSetUp chooses them."""
    options, color = case["basis"], np.array(case["color"])
    if case["metalness"] == 0.0:
        return "linear", linear_weights("schlick", f0=np.full(3, 0.04), f90=1.0)
    if options["model"] == "f82-tint":
        return "linear", linear_weights("f82-tint", f0=color, tint=np.array(options["tint"]))
    if options["model"] == "coefficients":
        return "basis", np.array(options["coefficients"])
    if options["model"] == "nk":
        return "basis", coefficients_per_pixel_nk(np.array(options["eta"]), np.array(options["kappa"]))
    return "basis", coefficients_per_pixel_gulbrandsen(color, np.array(options["edge"]))


def _mirror(case, tables):
    """The package's arithmetic in float64 on its half-float tables: the furnace's radiance × single scattering plus
    irradiance / π × the multiple-scattering term, for a metal (metalness 1) or a black dielectric (metalness 0)."""
    grid = LutGrid(128, 128)
    mu, roughness = case["mu"], max(case["roughness"], THREE_MIN_ROUGHNESS)
    multiple = case["basis"]["multipleScattering"]
    kind, values = _fresnel(case)
    if kind == "linear":
        schlick = grid.lookup(tables["schlick"], mu, roughness)
        return weigh_schlick_texels(np.insert(values, 2, 0.0, axis=-1), schlick, multiple)
    coefficients = values
    terms = grid.lookup(tables["basis"], mu, roughness)
    single = coefficients @ terms
    if not multiple:
        return single
    average = np.clip(coefficients @ resolve_basis(None).hemispherical_averages, 0.0, 1.0)
    return compensated_albedo(single, np.clip(terms[0], 0.0, 1.0), average)


def test_furnace_matches_the_mirror(page, atlas_tables):
    cases = _cases()
    rendered = furnace(page, cases)
    expected = np.array([_mirror(case, atlas_tables) for case in cases])
    assert np.all(np.isfinite(rendered))
    np.testing.assert_allclose(rendered, expected, rtol=0, atol=5e-6)


def test_single_scattering_against_the_exact_integral(page):
    """Exact Fresnel of the materials, integrated independently (tests/references), against what three.js renders:
    the error is the basis' own (the same arithmetic on the float32 tables) plus at most 3e-4 of half-float storage
    (measured 1.5e-4); gold within 2e-3 in all (1.1e-3), the Figure 2 material, the basis' hard case, within 1.5e-2."""
    float32_tables = dict(zip(("basis", "schlick"), shipped_tables()[:2]))
    gold_eta, gold_kappa = gulbrandsen_to_nk(np.array(GOLD["reflectivity"]), np.array(GOLD["edge"]))
    figure_eta, figure_kappa = gulbrandsen_to_nk(np.array(FIGURE_2["reflectivity"]), np.array(FIGURE_2["edge_tint"]))
    points = [(mu, roughness) for roughness in (0.1, 0.3, 0.6, 1.0) for mu in (0.05, 0.3, 0.7, 1.0)]
    for (eta, kappa), options, color, tolerance in (
        ((gold_eta, gold_kappa), {"model": "gulbrandsen", "edge": GOLD["edge"]}, GOLD["reflectivity"], 2e-3),
        (
            (figure_eta, figure_kappa),
            {"model": "nk", "eta": figure_eta.tolist(), "kappa": figure_kappa.tolist()},
            [0.0, 0.0, 0.0],
            1.5e-2,
        ),
    ):
        cases = [
            {"mu": mu, "roughness": r, "metalness": 1.0, "color": color, "physical": True,
             "basis": dict(options, multipleScattering=False)}
            for mu, r in points
        ]  # fmt: skip
        rendered = furnace(page, cases)
        float32 = np.array([_mirror(case, float32_tables) for case in cases])
        mu, alpha = np.array(points).T[0], np.array(points).T[1] ** 2
        exact = reference_albedo_grid(lambda x: fresnel_complex(x[:, None], eta[None, :], kappa[None, :]), mu, alpha)
        assert np.max(np.abs(rendered - float32)) < 3e-4
        assert np.max(np.abs(rendered - exact)) < min(tolerance, np.max(np.abs(float32 - exact)) + 3e-4)


def test_figure_2_green_rim(page):
    """Spheres of the Figure 2 material under white light: the basis' rim turns green; stock three.js's stays grey."""
    size = 96
    material = {"mu": 1.0, "roughness": float(np.sqrt(FIGURE_2["alpha"])), "metalness": 1.0,
                "color": list(FIGURE_2["reflectivity"]), "physical": True}  # fmt: skip
    basis = dict(material, basis={"model": "gulbrandsen", "edge": list(FIGURE_2["edge_tint"])})
    image = spheres(page, [material, basis], size)
    y, x = np.mgrid[0:size, 0:size] + 0.5
    radius = np.hypot(x - size / 2, y - size / 2) / (size / 2 - 1)
    rim = (radius > 0.9) & (radius < 0.97)
    centre = radius < 0.3
    stock_rim, basis_rim = image[:, :size][rim, :3].mean(axis=0), image[:, size:][rim, :3].mean(axis=0)
    stock_centre, basis_centre = image[:, :size][centre, :3].mean(axis=0), image[:, size:][centre, :3].mean(axis=0)
    assert np.ptp(stock_rim) < 1e-3 and np.ptp(stock_centre) < 1e-3  # grey: F0 = 0.44 in every channel
    assert np.ptp(basis_centre) < 0.02  # head-on the material is grey too
    assert basis_rim[1] > 1.3 * max(basis_rim[0], basis_rim[2])  # the rim is green


def _metal_fresnel(case):
    """(F(μ) per channel as a function, F0 per channel) of a case's metal (metalness 1) or black dielectric."""
    kind, values = _fresnel(case)
    if kind == "linear":
        return (lambda mu: linear_direct(values, mu)), values[:, 0]
    return (lambda mu: direct_fresnel(values, mu)), values[:, 0]


def _punctual_mirror(case, light, tables):
    """three.js's RE_Direct_Physical for a black material (BRDF_GGX, Frostbite's V and D) with the package's F(V·H)
    and its compensation 1 + F0 (1/E − 1) (Turquin 2019 eq. 16; E = the Schlick table's scale + bias)."""
    mu, roughness = case["mu"], max(case["roughness"], THREE_MIN_ROUGHNESS)
    normal, view = np.array([0.0, np.sqrt(1.0 - mu * mu), mu]), np.array([0.0, 0.0, 1.0])
    half = (light + view) / np.linalg.norm(light + view)
    n_l, n_h, v_h = max(normal @ light, 0.0), max(normal @ half, 0.0), max(view @ half, 0.0)
    a2 = roughness**4
    visibility = 0.5 / (n_l * np.sqrt(a2 + (1 - a2) * mu * mu) + mu * np.sqrt(a2 + (1 - a2) * n_l * n_l))
    distribution = a2 / (np.pi * (n_h * n_h * (a2 - 1.0) + 1.0) ** 2)
    fresnel, f0 = _metal_fresnel(case)
    scale, bias = LutGrid(128, 128).lookup(tables["schlick"], mu, roughness)[:2]
    return n_l * fresnel(v_h) * visibility * distribution * (1.0 + f0 * (1.0 / (scale + bias) - 1.0))


def _lit_cases():
    return [case for case in _cases() if case["roughness"] >= 0.3 and case["basis"]["multipleScattering"]]


def test_punctual_light_matches_the_mirror(page, atlas_tables):
    direction = np.array([0.2, 0.45, 0.87])
    cases = _lit_cases()
    rendered = furnace(page, cases, {"kind": "directional", "direction": direction.tolist()})
    light = direction / np.linalg.norm(direction)
    expected = np.array([_punctual_mirror(case, light, atlas_tables) for case in cases])
    assert np.all(np.isfinite(rendered)) and np.max(expected) > 0.1
    np.testing.assert_allclose(rendered, expected, rtol=2e-4, atol=1e-6)


def test_rect_light_fresnel_is_the_split_sum(page, atlas_tables):
    """A RectAreaLight keeps three.js's LTC lobe and takes the package's split sum as its Fresnel: against a material
    whose F is 1 at every angle (F82 tint with F0 = tint = 1: the split sum is E), each pixel's ratio is F̄ / E."""
    lighting = {"kind": "rect", "position": [64.0, 30.0, 30.0], "size": [200.0, 60.0], "lookAt": [64.0, 0.0, 0.0]}
    cases = _lit_cases()
    white = [dict(case, color=[1.0, 1.0, 1.0], metalness=1.0, basis={"model": "f82-tint", "tint": [1.0, 1.0, 1.0]})
             for case in cases]  # fmt: skip
    rendered, reference = furnace(page, cases, lighting), furnace(page, white, lighting)
    lit = reference[:, 0] > 1e-4
    assert np.all(np.isfinite(rendered)) and lit.sum() > len(cases) // 2
    grid = LutGrid(128, 128)
    expected = []
    for case in cases:
        roughness = max(case["roughness"], THREE_MIN_ROUGHNESS)
        single = _mirror(dict(case, basis=dict(case["basis"], multipleScattering=False)), atlas_tables)
        scale, bias = grid.lookup(atlas_tables["schlick"], case["mu"], roughness)[:2]
        expected.append(single / (scale + bias))
    np.testing.assert_allclose(rendered[lit] / reference[lit, :1], np.array(expected)[lit], rtol=1e-4)


def test_gltf_plugin_maps_specular_colour_to_f82_tint(page, atlas_tables):
    """KHR_materials_specular's specularColorFactor of a metal becomes its F82 tint (EXT_materials_specular_openpbr);
    a dielectric (metallicFactor 0) keeps three.js's material."""
    tint, base = [0.9, 0.6, 0.3], [0.95, 0.64, 0.54]
    triangle = (np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0]]), None, None)
    loaded = load_gltf(
        page,
        gltf_document(
            [triangle] * 3,
            [
                {"pbrMetallicRoughness": {"baseColorFactor": [*base, 1.0], "metallicFactor": 1.0, "roughnessFactor": 0.5},
                 "extensions": {"KHR_materials_specular": {"specularColorFactor": tint}}},
                {"pbrMetallicRoughness": {"baseColorFactor": [*base, 1.0], "roughnessFactor": 0.5}},
                {"pbrMetallicRoughness": {"metallicFactor": 0.0, "roughnessFactor": 0.5}},
            ]
        ),
    )  # fmt: skip
    assert [m["type"] for m in loaded] == ["MeshPhysicalMaterial", "MeshStandardMaterial", "MeshStandardMaterial"]
    assert [m["defines"].get("FRESNEL_THREE_MODEL") for m in loaded] == [2, 2, None]
    mus = [0.05, 0.3, 1.0]
    rendered = furnace(page, [{"gltf": i, "mu": mu} for i in (0, 1) for mu in mus])
    for i, material_tint in ((0, tint), (1, [1.0, 1.0, 1.0])):
        for mu, value in zip(mus, rendered[3 * i : 3 * i + 3]):
            case = {"mu": mu, "roughness": 0.5, "metalness": 1.0, "color": base,
                    "basis": {"model": "f82-tint", "tint": material_tint, "multipleScattering": True}}  # fmt: skip
            np.testing.assert_allclose(value, _mirror(case, atlas_tables), rtol=0, atol=5e-6)


def test_readme_snippet_runs(page):
    """README's three.js example, as written, in the page (three.js and the package resolve as in an app)."""
    readme = (PACKAGE.parents[1] / "README.md").read_text(encoding="utf-8")
    section = readme.split("### three.js", 1)[1]
    snippet = section.split("```js\n", 1)[1].split("```", 1)[0]
    result = "export const result = { defines: gold.defines, edge: uniforms.fresnelBasisEdge.value.toArray() };"
    outcome = run_module(page, "readme", snippet + result)
    assert outcome["defines"]["FRESNEL_THREE_MODEL"] == 0 and outcome["edge"] == [1.0, 0.9, 0.6]


def test_every_physical_feature_compiles_with_the_patch(page):
    """Clear coat, sheen, iridescence, anisotropy, transmission, dispersion, KHR_materials_specular and a point light
    beside the environment: three.js's own branches around the patched lines compile and give finite light."""
    features = [
        {"clearcoat": 1.0, "clearcoatRoughness": 0.2},
        {"sheen": 1.0, "sheenRoughness": 0.5},
        {"iridescence": 1.0, "iridescenceIOR": 1.3},
        {"anisotropy": 0.6},
        {"transmission": 0.5, "thickness": 0.1, "dispersion": 0.2},
        {"specularIntensity": 0.5},
    ]
    cases = [
        {"mu": mu, "roughness": 0.4, "metalness": metalness, "color": [0.9, 0.6, 0.3], "physical": True,
         "extra": extra, "basis": {"model": "gulbrandsen", "edge": [1.0, 0.8, 0.6]}}
        for extra in features
        for metalness in (0.0, 0.5, 1.0)
        for mu in (0.1, 0.9)
    ]  # fmt: skip
    # iridescence's image-based light stays three.js's own, which goes negative at grazing in stock three.js too
    # (its Schlick_to_F0 inversion): the others must stay non-negative
    own = np.array(["iridescence" not in case["extra"] for case in cases])
    for lighting in (None, {"kind": "directional", "direction": [0.2, 0.45, 0.87]}):
        rendered = furnace(page, cases, lighting)
        assert np.all(np.isfinite(rendered)) and np.all(rendered[own] >= 0.0) and np.max(rendered) > 0.05
