"""The README's Python example runs as written and its numbers agree with an independent evaluation."""

import re
from pathlib import Path

import numpy as np

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
    from preintegrate.shaders import coefficients_per_pixel_gulbrandsen

    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    block = next(block for block in blocks if "coefficients_from_gulbrandsen(reflectivity" in block)
    namespace: dict = {}
    exec(compile(block, str(README), "exec"), namespace)
    per_pixel = coefficients_per_pixel_gulbrandsen(namespace["reflectivity"], namespace["edge_tint"])
    for channel, name in enumerate(("red", "green", "blue")):
        texture = namespace[name]
        assert texture.dtype == np.float32 and texture.shape == (*namespace["reflectivity"].shape[:2], 4)
        np.testing.assert_allclose(texture, per_pixel[..., channel, :], rtol=0, atol=1e-7)
