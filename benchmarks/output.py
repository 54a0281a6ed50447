"""What every benchmark does with its Markdown: print it, and write it whole where ``--out`` names a file; and the
machine it ran on, in words (ratios of shader passes differ by CPU: the (r, g) pass read 1.58 x Schlick's on one
machine and 1.6-1.7 x on an AVX-512 one, 2026-12).

Public objects: ``publish``, ``machine``.
"""

from __future__ import annotations

import os
import platform
from pathlib import Path

from basis.storage import write_text
from fresnel_lut.report.readme import read_system_value

__all__ = ["machine", "publish"]


def publish(text: str, out: str | Path | None) -> None:
    """Print ``text``; with ``out``, also write it there (a temporary file renamed into place: whole or not at all)."""
    print(text)
    if out is not None:
        write_text(out, text)


def machine() -> str:
    """``x86_64, AMD EPYC, 2 cores``: the architecture, the CPU's model name (as the report's environment reads it)
    and the cores."""
    return f"{platform.machine()}, {read_system_value('/proc/cpuinfo', 'model name')}, {os.cpu_count()} cores"
