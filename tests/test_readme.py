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
