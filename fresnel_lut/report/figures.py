"""Shared plotting helpers of the report studies (matplotlib is the optional ``plot`` extra).

Public objects: ``pyplot``, ``save_figure``, ``figure_png``.
"""

from __future__ import annotations

from pathlib import Path

from basis.storage import write_together
from basis.validation import ParameterError

__all__ = ["figure_png", "pyplot", "save_figure"]


def pyplot():
    """matplotlib.pyplot with the non-interactive Agg backend; a clear error if the extra is missing."""
    try:
        import matplotlib
    except ImportError:
        raise ParameterError("plots need matplotlib: pip install 'fresnel-basis[plot]'") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def figure_png(figure) -> bytes:
    """The figure as PNG bytes, and closed: for a group of files written as one transaction."""
    import io

    buffer = io.BytesIO()
    try:
        figure.savefig(buffer, format="png")
    finally:
        pyplot().close(figure)
    return buffer.getvalue()


def save_figure(figure, path) -> Path | bytes:
    """Save ``figure`` as PNG atomically (temporary sibling, then rename) and close it; with ``path`` None, return the
    PNG bytes instead (:func:`figure_png`), for a caller that writes a group of files as one transaction."""
    if path is None:
        return figure_png(figure)
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise ParameterError(f"path must end in .png, got {str(path)!r}")
    try:
        write_together([(path, lambda temporary: figure.savefig(temporary, format="png"))])
    finally:
        pyplot().close(figure)
    return path
