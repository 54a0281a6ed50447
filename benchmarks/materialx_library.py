"""MaterialX's environment light with and without the basis branch (issue 40), against the exact model and against
MaterialX's own FIS path.

MaterialX 1.39.5 from PyPI generates each document's GLSL; Mesa's llvmpipe runs it in a white furnace
(benchmarks/materialx_render.py: N·V from grazing to 1). What a pixel shows is MaterialX's image-based light:
F̄ × its energy compensation 1 + F(N·V) (1 − E) / E (Turquin 2019 eq. 16). The exact model is that with F̄ and E
integrated from the exact curve by an independent quadrature (tests/references). Compared: stock MaterialX's
prefiltered path (mx_ggx_dir_albedo: Schlick of F0, a fitted E), the basis branch (handoff.materialx.basis_branch),
MaterialX's FIS path (the exact Fresnel per sample, ``--samples`` of them) stock, and the same with the branch's E.

Documents: ``conductor_bsdf`` and ``standard_surface`` (metalness 1, Gulbrandsen's artistic IOR) for gold, the
Figure 2 material and three seeded (r, g); ``open_pbr_surface`` (base_metalness 1) for five F0 × F82-tint pairs;
perceptual roughness 0.2, 0.5, 0.8 (α = r²). |Δ| over R, G, B at 11 values of N·V from 0.04 to 1.

Run: ``.venv/bin/python -m benchmarks.materialx_library [--samples N] [--materials N] [--out FILE]`` (the report:
``--out report/materialx.md``).
"""

from __future__ import annotations

import argparse

import numpy as np

from basis.gulbrandsen import gulbrandsen_to_nk
from basis.storage import shipped_path
from basis.training.holdout import FIGURE_2
from benchmarks import materialx_render as render
from benchmarks.output import publish
from handoff.exr import read_lut
from handoff.materialx import ATLAS_UNIFORM, MATERIALX_VERSION, basis_branch
from tests.references.fresnel import fresnel_complex

ROUGHNESS = (0.2, 0.5, 0.8)


def _metals(count: int) -> list[tuple[str, np.ndarray, np.ndarray]]:
    rng = np.random.default_rng(40)
    metals = [
        ("gold", np.array([0.944, 0.776, 0.373]), np.array([0.998, 0.981, 0.751])),
        ("Figure 2", np.array(FIGURE_2["reflectivity"], dtype=float), np.array(FIGURE_2["edge_tint"], dtype=float)),
    ]
    metals += [(f"random {i}", rng.uniform(0.05, 0.95, 3), rng.uniform(0.0, 1.0, 3)) for i in range(3)]
    return metals[:count]


def _cases(count: int):
    """(model, material, build, exact curve, α) of every document."""
    cases = []
    for name, reflectivity, edge in _metals(count):
        eta, kappa = gulbrandsen_to_nk(reflectivity, edge)
        curve = lambda x, eta=eta, kappa=kappa: fresnel_complex(x[:, None], eta[None, :], kappa[None, :])  # noqa: E731
        for r in ROUGHNESS:
            cases.append(("conductor_bsdf", name, lambda e=eta, k=kappa, r=r: render.conductor(e, k, r * r), curve, r))
            builder = lambda g=reflectivity, e=edge, r=r: render.standard_surface(g, e, r)  # noqa: E731
            cases.append(("standard_surface", name, builder, curve, r))
    rng = np.random.default_rng(41)
    for i in range(count):
        f0, tint = rng.uniform(0.3, 0.98, 3), rng.uniform(0.0, 1.0, 3)
        for r in ROUGHNESS:
            builder = lambda f=f0, t=tint, r=r: render.open_pbr_surface(f, t, r)  # noqa: E731
            cases.append(("open_pbr_surface", f"F82 tint {i}", builder, render.f82_tint_curve(f0, tint), r))
    return cases


def run(samples: int, count: int, out: str | None) -> None:
    atlas = read_lut(shipped_path("fresnel_atlas_rgba.exr"))[0]
    textures = {ATLAS_UNIFORM: atlas}
    errors: dict[str, dict[str, list[float]]] = {}
    for model, _, build, curve, r in _cases(count):
        doc, node = build()
        exact = render.exact_environment_light(curve, r * r)
        stock = render.generate(doc, node)
        fis = render.generate(doc, node, "fis")
        rendered = {
            "stock (prefiltered)": render.furnace(stock),
            "basis branch": render.furnace(basis_branch(stock), textures=textures),
            "FIS, stock": render.furnace(fis, {"u_envRadianceSamples": samples}),
            "FIS, exact E": render.furnace(basis_branch(fis), {"u_envRadianceSamples": samples}, textures=textures),
        }
        for path, values in rendered.items():
            errors.setdefault(model, {}).setdefault(path, []).extend(np.abs(values[render.COMPARED] - exact).ravel())
    paths = ["stock (prefiltered)", "basis branch", "FIS, stock", "FIS, exact E"]
    lines = [
        "# MaterialX with the basis branch",
        "",
        f"MaterialX {MATERIALX_VERSION} from PyPI, its GLSL on Mesa's llvmpipe in a white furnace; |Δ| of the "
        "image-based light (F̄ × its energy compensation) against the exact model, R, G, B at 11 values of N·V and "
        f"perceptual roughness {list(ROUGHNESS)}; FIS with {samples} samples. Command: "
        "`python -m benchmarks.materialx_library --out report/materialx.md`.",
        "",
        "| document | " + " | ".join(f"{path} max / median" for path in paths) + " |",
        "|---|" + "---|" * len(paths),
    ]
    for model, by_path in errors.items():
        cells = [f"{np.max(by_path[p]):.2e} / {np.median(by_path[p]):.2e}" for p in paths]
        lines.append(f"| `{model}` | " + " | ".join(cells) + " |")
    lines += [
        "",
        "Conductors: gold, the Figure 2 material and three seeded Gulbrandsen (r, g) (`conductor_bsdf` through his "
        "(η, κ), `standard_surface` through MaterialX's `artistic_ior`); `open_pbr_surface`: five seeded F0 × F82 "
        "tint pairs. Stock MaterialX reduces a conductor to Schlick of its F0 and drops OpenPBR's F82 tint in its "
        "prefiltered path (MaterialX #1420, #2808); the branch's error is the basis' own for conductors and the "
        "Schlick table's interpolation for the F82 tint. MaterialX's FIS path evaluates the exact Fresnel per sample "
        "but weights it by the same energy compensation, whose fitted E alone puts it off by the 'FIS, stock' column; "
        "with the table's E it converges to the exact model.",
    ]
    publish("\n".join(lines) + "\n", out)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--samples", type=int, default=4096, help="FIS samples per pixel (default 4096)")
    parser.add_argument("--materials", type=int, default=5, help="materials per document kind (default 5)")
    parser.add_argument("--out", default=None, help="Markdown file (default: print)")
    arguments = parser.parse_args(argv)
    run(arguments.samples, arguments.materials, arguments.out)


if __name__ == "__main__":
    main()
