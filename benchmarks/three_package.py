"""The three.js package inside three.js (issue 40): stock three.js r187 against ``applyFresnelBasis`` on the same
planes, both against the exact integral, and a picture.

Both render a furnace (uniform white environment: radiance 1, irradiance π; benchmarks.three_page) with real
MeshPhysicalMaterial programs in headless Chromium: what a pixel shows is the material's directional albedo as
three.js's image-based light computes it, multiple scattering included (three.js: Fdez-Agüera 2019 with its 16 × 16
DFG table and F_avg of Schlick's F0; the package: the same form with the basis' E and F_avg). The reference is that
same model made exact: F̄_ss by an independent quadrature of the exact Fresnel curve (tests/references), E likewise,
F_avg = 2∫F μ dμ exactly, combined by Kulla–Conty / Fdez-Agüera's formula. Materials: the measured metals of
``luts/materials.json`` in linear sRGB (stock: base colour = their F0; the package: their basis coefficients, model
``coefficients``), gold and the talk's Figure 2 material as Gulbrandsen (r, g) (stock: base colour r; the package:
``gulbrandsen`` with the edge colour). Errors are |Δ| over R, G, B at N·V ∈ {0.1, 0.3, 0.5, 0.7, 0.9, 1} and
perceptual roughness ∈ {0.1, 0.3, 0.5, 0.7, 0.9}. The picture: both on spheres in three.js's RoomEnvironment.

Run: ``.venv/bin/python -m benchmarks.three_package [--materials N] [--out FILE]`` (the report:
``--out report/three.md``, which also writes ``report/three_spheres.png``).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from basis.materials import material_from_mapping
from basis.presets import material_coefficients
from basis.training.holdout import FIGURE_2
from benchmarks.browser import chromium
from benchmarks.output import publish
from benchmarks.three_page import furnace, open_page, screenshot
from handoff.three import THREE_VERSION
from preintegrate.multiple_scattering import compensated_albedo
from tests.references.integration import reference_albedo_grid

MUS = (0.1, 0.3, 0.5, 0.7, 0.9, 1.0)
ROUGHNESS = (0.1, 0.3, 0.5, 0.7, 0.9)
GOLD = {"reflectivity": [0.944, 0.776, 0.373], "edge_tint": [0.998, 0.981, 0.751]}


def _materials(count: int | None) -> list[dict]:
    """name, exact curve, stock base colour and the package's options of each material."""
    presets = json.loads((Path(__file__).resolve().parents[1] / "luts" / "materials.json").read_text())["materials"]
    metals = [name for name, entry in presets.items() if entry["kind"] == "metal"][:count]
    materials = []
    for name in metals:
        material = material_from_mapping({"preset": name}, "sRGB")
        materials.append(
            {
                "name": name,
                "curve": material.curve,
                "color": material.curve(np.array(1.0)).tolist(),
                "basis": {"model": "coefficients", "coefficients": material_coefficients(name, "sRGB").tolist()},
            }
        )
    for name, described in (("Gold (r, g)", GOLD), ("Figure 2 (r, g)", FIGURE_2)):
        material = material_from_mapping({k: described[k] for k in ("reflectivity", "edge_tint")}, "sRGB")
        materials.append(
            {
                "name": name,
                "curve": material.curve,
                "color": list(described["reflectivity"]),
                "basis": {"model": "gulbrandsen", "edge": list(described["edge_tint"])},
            }
        )
    return materials


def _exact(curve) -> np.ndarray:
    """(len(ROUGHNESS) × len(MUS), 3) of the exact model: F̄_ss and E by quadrature, F_avg exact, compensated."""
    mu, roughness = np.meshgrid(MUS, ROUGHNESS)
    mu, alpha = mu.ravel(), roughness.ravel() ** 2
    single = reference_albedo_grid(lambda x: curve(x), mu, alpha)
    albedo = reference_albedo_grid(lambda x: np.ones((x.size, 1)), mu, alpha)[:, 0]
    nodes, weights = np.polynomial.legendre.leggauss(64)
    x = 0.5 * (nodes + 1.0)
    average = np.clip((0.5 * weights * 2.0 * x) @ curve(x), 0.0, 1.0)
    return compensated_albedo(single, np.clip(albedo, 0.0, 1.0), average)


