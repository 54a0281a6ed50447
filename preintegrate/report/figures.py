"""Shared plotting helpers of the report studies (matplotlib is the optional ``plot`` extra).

Public objects: ``pyplot``, ``save_figure``.
"""

from __future__ import annotations

from pathlib import Path

from basis.storage import replace_together, temporary_sibling
from basis.validation import ParameterError

__all__ = ["pyplot", "save_figure"]


def pyplot():
    """matplotlib.pyplot with the non-interactive Agg backend; a clear error if the extra is missing."""
    try:
        import matplotlib
    except ImportError:
        raise ParameterError("plots need matplotlib: pip install 'fresnel-basis[plot]'") from None
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save_figure(figure, path) -> Path:
    """Save ``figure`` as PNG atomically (temporary sibling, then rename) and close it."""
    path = Path(path)
    if path.suffix.lower() != ".png":
        raise ParameterError(f"path must end in .png, got {str(path)!r}")
    temporary = temporary_sibling(path)
    try:
        figure.savefig(temporary, format="png")
        replace_together([(temporary, path)])
    finally:
        temporary.unlink(missing_ok=True)
        pyplot().close(figure)
    return path
