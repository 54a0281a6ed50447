"""Issue 36 item 1: no text reaches a generated file as anything but one inert line.

A scene file's name, a command line or any header attribute goes into the comments of the generated shader includes
(GLSL, HLSL, WGSL), the C header's comment, EXR, KTX2 and PNG attributes and the scene report's title. Each passes
through :func:`basis.validation.safe_line`; these tests feed line breaks, comment ends, ``#``, backslashes, NUL and
non-Latin-1 text through every writer and read every file back with its own reader.
"""

from __future__ import annotations

import json
import shutil
import subprocess

import numpy as np
import pytest

from basis import default_basis
from basis.validation import safe_line
from handoff.exr import read_lut
from handoff.formats import FORMATS, payload_hash
from handoff.shaders import shader_includes
from handoff.tables import Table, write_tables
from tests.conftest import gpu_missing, read_png16, run
from tests.references.ktx2 import read_ktx2

#: Texts an attacker would choose: a function after a line break, a block comment's end, a preprocessor line, a
#: backslash that continues a GLSL comment, NUL, Unicode line and paragraph separators, a bidi override, non-Latin-1.
HOSTILE = [
    "x\nfloat injected() { return 42.0; }\n#pragma .toml",
    "a */ float injected = 1.0; /* b",
    "#define injected 1",
    "injected\\",
    "nul\x00injected",
    "line\u2028injected\u2029end",
    "\u202einjected fn \u91d1 Gr\u00fcn \U0001f600",
    "injected\r\nfn injected() {}",
]


@pytest.mark.parametrize("text", HOSTILE)
def test_safe_line_is_one_inert_line_that_reads_back(text):
    line = safe_line(text)
    assert line.isascii() and line.isprintable() and "/*" not in line and "*/" not in line
    assert not line.endswith("\\") and safe_line(line) == line
    assert line == text or json.loads(line) == text  # inert text stays as it is


def _comment_lines_only(text: str, marker: str = "injected") -> None:
    """Every line of a shader include that holds ``marker`` is a ``//`` comment that does not continue onto the next
    line; nothing else of the text holds it."""
    for line in text.splitlines():
        if marker in line:
            assert line.lstrip().startswith("//") and not line.endswith("\\"), line
    assert "\r" not in text and "\x00" not in text and text.isascii()


@pytest.mark.parametrize("text", HOSTILE)
def test_includes_carry_a_hostile_command_as_a_comment(text):
    for _, include in shader_includes(default_basis(), command=f"fresnel-lut scene {text}"):
        _comment_lines_only(include)


def _c_comment_lines_only(text: str) -> None:
    """The C header's one block comment holds the hostile texts, and it closes once, at its end."""
    comment, rest = text.split("*/", 1)
    assert comment.startswith("/*") and "injected" not in rest and "*/" not in rest and text.isascii()
    *lines, closing = comment.splitlines()[1:]
    assert closing == " " and all(line.startswith(" * ") for line in lines), lines


@pytest.mark.parametrize("text", HOSTILE)
def test_every_table_format_seals_a_hostile_attribute(tmp_path, text):
    """EXR, KTX2, PNG16 and the C header: the text is stored as its safe line, and each file's own hash verifies."""
    attributes = {"generator": f"fresnel-lut build {text}", "note": text, "channels": "R,G"}
    table = Table("ggx_hostile", np.full((3, 4, 2), 0.25), ("R", "G"), attributes)
    paths = {path.suffix: path for path in write_tables([table], tmp_path, list(FORMATS))}
    _, header = read_lut(paths[".exr"])  # read_lut recomputes the content hash
    assert header["note"] == safe_line(text)
    ktx = read_ktx2(paths[".ktx2"].read_bytes())
    stored = {key[len("fresnel:") :]: value for key, value in ktx["key_values"].items() if key.startswith("fresnel:")}
    assert stored["note"] == safe_line(text)
    assert stored["content_hash"] == payload_hash(stored, ktx["texels"].astype("<f4").tobytes())
    texels, chunks = read_png16(paths[".png"])
    stored = {key[len("fresnel:") :]: value for key, value in chunks.items()}
    samples = np.round(texels * 65535.0).astype(">u2")
    stacked = np.moveaxis(samples, 2, 0).reshape(-1, samples.shape[1]).tobytes()
    assert stored["note"] == safe_line(text) and stored["content_hash"] == payload_hash(stored, stacked)
    _c_comment_lines_only(paths[".h"].read_text(encoding="ascii"))


