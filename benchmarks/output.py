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

__all__ = ["machine", "publish"]


def publish(text: str, out: str | Path | None) -> None:
    """Print ``text``; with ``out``, also write it there (a temporary file renamed into place: whole or not at all)."""
    print(text)
    if out is not None:
        write_text(out, text)


def machine() -> str:
    """``x86_64, AMD EPYC …, 2 cores``: the architecture, the CPU's model name where ``/proc/cpuinfo`` gives it,
    and the cores."""
    model = ""
    try:
        for line in Path("/proc/cpuinfo").read_text(encoding="utf-8", errors="replace").splitlines():
            if line.startswith("model name"):
                model = ", " + line.partition(":")[2].strip()
                break
    except OSError:
        pass
    return f"{platform.machine()}{model}, {os.cpu_count()} cores"