def run(count: int | None, out: str | None) -> None:
    materials = _materials(count)
    cases = []
    for material in materials:
        for basis in (None, material["basis"]):
            for roughness in ROUGHNESS:
                for mu in MUS:
                    case = {"mu": mu, "roughness": roughness, "metalness": 1.0, "color": material["color"],
                            "physical": True}  # fmt: skip
                    if basis is not None:
                        case["basis"] = basis
                    cases.append(case)
    picture = None
    with chromium() as browser:
        page, _ = open_page(browser)
        rendered = furnace(page, cases).reshape(len(materials), 2, len(ROUGHNESS) * len(MUS), 3)
        if out is not None:
            shown = [m for m in materials if m["name"] in ("Figure 2 (r, g)", "Gold (r, g)")]
            spheres = [
                {"color": m["color"], "metalness": 1.0, "roughness": r, "physical": True, **extra}
                for m in shown
                for r in (0.28,)
                for extra in ({}, {"basis": m["basis"]})
            ]
            picture = screenshot(page, spheres, 256)
    rows, stock_all, basis_all = [], [], []
    for material, (stock, basis) in zip(materials, rendered):
        exact = _exact(material["curve"])
        stock_error, basis_error = np.abs(stock - exact), np.abs(basis - exact)
        stock_all.append(stock_error)
        basis_all.append(basis_error)
        rows.append(
            f"| {material['name']} | {stock_error.max():.2e} | {np.median(stock_error):.2e} | {basis_error.max():.2e} "
            f"| {np.median(basis_error):.2e} | {stock_error.max() / basis_error.max():.1f} |"
        )
    stock_all, basis_all = np.array(stock_all), np.array(basis_all)
    lines = [
        "# The three.js package inside three.js",
        "",
        f"three.js {THREE_VERSION} from npm in headless Chromium (SwiftShader), MeshPhysicalMaterial, a furnace "
        "(uniform white environment); |Δ| of the directional albedo with multiple scattering against the exact model "
        f"(exact Fresnel, independent quadrature), R, G, B at N·V ∈ {list(MUS)} and perceptual roughness ∈ "
        f"{list(ROUGHNESS)}. Stock: base colour = F0; the package: `applyFresnelBasis` (measured metals: their basis "
        "coefficients from `luts/materials.json`, linear sRGB; gold and Figure 2: Gulbrandsen's (r, g)). "
        "Command: `python -m benchmarks.three_package --out report/three.md`.",
        "",
        "| material | stock max | stock median | package max | package median | max ratio |",
        "|---|---|---|---|---|---|",
        *rows,
        f"| **all {len(materials)}** | {stock_all.max():.2e} | {np.median(stock_all):.2e} | {basis_all.max():.2e} | "
        f"{np.median(basis_all):.2e} | {stock_all.max() / basis_all.max():.1f} |",
        "",
        "The package's error is the basis' own (four terms; the Figure 2 material is its hard case) plus the half-float "
        "storage of its tables (at most 3e-4: `tests/luts/test_three.py`); stock three.js's is Schlick's curve from F0 "
        "alone (no edge colour) and its 16 × 16 DFG table.",
    ]
    if picture is not None:
        image = Path(out).with_name("three_spheres.png")
        image.write_bytes(picture)
        lines += [
            "",
            f"![Gold and the Figure 2 material, r = 0.28: stock three.js, then the package, each pair]({image.name})",
            "",
            f"`{image.name}`: left to right, gold (r, g) in stock three.js and with the package, then the Figure 2 "
            "material likewise (the package's green rim); three.js's RoomEnvironment, neutral tone mapping.",
        ]
    publish("\n".join(lines) + "\n", out)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--materials", type=int, default=None, help="only the first N measured metals")
    parser.add_argument("--out", default=None, help="Markdown file (default: print)")
    arguments = parser.parse_args(argv)
    run(arguments.materials, arguments.out)


if __name__ == "__main__":
    main()
