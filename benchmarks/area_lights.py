"""Area lights (issue 24): the LTC fit against the public tables, and a rectangular light's error split by source.

Run: ``.venv/bin/python -m benchmarks.area_lights [--size S] [--nodes N] [--three VERSION] [--out FILE]`` (the
report: ``--out report/area_lights.md``, which also writes ``report/area_lights.png``). Sections:

1. **Fit**: the wall-clock time of the shipped table's two fits and its per-texel choice
   (:func:`preintegrate.ltc_choice.fit_area_ltc`, 64 × 64, this machine; one run) and their lobe error
   ½∫|f̂ − D| dω per texel (max, mean).
2. **Peers**: the same lobe error for three.js's LTC table (npm ``three``, ``examples/jsm/lights/
   RectAreaLightTexturesLib.js`` ``LTC_MAT_1``, 64 × 64, from the public ``ltc_code`` fit) and for ours, at 3000
   seeded random (μo, r), each read by bilinear lookup. Both fit the same BRDF (GGX with the height-correlated G2:
   ``ltc_code``'s ``brdf_ggx.cpp``) on the same axes (u = r, v = √(1 − μo), end points on texel centres) and
   packing, so the comparison is like for like. ``npm pack`` fetches the package; without npm the section says so.
3. **Rectangular light**: spheres under the renderer's soft box (``fresnel_lut.render.RECT_LIGHT``), the Figure 2
   material, gold, chromium and beryllium (ACEScg), the error split into its three sources, as max and mean
   ΔE2000 over the lit pixels (tone-mapped as the renders are): the **LTC's shape** (the LTC with the exact curve
   through the include's factorisation, E mix(F̃, F̄ / E, w), :func:`fresnel_lut.render.render_rect_light`
   against the reference: the exact BRDF and curve over the light's area, ``tests/references/area_light.py``,
   Gauss-Legendre), the **basis' Fresnel** (``fresnelBasisRectLight`` against that) and **Schlick's** (LTC × Schlick
   against that). Target: the basis' Fresnel part at the lit pixels (over the LTC integral: w ΔF̄ + (1 − w) E ΔF̃,
   issue 41's blend) no larger than the larger of its own errors for the material: the split sum's
   (max |F̄_basis − F̄_exact| over the table at that roughness) and F̃'s (max E |F̃_basis − F̃_exact| over every V·H and
   r' from 0 to that roughness, F̃ the curve averaged over a GGX lobe of roughness r' at V·H).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from basis.colorimetry import delta_E_2000
from basis.storage import shipped_path, write_together
from benchmarks.area_light_set import three_tables
from fresnel_lut.render import DEFAULT_SCENES, RECT_LIGHT, render_rect_light, sphere_geometry, to_srgb8, tone_map
from handoff.exr import read_lut
from handoff.shaders import rect_light_punctual
from handoff.shipped import BASIS_LUT, LTC_LUT, SCHLICK_LUT
from preintegrate.ggx import roughness_to_alpha
from preintegrate.ltc import fit_ltc, ltc_grid, smoothed_fresnel, stored_lobe_error
from preintegrate.ltc_choice import (
    CHOICE_NODES,
    CHOICE_ROUGHNESS_MIN,
    free_texels,
    per_texel_fit,
    training_lights,
)
from preintegrate.lut import lut_lookup
from preintegrate.quadrature import directional_albedo
from tests.references.area_light import rect_light_reference

SPACE = "ACEScg"
EXPOSURE = 1.0
RADIANCE = 4.0
ROUGHNESS = {"figure2": 0.2828, "gold": 0.3, "chromium": 0.3, "beryllium": 0.6}
#: The fits timed and compared: the shipped table takes per texel "mean" or "chi-square" (preintegrate.ltc_choice).
FITS = {"mean": {}, "free": {"axis": "free"}, "chi-square": {"axis": "free", "weighting": "chi-square"}}
MEAN_AXIS_FIT = "mean-axis fit (the public fit's method; shipped before)"
#: The choice's quadrature nodes per light axis, as shipped and doubled (its convergence).
CHOICE_NODES_PAIR = (CHOICE_NODES, 2 * CHOICE_NODES)


def three_table(version: str) -> np.ndarray | str:
    """three.js's ``LTC_MAT_1`` (64, 64, 4), rows √(1 − μo), columns r, entries (m00, m20, m02, m22) as its shader's
    ``mat3(vec3(t.x, 0, t.y), …)`` reads them (:func:`benchmarks.area_light_set.three_tables`); or why it could not be
    had."""
    tables = three_tables(version)
    return tables if isinstance(tables, str) else tables[0]


def choice_convergence(mean, free, chosen) -> str:
    """A sentence: where the per-texel choice between the fits ``mean`` and ``free`` (preintegrate.ltc.LtcFit),
    ``chosen`` with its own quadrature nodes over each training light (:func:`preintegrate.ltc_choice.free_texels`),
    changes with twice the nodes."""
    finer = free_texels(mean.inverse, free.inverse, mean.grid, training_lights(), CHOICE_NODES_PAIR[1])
    changed = chosen != finer
    roughness = mean.grid.roughness
    where = f"all at r ≤ {roughness[np.nonzero(changed.any(axis=0))[0]].max():.3f}" if changed.any() else "none"
    return (
        f"With {CHOICE_NODES_PAIR[1]}² nodes over each training light instead of {CHOICE_NODES_PAIR[0]}², the choice "
        f"differs at {int(changed.sum())} texels, {where} (the choice stops at r = {CHOICE_ROUGHNESS_MIN:g})."
    )


def peer_lines(tables: dict[str, np.ndarray]) -> list[str]:
    grid = ltc_grid(64)
    rng = np.random.default_rng(24)
    mu_o, roughness = rng.uniform(0.0, 1.0, 3000), rng.uniform(0.0, 1.0, 3000)
    lines = [
        "| table | mean | median | 90th percentile | 99th percentile |",
        "|---|---|---|---|---|",
    ]
    for name, table in tables.items():
        error = stored_lobe_error(grid.lookup(table, mu_o, roughness), mu_o, roughness)
        p50, p90, p99 = np.percentile(error, [50, 90, 99])
        lines.append(f"| {name} | {error.mean():.4f} | {p50:.4f} | {p90:.4f} | {p99:.4f} |")
    return lines + [""]


def _reference(material, roughness: float, size: int, nodes: int) -> np.ndarray:
    normals, mask = sphere_geometry(size)
    view = np.broadcast_to([0.0, 0.0, 1.0], normals.shape)
    image = np.zeros(normals.shape)
    for row in range(size):
        image[row] = RADIANCE * rect_light_reference(
            normals[row], view[row], normals[row], RECT_LIGHT, roughness_to_alpha(roughness), material.curve, nodes
        )
    image[~mask] = 0.0
    return image


def light_rows(size: int, nodes: int, others: dict[str, np.ndarray]):
    """Per material: (name, r, {error source: (max, mean) dE}, basis ΔF̄ at the lit pixels, own split-sum error,
    own direct-light error E F);
    the LTC-shape error also with each of ``others`` (other LTC tables under the same light)."""
    ltc, basis, schlick = (read_lut(shipped_path(name))[0] for name in (LTC_LUT, BASIS_LUT, SCHLICK_LUT))
    rows, pictures = [], []
    for key, make in DEFAULT_SCENES.items():
        material, roughness = make(SPACE), ROUGHNESS[key]
        images = render_rect_light(material, roughness, size, ltc, basis, schlick, radiance=RADIANCE)
        reference = _reference(material, roughness, size, nodes)
        others_images = {
            name: render_rect_light(material, roughness, size, table, basis, schlick, radiance=RADIANCE)
            for name, table in others.items()
        }
        # one set of pixels for every table: where the reference or any LTC sees the light
        lit = (images["ltc"] > 1e-4) | (np.max(reference, axis=-1) > 1e-4 * RADIANCE)
        for other in others_images.values():
            lit |= other["ltc"] > 1e-4
        shown = {
            name: tone_map(image, EXPOSURE)
            for name, image in (("reference", reference), *images.items())
            if name != "ltc"
        }
        maps = {
            "LTC shape": delta_E_2000(shown["exact"], shown["reference"], SPACE),
            "basis Fresnel": delta_E_2000(shown["basis"], shown["exact"], SPACE),
            "Schlick Fresnel": delta_E_2000(shown["schlick"], shown["exact"], SPACE),
        }
        for name, other in others_images.items():  # the LTC shape of another table under the same light, exact F̄
            maps[name] = delta_E_2000(tone_map(other["exact"], EXPOSURE), shown["reference"], SPACE)
        seen = images["ltc"] > 1e-4
        integral = np.where(seen, images["ltc"], 1.0)[..., None]
        at_pixels = float(np.max(np.abs(images["basis"] - images["exact"])[seen] / (RADIANCE * integral[seen])))
        mu = np.linspace(0.0, 1.0, 129)[1:]
        exact = directional_albedo(material.curve, mu, roughness_to_alpha(roughness), workers=1)
        terms = lut_lookup(basis, mu, roughness)
        own = float(np.max(np.abs(terms @ material.coefficients.T - exact)))
        # the blend's other factor, E F̃, as the include reads F̃ (the basis table at (V·H, r')), at any V·H and r' ≤ r
        cosine, spread = (
            axis.ravel() for axis in np.meshgrid(np.linspace(0.0, 1.0, 257), np.linspace(0.0, roughness, 5))
        )
        coefficients = np.broadcast_to(material.coefficients, cosine.shape + material.coefficients.shape)
        smoothed = rect_light_punctual(basis, coefficients, cosine, spread=spread)
        direct = smoothed - smoothed_fresnel(material.curve, cosine, spread, workers=1)
        own_direct = float(terms[:, 0].max() * np.max(np.abs(direct)))
        errors = {name: (m[lit].max(), m[lit].mean()) for name, m in maps.items()}
        rows.append((material.name, roughness, errors, at_pixels, own, own_direct))
        pictures.append((material.name, roughness, shown, maps))
    return rows, pictures


def figure(pictures):
    from fresnel_lut.report.figures import figure_png, pyplot

    plt = pyplot()
    columns = ["reference", "exact", "basis", "schlick", "LTC shape", "basis Fresnel", "Schlick Fresnel"]
    titles = [
        "reference",
        "LTC x exact Fbar",
        "LTC x basis",
        "LTC x Schlick",
        "dE: LTC shape",
        "dE: basis Fresnel",
        "dE: Schlick Fresnel",
    ]
    fig, axes = plt.subplots(len(pictures), len(columns), figsize=(2.0 * len(columns), 2.1 * len(pictures)))
    for line, (name, roughness, shown, maps) in zip(axes, pictures):
        for axis, column, title in zip(line, columns, titles):
            if column in maps:
                image = axis.imshow(maps[column], vmin=0.0, vmax=5.0, cmap="magma")
            else:
                axis.imshow(to_srgb8(shown[column]))
            axis.set_xticks([])
            axis.set_yticks([])
            axis.set_title(title, fontsize=7)
        line[0].set_ylabel(f"{name}\nr = {roughness:.2f}", fontsize=7)
    fig.colorbar(image, ax=axes, shrink=0.6, label="dE2000 (0-5)")
    return figure_png(fig)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=96, help="sphere image size (default 96)")
    parser.add_argument(
        "--nodes", type=int, default=96, help="reference Gauss-Legendre nodes per light axis (default 96)"
    )
    parser.add_argument(
        "--three", default="0.170.0", help="three.js version whose LTC table is compared ('none': skip the peers)"
    )
    parser.add_argument("--ltc-size", type=int, default=64, help="size of the timed fit (default 64, the shipped one)")
    parser.add_argument("--out", type=Path, default=None, help="also write the Markdown (and the PNG beside it) here")
    arguments = parser.parse_args(argv)
    three = "not asked for (--three none)" if arguments.three == "none" else three_table(arguments.three)
    timings, fits = {}, {}
    grid = ltc_grid(arguments.ltc_size)
    for name, options in FITS.items():
        started = time.perf_counter()
        fits[name] = fit_ltc(grid, **options)
        timings[name] = time.perf_counter() - started
    started = time.perf_counter()
    preferred = free_texels(fits["mean"].inverse, fits["chi-square"].inverse, grid, training_lights(), CHOICE_NODES)
    fits["shipped"] = per_texel_fit(fits["mean"], fits["chi-square"], preferred=preferred)
    timings["choice"] = time.perf_counter() - started
    free_share = float(np.mean(np.all(fits["shipped"].inverse == fits["chi-square"].inverse, axis=-1)))
    convergence = choice_convergence(fits["mean"], fits["chi-square"], preferred)
    shipped = read_lut(shipped_path(LTC_LUT))[0]
    difference = (
        float(np.max(np.abs(fits["shipped"].inverse.astype(np.float32) - shipped)))
        if fits["shipped"].inverse.shape == shipped.shape
        else np.inf
    )
    others = {}
    if arguments.ltc_size == 64:  # issue 41's study (benchmarks.area_light_set): each fit alone, and its glow if any
        others[MEAN_AXIS_FIT] = fits["mean"].inverse
        others["free-axis fit"] = fits["free"].inverse
        others["free-axis chi-square fit"] = fits["chi-square"].inverse
    if not isinstance(three, str):
        others[f"three.js {arguments.three}"] = three
    lines = [
        "# Area lights: linearly transformed cosines with the basis Fresnel (issue 24)",
        "",
        f"Command: `python -m benchmarks.area_lights --out report/area_lights.md` (sizes {arguments.size}, "
        f"{arguments.nodes}^2 reference nodes).",
        "",
        "## The fit",
        "",
        f"`fit_area_ltc()` ({arguments.ltc_size} x {arguments.ltc_size}, height-correlated GGX; "
        "`preintegrate.ltc_choice`): per texel the mean-axis L2 fit (the LTC's axis on the lobe's mean direction, "
        f"the public fit's method; {timings['mean']:.1f} s wall clock on this machine, one run) or the fit with M's "
        f"four entries free in chi-square ({timings['chi-square']:.1f} s), whichever holds the lobe better over "
        f"seeded training lights (the choice {timings['choice']:.1f} s; {free_share:.0%} "
        f"of the texels take the free fit); against the shipped table, max |Δ| {difference:.1e} in float32 (0: the "
        "same bits; `fresnel-lut build --ltc` writes it with numpy's and OpenBLAS' kernels pinned, "
        "`fresnel_lut.kernels`, and this process runs with the CPU's own, whose last bits may differ). Lobe error "
        "(half the L1 distance between the LTC and the normalised cosine-weighted lobe, 0: the same, 1: disjoint) per "
        f"texel: max {fits['shipped'].error.max():.3f}, mean {fits['shipped'].error.mean():.4f}; the mean-axis fit "
        f"alone max {fits['mean'].error.max():.3f}, mean {fits['mean'].error.mean():.4f}; with M's four entries free "
        f"in L2 (`fit_ltc(axis='free')`, {timings['free']:.1f} s) max {fits['free'].error.max():.3f}, mean "
        f"{fits['free'].error.mean():.4f}. They grow towards grazing views at mid roughness, where the lobe is least "
        f"like a transformed cosine. {convergence}",
        "",
        "## Against the public tables",
        "",
        "Lobe error at 3000 seeded random (mu_o, r), bilinear lookups, the same BRDF, axes and packing"
        + ("" if not isinstance(three, str) else f" (three.js not measured: {three})")
        + ":",
        "",
        *peer_lines({"this project (ggx_ltc, shipped)": shipped.astype(np.float64), **others}),
        "## A rectangular light, its error by source",
        "",
        "dE2000 over the lit pixels (where the reference, or the LTC integral of any table compared, exceeds 1e-4), "
        "max / mean. 'own split-sum error' is max |Fbar_basis - "
        "Fbar_exact| over the table's view angles at that roughness; 'own direct-light error' max E |F~_basis - "
        "F~_exact| over every V.H and r' from 0 to that roughness, F~ the curve averaged over a GGX lobe of roughness "
        "r' seen at V.H as the include reads it (the basis table at (V.H, r'), over its albedo there; r' = 0 its "
        "mirror row, F itself) and E the table's largest at that roughness; 'at the lit pixels' the Fresnel part as "
        "the area light carries it (divided by the LTC integral): w dFbar + (1 - w) E dF~, issue 41's blend of the split sum with the punctual limit, w the "
        "share of the lobe the light covers, so its target is at most the larger of the two own errors (issue 24's "
        "was the split sum's alone, from before the blend). "
        "The last columns: the LTC's shape error with the other tables under the same light. Every table's integral "
        "(three.js's too) is taken toward the lobe's punctual limit as the include takes the shipped one's "
        "(`fresnelLtcRectVector`, report/area_light_set.md).",
        "",
        "| material | r | LTC shape | basis Fresnel | Schlick Fresnel | basis dF at the lit pixels | own split-sum "
        "error | own direct-light error |" + "".join(f" LTC shape, {name} |" for name in others),
        "|---|---|---|---|---|---|---|---|" + "---|" * len(others),
    ]
    rows, pictures = light_rows(arguments.size, arguments.nodes, others)
    for name, roughness, errors, at_pixels, own, own_direct in rows:
        cells = " | ".join(
            f"{errors[k][0]:.2f} / {errors[k][1]:.3f}" for k in ("LTC shape", "basis Fresnel", "Schlick Fresnel")
        )
        extra = "".join(f" {errors[k][0]:.2f} / {errors[k][1]:.3f} |" for k in others)
        lines.append(f"| {name} | {roughness:.2f} | {cells} | {at_pixels:.2e} | {own:.2e} | {own_direct:.2e} |{extra}")
    if "free-axis fit" in others:
        lines += [
            "",
            "Why the shipped table takes the free fit only where training lights prefer it: with the four entries "
            "free the lobe error is lower, but at some grazing views (the sphere's silhouette, here the upper-left "
            "one facing the soft box) that fit spreads a thin layer of the LTC over the back-scattering half of the "
            "hemisphere, where the lobe has almost nothing: a faint rim on glossy spheres under a light on the "
            "viewer's side (the free fits' max dE above). On the mean axis the LTC's support is the half-space "
            "facing the lobe, as in the public fit, but it has no density on the viewer's side, where a rough lobe "
            "still reflects (report/area_light_set.md). The training lights keep the mean-axis fit where the free "
            "one glows.",
        ]
    lines += [
        "",
        "![spheres under the rectangular light and the dE maps of each error source](area_lights.png)",
        "",
        "Left to right: the reference, the LTC with the exact curve, with the basis, LTC x Schlick, then dE2000 maps "
        "(0-5) of the LTC's shape, the basis' Fresnel and Schlick's Fresnel.",
    ]
    text = "\n".join(lines) + "\n"
    print(text)
    if arguments.out is not None:
        png = figure(pictures)
        picture = arguments.out.with_suffix(".png")
        write_together(
            [
                (arguments.out, lambda path: path.write_text(text, encoding="utf-8")),
                (picture, lambda path: path.write_bytes(png)),
            ]
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
