"""LUT files beside EXR (handoff/formats.py), read back by consumers that share no code with the writers:
16-bit PNG decoded by pypng, the C header compiled and run by gcc, KTX2 read by a reader typed from the
specification (tests/references/ktx2.py). Each round-trips to the EXR within its precision: the PNG
within half a 16-bit step of its stated scale, the header and KTX2 exactly (float32, or half as the
half EXR)."""

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from handoff.exr import read_lut
from tests.conftest import assert_one_line_error, read_png16, run


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    out = tmp_path_factory.mktemp("formats")
    assert run(["build", "--size", 16, "--format", "exr,png16,header", "--out", out]) == 0
    return out


@pytest.mark.parametrize("name", ["ggx_basis_rgba", "ggx_schlick_rgba", "ggx_albedo_average"])
def test_png16_round_trips_to_the_exr_within_its_step(built, name):
    table, header = read_lut(built / f"{name}.exr")
    texels, text = read_png16(built / f"{name}.png")
    encoding = json.loads(text["fresnel:encoding"])
    offset, scale = np.array(encoding["offset"]), np.array(encoding["scale"])
    decoded = offset + scale * texels
    np.testing.assert_allclose(decoded, table, rtol=0, atol=float(np.max(scale)) / 65535.0 / 2 + 1e-7)
    assert text["fresnel:convention"] == header["convention"] and text["fresnel:channels"] == header["channels"]


def test_png16_keeps_the_signed_channel(built):
    """The basis table's A (b̄3) is negative in places: a unorm path would clip it; the PNG's offset keeps it."""
    table, _ = read_lut(built / "ggx_basis_rgba.exr")
    assert table[..., 3].min() < -0.1
    texels, text = read_png16(built / "ggx_basis_rgba.png")
    encoding = json.loads(text["fresnel:encoding"])
    decoded = encoding["offset"][3] + encoding["scale"][3] * texels[..., 3]
    assert decoded.min() == pytest.approx(table[..., 3].min(), abs=1e-4)


def _default_read(reader: str, path: Path) -> np.ndarray:
    """The 16-bit samples (rows, columns) of a greyscale PNG as each library's plain, default call returns them."""
    if reader == "openimageio":
        import OpenImageIO

        return np.round(OpenImageIO.ImageBuf(str(path)).get_pixels()[..., 0].astype(np.float64) * 65535.0)
    if reader == "pillow":
        from PIL import Image

        with Image.open(path) as image:
            return np.asarray(image).astype(np.float64)
    import imageio.v3

    return np.asarray(imageio.v3.imread(path)).astype(np.float64)


@pytest.mark.parametrize("name", ["ggx_basis_rgba", "ggx_schlick_rgba", "ggx_albedo_average"])
@pytest.mark.parametrize("reader", ["openimageio", "pillow", "imageio"])
def test_png16_reads_the_same_in_the_loaders_engines_use(built, name, reader):
    """Issue 26 item 19: an RGBA PNG was premultiplied by its alpha (b̄3) in OpenImageIO's default read (errors 0.69,
    1.34), and Pillow and imageio decode 16-bit RGB(A) to 8 bits. The greyscale layout, channels stacked, reads as
    the same 16-bit samples in each library's default call as in pypng (the reference reader here)."""
    texels, _ = read_png16(built / f"{name}.png")
    height, width, channels = texels.shape
    want = np.round(texels * 65535.0).transpose(2, 0, 1).reshape(channels * height, width)
    got = _default_read(reader, built / f"{name}.png")
    assert got.shape == want.shape and np.array_equal(got, want), (reader, got.shape, np.abs(got - want).max())


def test_png16_stores_unit_channels_as_they_are(built):
    """Channels in [0, 1] keep offset 0 and scale 1 (README), also b̄0, Schlick's scale and E, which the quadrature
    takes 2e-8 past 1 at normal incidence (issue 26 item 19: they were given offsets of 0.31 and 0.019)."""
    from handoff.formats import PNG16_SLACK, png16_encoding

    for name, unit in (("ggx_basis_rgba", [0, 1, 2]), ("ggx_schlick_rgba", [0, 1, 2]), ("ggx_albedo_average", [0])):
        table, _ = read_lut(built / f"{name}.exr")
        encoding = json.loads(read_png16(built / f"{name}.png")[1]["fresnel:encoding"])
        for channel in unit:
            assert table[..., channel].min() >= -PNG16_SLACK and table[..., channel].max() <= 1 + PNG16_SLACK
            assert (encoding["offset"][channel], encoding["scale"][channel]) == (0.0, 1.0), (name, channel)
    offset, scale = png16_encoding(np.array([[[1.0 + 2e-8, -1e-8], [0.5, 0.5]]]))
    assert offset.tolist() == [0.0, 0.0] and scale.tolist() == [1.0, 1.0]
    offset, scale = png16_encoding(np.array([[[1.0 + 1e-4, 0.5]]]))
    assert scale[0] != 1.0  # beyond the slack: encoded with its own range


