"""What every benchmark does with its Markdown: print it, and write it whole where ``--out`` names a file.

Public objects: ``publish``.
"""

from __future__ import annotations

from pathlib import Path

from basis.storage import write_text

__all__ = ["publish"]


def publish(text: str, out: str | Path | None) -> None:
    """Print ``text``; with ``out``, also write it there (a temporary file renamed into place: whole or not at all)."""
    print(text)
    if out is not None:
        write_text(out, text)
