"""Pictures: Fresnel curves and colour strips, and spheres rendered three ways with ΔE2000 heat maps.

Public objects: ``render_study``, ``render_markdown``, ``write_renders``.

For every default scene of :data:`fresnel_lut.render.DEFAULT_SCENES` (the talk's Figure 2 material,
Chromium, Gold, Beryllium; linear sRGB) and each of its roughnesses: the split sum with the shipped
Schlick LUT, with the shipped basis LUT, and a Monte-Carlo reference with the exact Fresnel curve; the
CIEDE2000 of each split-sum image against the reference (on the tone-mapped linear values, white = 1),
over the sphere's pixels: mean and 99th percentile; and the basis split sum compensated for multiple
scattering, with the ΔE2000 that compensation makes (the reference is single scattering). The reference's own noise is measured the same way,
between two references of different seeds, and reported beside.

Run: ``fresnel-lut render [--quick] [--out DIR]``.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from basis.angles import cos_theta
from basis.colorimetry import delta_E_2000
from basis.models.formulas import schlick_curve  # unchecked: an sRGB F0 may leave [0, 1]
from handoff.exr import write_luts
from handoff.shipped import shipped_tables

from ..render import (
    DEFAULT_SCENES,
    render_reference,
    render_split_sum,
    sphere_geometry,
    to_srgb8,
    tone_map,
)
from .figures import figure_png, pyplot

__all__ = ["render_markdown", "render_study", "write_renders"]

SPACE = "sRGB"
EXPOSURE = 1.0


def render_study(quick: bool = False, scenes=None, progress=None) -> dict:
    """Images and ΔE2000 statistics of every scene and roughness (module docstring)."""
    # lattice references: 256 spp are less noisy than 512 independent samples were (tests/fresnel_lut/test_render.py)
    size, samples = (128, 128) if quick else (256, 256)
    basis_lut, schlick_lut = shipped_tables()
    results = []
    names = list(DEFAULT_SCENES) if scenes is None else scenes
    for scene in names:
        material = DEFAULT_SCENES[scene](SPACE)
        roughnesses = material.roughness[:2] if quick else material.roughness
        for roughness in roughnesses:
            split = render_split_sum(material, roughness, size, basis_lut, schlick_lut)
            timed = render_split_sum(material, roughness, 512, basis_lut, schlick_lut)["seconds"]
            reference, _, seconds = render_reference(material, roughness, size, samples, seed=1)
            second, _, _ = render_reference(material, roughness, size, samples, seed=2)
            _, mask = sphere_geometry(size)
            shown = {key: tone_map(split[key], EXPOSURE) for key in ("schlick", "basis")}
            truth = tone_map(reference, EXPOSURE)
            maps = {key: delta_E_2000(shown[key], truth, SPACE) for key in shown}
            # what multiple-scattering compensation changes (the reference is single scattering)
            gain = delta_E_2000(tone_map(split["basis_multiple_scattering"], EXPOSURE), shown["basis"], SPACE)[mask]
            noise = delta_E_2000(tone_map(second, EXPOSURE), truth, SPACE)[mask]
            row = {
                "scene": scene,
                "material": material.name,
                "roughness": roughness,
                "size": size,
                "samples": samples,
                "reference_seconds": seconds,
                "split_sum_512_seconds": timed,
                "images": {
                    "schlick": split["schlick"],
                    "basis": split["basis"],
                    "reference": reference,
                    "basis_multiple_scattering": split["basis_multiple_scattering"],
                },
                "maps": maps,
                "mask": mask,
                "multiple_scattering_mean": float(gain.mean()),
                "multiple_scattering_p99": float(np.percentile(gain, 99)),
                "noise_mean": float(noise.mean()),
                "noise_p99": float(np.percentile(noise, 99)),
            }
            for key, values in maps.items():
                row[f"{key}_mean"] = float(values[mask].mean())
                row[f"{key}_p99"] = float(np.percentile(values[mask], 99))
            results.append(row)
            if progress is not None:
                progress(len(results), None)
    return {"rows": results, "quick": quick}


#: Line styles of ground truth, Schlick and the basis; colours of the R, G, B channels.
STYLES = ("-", "--", ":")
CHANNEL_COLOURS = ("tab:red", "tab:green", "tab:blue")


def _curves_figure(scene: str) -> bytes:
    """RGB curves and colour strips (0–90°, zoom 80–90°) of ground truth, Schlick and the basis."""
    from basis.eigenbasis import default_basis

    plt = pyplot()
    from matplotlib.lines import Line2D

    material = DEFAULT_SCENES[scene](SPACE)
    basis = default_basis()
    theta = np.linspace(0.0, 0.5 * np.pi, 901)
    truth = material.curve(cos_theta(theta))
    f0 = truth[0]
    curves = {
        "ground truth": truth,
        "Schlick": schlick_curve(cos_theta(theta)[:, None], f0),
        "basis": (material.coefficients @ basis.evaluate(theta).T).T,
    }
    figure, axes = plt.subplots(2, 2, figsize=(11, 6), gridspec_kw={"height_ratios": [3, 1.4]})
    for column, (low, high) in enumerate(((0.0, 90.0), (80.0, 90.0))):
        plot = axes[0, column]
        degrees = np.degrees(theta)
        for (label, values), style in zip(curves.items(), STYLES):
            # thick to thin, so that equal channels (the Figure 2 material's R and B) both stay visible
            for channel, colour, width in zip(range(3), CHANNEL_COLOURS, (2.8, 2.0, 1.2)):
                plot.plot(degrees, values[:, channel], style, color=colour, lw=width)
        handles = [Line2D([], [], color="0.25", linestyle=style, label=label) for label, style in zip(curves, STYLES)]
        handles += [
            Line2D([], [], color=colour, lw=width, label=f"{name} channel")
            for name, colour, width in zip("RGB", CHANNEL_COLOURS, (2.8, 2.0, 1.2))
        ]
        above = [name for name, channel in zip("RGB", truth.T) if np.max(channel) > 1.0 + 1e-6]
        if above:  # a reflectance above 1: the colour lies outside the working space's gamut
            plot.axhline(1.0, color="0.6", lw=0.8)
            plot.text(
                0.99,
                0.02,
                f"{', '.join(above)} above 1: outside the linear {SPACE} gamut (strips clip it)",
                transform=plot.transAxes,
                ha="right",
                va="bottom",
                fontsize=7.5,
                color="0.3",
            )
        plot.set_xlim(low, high)
        plot.set_xlabel("angle of incidence (degrees)")
        plot.set_ylabel(f"reflectance (linear {SPACE})")

        inside = (degrees >= low) & (degrees <= high)
        strips = np.stack([to_srgb8(np.clip(values[inside], 0.0, 1.0)) for values in curves.values()])
        axes[1, column].imshow(np.repeat(strips, 12, axis=0), aspect="auto", extent=(low, high, 0, 3 * 12))
        axes[1, column].set_yticks([6 + 12 * k for k in range(3)], list(curves)[::-1])
        axes[1, column].set_xlabel("colour strips, degrees")
    figure.suptitle(f"{material.name}: Fresnel curves (solid: ground truth; dashed: Schlick; dotted: basis)")
    figure.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 0.955), ncol=6, fontsize=8, frameon=False)
    figure.tight_layout(rect=(0, 0, 1, 0.92))
    return figure_png(figure)


def _spheres_figure(rows: list[dict]) -> bytes:
    plt = pyplot()
    figure, axes = plt.subplots(len(rows), 6, figsize=(18, 3.1 * len(rows)), squeeze=False)
    limit = max(3.0, max(float(np.percentile(row["maps"]["schlick"][row["mask"]], 99)) for row in rows))
    for line, row in zip(axes, rows):
        panels = [
            ("split sum, Schlick LUT", row["images"]["schlick"]),
            ("split sum, basis LUT", row["images"]["basis"]),
            (f"reference, {row['samples']} spp", row["images"]["reference"]),
        ]
        for axis, (title, image) in zip(line[:3], panels):
            axis.imshow(to_srgb8(tone_map(image, EXPOSURE)))
            axis.set_title(f"{title}\n{row['material']}, r = {row['roughness']:.2f}", fontsize=8)
        line[5].imshow(to_srgb8(tone_map(row["images"]["basis_multiple_scattering"], EXPOSURE)))
        line[5].set_title(
            f"basis LUT + multiple scattering (Kulla–Conty)\nΔE2000 to single: mean "
            f"{row['multiple_scattering_mean']:.2f}, p99 {row['multiple_scattering_p99']:.2f}",
            fontsize=8,
        )
        for axis, key in zip(line[3:5], ("schlick", "basis")):
            shown = np.where(row["mask"], row["maps"][key], np.nan)
            heat = axis.imshow(shown, cmap="magma", vmin=0.0, vmax=limit)
            axis.set_title(f"ΔE2000 {key}: mean {row[f'{key}_mean']:.2f}, p99 {row[f'{key}_p99']:.2f}", fontsize=8)
            figure.colorbar(heat, ax=axis, fraction=0.046)
        for axis in line:
            axis.set_xticks([])
            axis.set_yticks([])
    figure.tight_layout()
    return figure_png(figure)


def render_markdown(result: dict) -> str:
    lines = [
        (
            "| scene | roughness | Schlick ΔE2000 mean / p99 | basis ΔE2000 mean / p99 | reference noise mean / p99 "
            "| multiple scattering ΔE2000 mean / p99 | reference | 512² split sum |"
        ),
        "|---|---|---|---|---|---|---|---|",
    ]
    for row in result["rows"]:
        lines.append(
            f"| {row['material']} | {row['roughness']:.3f} | {row['schlick_mean']:.2f} / {row['schlick_p99']:.2f} "
            f"| {row['basis_mean']:.2f} / {row['basis_p99']:.2f} | {row['noise_mean']:.2f} / {row['noise_p99']:.2f} "
            f"| {row['multiple_scattering_mean']:.2f} / {row['multiple_scattering_p99']:.2f} "
            f"| {row['size']}², {row['samples']} spp, {row['reference_seconds']:.1f} s "
            f"| {row['split_sum_512_seconds']:.2f} s |"
        )
    return "\n".join(lines) + "\n"


def write_renders(out, quick: bool = False, progress=None) -> dict:
    """PNGs (curves, spheres and heat maps per scene), linear EXRs beside them, and ``renders.md``."""
    out = Path(out)
    started = time.perf_counter()
    result = render_study(quick=quick, progress=progress)
    # every picture, image and the Markdown are one transaction: Ctrl-C or a full disk leaves the folder as it was
    figures, items = {}, []
    for scene in dict.fromkeys(row["scene"] for row in result["rows"]):
        rows = [row for row in result["rows"] if row["scene"] == scene]
        figures[out / f"{scene}_curves.png"] = _curves_figure(scene)
        figures[out / f"{scene}_spheres.png"] = _spheres_figure(rows)
        for row in rows:
            for key, image in row["images"].items():
                items.append(
                    (
                        out / f"{scene}_r{row['roughness']:.2f}_{key}.exr",
                        image,
                        ("R", "G", "B"),
                        {
                            "content": f"{key} render of {row['material']} at roughness {row['roughness']:.4f}, linear {SPACE}",
                            "samples": str(row["samples"]) if key == "reference" else "split sum",
                        },
                    )
                )
    exrs = write_luts(
        items,
        extra_writers=[
            (path, lambda temporary, data=data: temporary.write_bytes(data)) for path, data in figures.items()
        ],
        texts=[
            (
                out / "renders.md",
                (
                    f"# Renders{' (quick)' if quick else ''}\n\nMade by `fresnel-lut render{' --quick' if quick else ''}`; "
                    "ΔE2000 of each split-sum image against the Monte-Carlo reference over the sphere, on tone-mapped "
                    f"linear {SPACE} (white = 1). Reference noise: ΔE2000 between two references of different seeds. "
                    "Multiple scattering: ΔE2000 that Kulla–Conty compensation (Fdez-Agüera's form, F_avg from the basis) "
                    "adds to the basis split sum; the reference is single scattering, so it is a change, not an error.\n\n"
                    + render_markdown(result)
                ),
            )
        ],
    )
    result["pngs"], result["exrs"], result["markdown"] = list(figures), exrs, out / "renders.md"
    result["seconds"] = time.perf_counter() - started
    return result