def test_c_header_compiles_and_holds_the_exr_values(built, tmp_path):
    compiler = shutil.which("gcc") or shutil.which("cc")
    if compiler is None:
        pytest.skip("no C compiler")
    program = tmp_path / "read.c"
    program.write_text(
        '#include <stdio.h>\n#include "ggx_basis_rgba.h"\n#include "ggx_schlick_rgba.h"\n'
        "int main(void) {\n"
        "  for (int k = 0; k < GGX_BASIS_RGBA_WIDTH * GGX_BASIS_RGBA_HEIGHT * GGX_BASIS_RGBA_CHANNELS; ++k)"
        ' printf("%.9g\\n", ggx_basis_rgba[k]);\n'
        '  for (int k = 0; k < 16 * 16 * GGX_SCHLICK_RGBA_CHANNELS; ++k) printf("%.9g\\n", ggx_schlick_rgba[k]);\n'
        "  return 0;\n}\n",
        encoding="utf-8",
    )
    executable = tmp_path / "read"
    subprocess.run(
        [compiler, "-std=c99", "-Wall", "-Werror", f"-I{built}", str(program), "-o", str(executable)],
        check=True,
        capture_output=True,
    )
    printed = np.array(
        subprocess.run([str(executable)], check=True, capture_output=True, text=True).stdout.split(), dtype=np.float64
    )
    expected = np.concatenate(
        [read_lut(built / "ggx_basis_rgba.exr")[0].ravel(), read_lut(built / "ggx_schlick_rgba.exr")[0].ravel()]
    )
    np.testing.assert_array_equal(printed.astype(np.float32), expected.astype(np.float32))


def test_formats_are_checked_before_the_work_and_png_alone_works(tmp_path, capsys):
    assert run(["build", "--size", 8, "--format", "png16,jpeg", "--out", tmp_path / "x"]) == 2
    assert_one_line_error(capsys.readouterr().err)
    assert not (tmp_path / "x").exists()
    assert run(["build", "--size", 8, "--format", "png16", "--out", tmp_path / "png"]) == 0
    assert sorted(path.name for path in (tmp_path / "png").iterdir()) == [
        "fresnel_basis.glsl",  # the shader includes of the basis go with every default build
        "fresnel_basis.hlsl",
        "fresnel_basis.wgsl",
        "ggx_albedo_average.png",
        "ggx_basis_rgba.png",
        "ggx_schlick_rgba.png",
    ]


@pytest.mark.parametrize("half", [False, True])
@pytest.mark.parametrize("name", ["ggx_basis_rgba", "ggx_schlick_rgba", "ggx_albedo_average"])
def test_ktx2_is_valid_and_round_trips_to_the_exr(tmp_path_factory, name, half):
    """KTX2 read by a reader typed from the specification (tests/references/ktx2.py: every offset,
    alignment, descriptor word and key/value rule): RGBA32F equals the float32 EXR exactly, RGBA16F the
    half EXR exactly (one rounding rule, exr.stored_values); three- and one-channel tables are padded (0, A = 1); the signed
    basis A survives."""
    from tests.references.ktx2 import read_ktx2

    out = tmp_path_factory.mktemp("ktx2")
    options = ["--half"] if half else []
    assert run(["build", "--size", 16, "--format", "exr,ktx2", "--out", out, *options]) == 0
    table, header = read_lut(out / f"{name}.exr")
    ktx = read_ktx2((out / f"{name}.ktx2").read_bytes())
    assert ktx["format"] == (97 if half else 109) and (ktx["height"], ktx["width"]) == table.shape[:2]
    channels = table.shape[2]
    np.testing.assert_array_equal(ktx["texels"][..., :channels], table)
    if channels < 4:  # padded: missing colours 0, alpha 1
        np.testing.assert_array_equal(ktx["texels"][..., channels:3], 0.0)
        np.testing.assert_array_equal(ktx["texels"][..., 3], 1.0)
    elif name == "ggx_basis_rgba":
        assert ktx["texels"][..., 3].min() < -0.1
    key_values = ktx["key_values"]
    assert key_values["KTXorientation"] == "rd" and key_values["KTXwriter"].startswith("fresnel-basis")
    assert key_values["fresnel:convention"] == header["convention"]
    assert key_values["fresnel:channels"] == header["channels"]


def test_ktx2_refuses_tables_it_cannot_hold():
    from basis.validation import ParameterError
    from handoff.formats import c_header, ktx2_bytes, png16_bytes

    with pytest.raises(ParameterError, match="NaN or inf"):
        ktx2_bytes(np.full((2, 2, 4), np.nan), {})
    with pytest.raises(ParameterError, match="1 to 4 channels"):
        ktx2_bytes(np.zeros((2, 2, 5)), {})
    for writer in (
        lambda table: ktx2_bytes(table, {}),
        lambda table: png16_bytes(table, {}),
        lambda table: c_header(table, "name", ["R"], {}),
    ):
        with pytest.raises(ParameterError, match="non-empty table"):
            writer(np.zeros((0, 2, 4)))
        with pytest.raises(ParameterError, match="table must be a real number"):
            writer("Gold")
    with pytest.raises(ParameterError, match="half-float range"):
        ktx2_bytes(np.full((2, 2, 4), 1e6), {}, half=True)
