"""The README's Python example runs as written and its numbers agree with an independent evaluation."""

import re
from pathlib import Path

import numpy as np
import pytest

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_python_example_runs(monkeypatch, capsys, tmp_path):
    """Executes the first ```python block of README.md from an empty folder; the printed F̄ must
    equal Σ_k c_k · LUT_k recomputed here from the basis channels by quadrature (tolerance 1e-5:
    float32 storage of the LUT)."""
    block = re.search(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S).group(1)
    monkeypatch.chdir(tmp_path)  # from any folder: the example finds the shipped LUT itself
    namespace: dict = {}
    exec(compile(block, str(README), "exec"), namespace)
    from basis import material_coefficients
    from preintegrate.channels import basis_channels
    from preintegrate.quadrature import directional_albedo

    mu_o, roughness = (90 / 127) ** 2, 40 / 127  # the texel (j, i) = (40, 90) of the default grid
    channels = directional_albedo(basis_channels().functions, mu_o, roughness**2)
    expected = material_coefficients("Gold") @ channels
    printed = np.array([float(v) for v in re.findall(r"[-+]?\d*\.\d+(?:e[-+]?\d+)?", capsys.readouterr().out)])
    np.testing.assert_allclose(printed, expected, atol=1e-5)


def test_readme_offline_coefficient_maps_are_the_shaders_numbers():
    """README's maps solved at import (its second ```python block, run as written) are three RGBA float32 maps whose
    texels are the include's per-pixel solve of the same texels (its Python mirror, operation for operation) within
    float32 rounding."""
    from handoff.shaders import coefficients_per_pixel_gulbrandsen

    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    block = next(block for block in blocks if "coefficients_from_gulbrandsen(reflectivity" in block)
    namespace: dict = {}
    exec(compile(block, str(README), "exec"), namespace)
    per_pixel = coefficients_per_pixel_gulbrandsen(namespace["reflectivity"], namespace["edge_tint"])
    for channel, name in enumerate(("red", "green", "blue")):
        texture = namespace[name]
        assert texture.dtype == np.float32 and texture.shape == (*namespace["reflectivity"].shape[:2], 4)
        np.testing.assert_allclose(texture, per_pixel[..., channel, :], rtol=0, atol=1e-7)


# ---- issue 36 item 15: README's snippets, tables and conventions checked against what the build writes ----------
#: What README's GLSL snippets take as given: the engine's own uniforms and BRDF functions.
_GLSL_PRELUDE = """#version 330
{includes}
uniform sampler2D ggxBasisLut, basisLut, schlickLut, ltcLut, reflectivityMap, edgeTintMap, coefficientLut, curveLut;
uniform sampler2D coefficientsRed, coefficientsGreen, coefficientsBlue;
uniform vec2 uv;
uniform vec3 N, V, L, prefiltered, lightColor, worldPosition, lightCorner0, lightCorner1, lightCorner2, lightCorner3;
uniform float NdotV, perceptualRoughness, roughness;
uniform vec4 cR, cG, cB;
float D_GGX(float NdotH, float alpha) {{ return alpha; }}
float V_SmithGGX(float NdotV, float NdotL, float r) {{ return r; }}
out vec4 result;
void main() {{
    vec3 color = vec3(0.0);
{block}
    result = vec4(color, 1.0);
}}
"""