def test_a_png16_scale_edited_in_the_file_breaks_its_hash(tmp_path):
    """Item 12: the PNG's encoding (offset and scale) is sealed with the texels."""
    table = Table("ggx_scaled", np.linspace(-0.5, 2.0, 24).reshape(3, 4, 2), ("R", "G"), {"channels": "R,G"})
    (path,) = write_tables([table], tmp_path, ["png16"])
    texels, chunks = read_png16(path)
    stored = {key[len("fresnel:") :]: value for key, value in chunks.items()}
    stacked = np.moveaxis(np.round(texels * 65535.0).astype(">u2"), 2, 0).reshape(-1, texels.shape[1]).tobytes()
    assert stored["content_hash"] == payload_hash(stored, stacked)
    encoding = json.loads(stored["encoding"])
    encoding["scale"] = [2.0 * scale for scale in encoding["scale"]]
    assert payload_hash({**stored, "encoding": json.dumps(encoding)}, stacked) != stored["content_hash"]


#: The issue's reproducer, a scene file named with a line break, a function and a preprocessor line, and names with
#: a trailing backslash and non-Latin-1 text (a file name holds neither NUL nor the ``/`` of a comment end: the
#: library tests above feed those).
SCENE_NAMES = [HOSTILE[0], "float injected = 1.0; \\", "\u91d1 injected Gr\u00fcn\u2028.toml"]


@pytest.mark.slow
@pytest.mark.parametrize("name", SCENE_NAMES)
def test_a_scene_file_name_reaches_no_generated_file_as_code(tmp_path, name, capsys):
    scene = tmp_path / name
    scene.write_text('[[material]]\nname="g"\npreset="Gold"\nroughness=[0.3,0.5]\n', encoding="utf-8")
    out = tmp_path / "s1"
    assert run(["scene", "--out", str(out), "--format", ",".join(FORMATS), "--", str(scene)]) == 0
    written = {path.name: path for path in out.iterdir()}
    includes = [written[f"fresnel_basis_scene.{language}"] for language in ("glsl", "hlsl", "wgsl")]
    for include in includes:
        _comment_lines_only(include.read_text(encoding="utf-8"))
    for header in (path for path in written.values() if path.suffix == ".h"):
        _c_comment_lines_only(header.read_text(encoding="ascii"))
    title = (out / "scene_report.md").read_text(encoding="utf-8").splitlines()[0]
    assert title.startswith("# Scene build: ") and title.isascii() and "\n" not in title
    assert json.loads((out / "scene_coefficients.json").read_text(encoding="utf-8"))["scene"] == name
    for table in (path for path in written.values() if path.suffix == ".exr"):
        assert "injected" in read_lut(table)[1]["generator"]  # read back, its hash verified
    glslang = shutil.which("glslangValidator")
    if glslang is None:
        gpu_missing("glslangValidator (Debian glslang-tools)")
    source = tmp_path / "check.frag"
    source.write_text(
        "#version 330\n" + includes[0].read_text(encoding="utf-8") + "\nout vec4 c;\nvoid main() { c = vec4(0.0); }\n",
        encoding="utf-8",
    )
    compiled = subprocess.run([glslang, str(source)], capture_output=True, text=True)
    assert compiled.returncode == 0, compiled.stdout
