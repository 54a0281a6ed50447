"""The look-development page (issue 25): its screenshot, its agreement with the Python renderer and its frame times.

Run: ``.venv/bin/python -m benchmarks.view_page [--size S] [--samples N] [--repeats R] [--out FOLDER]`` (the report:
``--out report``, which writes ``report/view.md`` and README's screenshot ``report/view.png``). In headless Chromium
(Debian's, WebGL 2 on SwiftShader, the CPU; no GPU here), the page served by :func:`fresnel_lut.view.serving`:

1. **Screenshot**: the talk's Figure 2 material (Gulbrandsen r 0.44, g (0, 1, 0), r = √0.08) under the studio, the
   four pictures side by side once the reference holds ``--samples`` samples per pixel (the page's frame-time line
   is masked: it is the only thing that changes from run to run).
2. **Agreement**: each split-sum picture read back from its float target against :func:`fresnel_lut.render.
   render_split_sum` on the same half-float tables (max |Δ| / value over the sphere), and the page's
   ΔE2000 numbers of each mode against its reference.
3. **Frame time**: ``fresnelView.timeModes(R)``: each picture drawn R times, the batch ended by a one-texel
   ``readPixels`` (which waits for the draws), five rounds with the modes alternated, each mode's fastest round; ms
   per draw and the ratio to Schlick's. On SwiftShader these are CPU times: the ratios are what carries over.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from basis.storage import shipped_path, write_together
from benchmarks.browser import browser_page, chromium
from fresnel_lut import render
from fresnel_lut.view import page_files, serving
from handoff.exr import read_lut, stored_values

MODES = {"schlick": "Schlick split sum", "basis": "basis split sum", "multiple": "basis + multiple scattering"}


def measure(size: int, samples: int, repeats: int) -> dict:
    """The page's screenshot (PNG bytes), its pictures' agreement with the renderer, its ΔE numbers and frame times."""
    with serving(page_files()) as server, chromium(viewport=(1400, 1000)) as browser:
        url = f"http://127.0.0.1:{server.server_address[1]}/?size={size}&spp=16"
        page, messages = browser_page(browser)
        page.goto(url)
        page.evaluate(f"() => fresnelView.ready.then(() => fresnelView.settle({samples}))")
        numbers = page.evaluate("() => fresnelView.statistics()")
        pictures = {
            mode: np.array(page.evaluate(f"() => fresnelView.readImage('{mode}')")).reshape(size, size, 4)[::-1]
            for mode in MODES
        }
        renderer = page.evaluate("() => fresnelView.renderer")
        screenshot = page.screenshot(full_page=True, mask=[page.locator("#timing")], mask_color="#1b1b1d")
        timings = page.evaluate(f"() => fresnelView.timeModes({repeats})")
        errors = [text for kind, text in messages if kind in ("error", "pageerror")]
    half = {
        name: stored_values(read_lut(shipped_path(f"{name}.exr"))[0], half=True).astype(np.float64)
        for name in ("ggx_basis_rgba", "ggx_schlick_rgba")
    }
    figure2 = render.DEFAULT_SCENES["figure2"]("sRGB")
    want = render.render_split_sum(
        figure2, render.FIGURE2_ROUGHNESS, size, half["ggx_basis_rgba"], half["ggx_schlick_rgba"]
    )
    mask = render.sphere_geometry(size)[1]
    agreement = {}
    for mode, key in zip(MODES, ("schlick", "basis", "basis_multiple_scattering")):
        difference = np.abs(pictures[mode][..., :3] - want[key])[mask]
        agreement[mode] = float((difference / np.maximum(np.abs(want[key][mask]), 1e-2)).max())
    return {
        "screenshot": screenshot,
        "numbers": numbers,
        "agreement": agreement,
        "timings": timings,
        "renderer": renderer,
        "errors": errors,
        "size": size,
        "samples": samples,
        "repeats": repeats,
    }


def markdown(result: dict) -> str:
    size, timings = result["size"], result["timings"]
    lines = [
        "# The look-development page (issue 25)",
        "",
        f"Command: `python -m benchmarks.view_page --out report` (sphere {size} x {size}, reference "
        f"{result['samples']} samples per pixel, {result['repeats']} timed draws per picture). `fresnel-lut view` "
        "serves the page; headless Chromium with WebGL 2 on SwiftShader (the CPU) ran it here: "
        f"{result['renderer']}. Console errors: {len(result['errors'])}.",
        "",
        "![the page](view.png)",
        "",
        "| picture | max \\|page - Python\\| / value | max ΔE2000 vs the page's reference | mean ΔE2000 | ms per draw "
        "| vs Schlick |",
        "|---|---|---|---|---|---|",
    ]
    for mode, name in MODES.items():
        numbers = result["numbers"][mode]
        lines.append(
            f"| {name} | {result['agreement'][mode]:.1e} | {numbers['max']:.2f} | {numbers['mean']:.3f} | "
            f"{timings[mode]:.2f} | {timings[mode] / timings['schlick']:.2f}x |"
        )
    lines += [
        f"| reference (1 sample per pixel) | | | | {timings['reference']:.2f} | "
        f"{timings['reference'] / timings['schlick']:.2f}x |",
        "",
        "The Python side is `fresnel_lut.render.render_split_sum` on the shipped tables as the page's KTX2 stores them "
        "(half floats, subnormal halves written as 0: `handoff.exr.stored_values`); the differences are float32 "
        "and the GPU's bilinear weights (tests/fresnel_lut/test_view.py holds them to 3e-3 of the value). "
        "The ΔE2000 numbers are the report's measure (tone-mapped linear sRGB, "
        "`fresnel_lut.render.tone_map`) against the page's own Monte-Carlo reference, which still carries its noise "
        "at this sample count. Frame times are SwiftShader's (a CPU, 2 shared cores), fastest of five alternated rounds; "
        "every picture runs the same shader with all of its lights, so they differ by their Fresnel only.",
        "",
    ]
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--size", type=int, default=256, help="the sphere's pixels (default 256)")
    parser.add_argument("--samples", type=int, default=1024, help="reference samples per pixel (default 1024)")
    parser.add_argument("--repeats", type=int, default=10, help="timed draws per picture and round (default 10)")
    parser.add_argument("--out", type=Path, default=None, help="also write view.md and view.png into this folder")
    arguments = parser.parse_args(argv)
    result = measure(arguments.size, arguments.samples, arguments.repeats)
    text = markdown(result)
    print(text)
    if arguments.out is not None:
        arguments.out.mkdir(parents=True, exist_ok=True)
        write_together(
            [
                (arguments.out / "view.md", lambda path: path.write_text(text, encoding="utf-8")),
                (arguments.out / "view.png", lambda path: path.write_bytes(result["screenshot"])),
            ]
        )
    return 1 if result["errors"] else 0


if __name__ == "__main__":
    raise SystemExit(main())