def test_readme_glsl_snippets_compile_against_the_shipped_includes(tmp_path):
    """Every ```glsl block of README compiles (glslangValidator, GLSL 3.30) after the include a build writes, with
    the engine's own names declared: a function renamed or dropped in the include fails here."""
    import shutil
    import subprocess

    from basis.storage import shipped_path
    from tests.conftest import gpu_missing

    glslang = shutil.which("glslangValidator")
    if glslang is None:
        gpu_missing("glslangValidator (Debian glslang-tools)")
    includes = shipped_path("fresnel_basis.glsl").read_text(encoding="utf-8")
    blocks = re.findall(r"```glsl\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    assert len(blocks) >= 4
    for index, block in enumerate(blocks):
        source = tmp_path / f"block{index}.frag"
        source.write_text(_GLSL_PRELUDE.format(includes=includes, block=block), encoding="utf-8")
        compiled = subprocess.run([glslang, str(source)], capture_output=True, text=True)
        assert compiled.returncode == 0, f"README's glsl block {index}:\n{block}\n{compiled.stdout}"


def _cells(row: str) -> list[str]:
    """A Markdown table row's cells: ``|`` splits, except escaped (``\\|``) or inside a code span."""
    cells, cell, code = [], "", False
    text = row.strip()
    text = text[1:] if text.startswith("|") else text
    text = text[:-1] if text.endswith("|") and not text.endswith("\\|") else text
    index = 0
    while index < len(text):
        character = text[index]
        if character == "\\" and index + 1 < len(text):
            cell += text[index : index + 2]
            index += 2
            continue
        if character == "`":
            code = not code
        if character == "|" and not code:
            cells.append(cell)
            cell = ""
        else:
            cell += character
        index += 1
    return cells + [cell]


@pytest.mark.parametrize("document", ["README.md", *sorted(p.name for p in (README.parent / "report").glob("*.md"))])
def test_markdown_tables_are_whole(document):
    """Every run of table lines is a header, its ``|---|`` line and rows of as many cells: README's engine table had a
    row cut off from it by a paragraph (rendered as text)."""
    path = README if document == "README.md" else README.parent / "report" / document
    lines, fenced = path.read_text(encoding="utf-8").splitlines(), False
    runs, current = [], []
    for number, line in enumerate(lines, 1):
        fenced ^= line.startswith("```")
        if not fenced and line.lstrip().startswith("|"):
            current.append((number, line))
        elif current:
            runs.append(current)
            current = []
    runs += [current] if current else []
    for run_lines in runs:
        (first, header), *rest = run_lines
        assert rest and re.fullmatch(r"\s*\|?(\s*:?-{3,}:?\s*\|)+\s*:?-{0,}:?\s*\|?\s*", rest[0][1]), (
            f"{document}:{first}: a table line without a header and |---| line under it: {header[:80]}"
        )
        width = len(_cells(header))
        for number, line in rest:
            assert len(_cells(line)) == width, f"{document}:{number}: {len(_cells(line))} cells, the header {width}"


#: (what README says, what the header of a table the build writes says): each statement of the texel conventions.
_CONVENTIONS = [
    ("column i ↔\n√μo = i/(W − 1)", "column i <-> sqrt(mu_o) = i / (width - 1)", "ggx_basis_rgba.exr"),
    ("row j ↔ perceptual roughness r = j/(H − 1) with GGX α = r²", "r = 0 + j * (1 - 0) / (height - 1)", None),
    ("row 0 is first in the\nfile", "row 0 first in the file", None),
    ("u = (x (W − 1) + 0.5)/W", "u = (sqrt(mu_o) * (width - 1) + 0.5) / width", None),
    ("row 0 is the mirror, r = 0, the last row r = 1", "r = 0 + j * (1 - 0) / (height - 1)", None),
    (
        "column 0 is grazing,\n  NdotV = 0, the last column NdotV = 1, the columns spaced in √NdotV",
        "sqrt(mu_o) = i",
        None,
    ),
    (
        "column i ↔ r = i/63, row j ↔ √(1 − μo) = j/63",
        "column i <-> perceptual roughness r = i / (size - 1)",
        "ggx_ltc.exr",
    ),
    ("column i ↔ r = i/63, row j ↔ √(1 − μo) = j/63", "row j <-> sqrt(1 - mu_o) = j / (size - 1)", "ggx_ltc.exr"),
]


def test_readme_conventions_are_what_the_build_writes(tmp_path):
    """Item 15: README said "row 0 is r = 0.5/H … u = NdotV" after the tables had moved to end-point rows and √μo
    columns (the Figure 2 material read 0.41 off). Each statement of a convention in README is paired with the text
    of the header a fresh build writes: both must hold."""
    from handoff.exr import read_lut
    from tests.conftest import run

    assert run(["build", "--size", "8", "--ltc", "--ltc-size", "4", "--out", tmp_path]) == 0
    text = README.read_text(encoding="utf-8")
    for said, written, table in _CONVENTIONS:
        assert said in text, f"README no longer says {said!r}"
        header = read_lut(tmp_path / (table or "ggx_basis_rgba.exr"))[1]
        assert written in header["convention"], f"the build's {table or 'basis'} header no longer says {written!r}"


def test_where_things_are_lists_every_module():
    """Issue 37 item 7: README's map named modules that had moved (``preintegrate/shaders.py``, ``exr.py``) and none
    of ``handoff``. Every product module appears in its package's block of *Where things are* (a subpackage's folder
    and its modules' file names), and every file name listed there exists in that package."""
    root = README.parent
    listing = re.search(r"## Where things are\n.*?```\n(.*?)```", README.read_text(encoding="utf-8"), re.S).group(1)
    blocks: dict[str, str] = {}
    current = None
    for line in listing.splitlines():
        top = re.match(r"(\w+)/\s", line)
        current = top.group(1) if top else current
        blocks[current] = blocks.get(current, "") + "\n" + line
    for package in ("basis", "preintegrate", "handoff", "fresnel_lut"):
        names = set(re.findall(r"\b\w+\.py\b|\b\w+/", blocks[package]))
        for path in sorted((root / package).rglob("*.py")):
            parts = path.relative_to(root / package).parts
            wanted = {f"{folder}/" for folder in parts[:-1]} | ({parts[-1]} if parts[-1] != "__init__.py" else set())
            assert wanted <= names, f"{package}/{'/'.join(parts)}: {sorted(wanted - names)} not in Where things are"
        for name in sorted(name for name in names if name.endswith(".py")):
            assert list((root / package).rglob(name)), f"Where things are names {package}/…/{name}, which is gone"


def test_readme_names_only_functions_the_include_defines():
    """Every include function README names (``fresnelBasisSplitSum``, and the table's ``…F82Tint`` shorthand for
    ``fresnelCoefficientsF82Tint``) is defined in the shipped GLSL include: a renamed function fails here even where
    no snippet calls it."""
    from basis.storage import shipped_path

    include = shipped_path("fresnel_basis.glsl").read_text(encoding="utf-8")
    defined = set(re.findall(r"^\w+ (fresnel\w+)\(", include, re.M))
    text = README.read_text(encoding="utf-8")
    named = set(re.findall(r"\b(fresnel[A-Z]\w*)\(", text)) | {
        f"fresnelCoefficients{name}" for name in re.findall(r"`…(\w+)\(", text)
    }
    assert len(named) >= 15 and named <= defined, sorted(named - defined)
