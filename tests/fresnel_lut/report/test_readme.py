"""`fresnel-lut report --quick`: one run writes the tables, the plots and the targets, atomically."""

import re

import pytest

from fresnel_lut.cli import main


@pytest.mark.slow
def test_quick_report(tmp_path, capsys):
    """The quick report writes README.md with the machine, the targets and the four studies, and two PNG plots;
    the LUT target row of study 1 holds a finite error for the shipped schedule (compared with the quadrature at
    order 64, independent of the schedule's node counts)."""
    pytest.importorskip("matplotlib")
    assert main(["report", "--quick", "--out", str(tmp_path)]) == 0
    text = (tmp_path / "README.md").read_text(encoding="utf-8")
    for heading in (
        "## Machine and versions",
        "## Targets",
        "## 1. Preintegration",
        "## 2 and 3. Fresnel models",
        "## 4. Basis build",
    ):
        assert heading in text
    assert "| numpy |" in text and "| basis hash |" in text
    shipped = re.search(
        r"\| quadrature-schedule \| shipped schedule × 1 \(the default\) \| [\d.]+ \| ([\d.e+-]+) \|", text
    )
    assert shipped is not None and float(shipped.group(1)) < 1e-5
    for name in ("lut_error_vs_time.png", "fresnel_models.png"):
        assert (tmp_path / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(tmp_path.glob(".*.tmp"))
    assert "target:" in capsys.readouterr().out
