"""Atomic file output: write to a temporary sibling, then rename into place, as one transaction.

Public objects: ``temporary_sibling``, ``replace_together``, ``write_text``.

A reader (or a crash, Ctrl-C or kill) never sees a half-written file: the data go to a temporary
file in the destination folder, which is renamed over the target only when complete. Several files
that belong together (the basis and Schlick LUTs of one build) are renamed as a group; if the group
is interrupted part-way, the files already replaced are rolled back to their previous content.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from .validation import ParameterError

__all__ = ["replace_together", "temporary_sibling", "write_text"]


def _default_mode() -> int:
    """0o666 filtered by the process umask: what ``open(path, "w")`` would have given."""
    umask = os.umask(0)
    os.umask(umask)
    return 0o666 & ~umask


def temporary_sibling(path) -> Path:
    """Create an empty temporary file next to ``path`` (same folder, hence same file system).

    Its permissions are those an ordinary new file would get (``mkstemp`` alone gives 0600).
    """
    path = Path(path)
    if path.exists() and not path.is_file():
        raise ParameterError(f"{path} exists and is not a regular file; refusing to replace it")
    path.parent.mkdir(parents=True, exist_ok=True)
    handle, name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(handle)
    os.chmod(name, _default_mode())
    return Path(name)


def replace_together(pairs) -> None:
    """Rename each (temporary, target) pair into place; on any failure restore every target.

    Before the first rename each existing target is hard-linked (or, where links are not supported,
    renamed) to a backup; if a rename fails or is interrupted, the targets already replaced get their
    backups back and new targets are removed. Temporaries are removed in every case.
    """
    pairs = [(Path(temporary), Path(target)) for temporary, target in pairs]
    backups: dict[Path, Path | None] = {}
    done: list[Path] = []
    try:
        for _, target in pairs:
            backups[target] = None
            if target.exists():
                backup = temporary_sibling(target)
                backup.unlink()
                try:
                    os.link(target, backup)
                except OSError:
                    os.replace(target, backup)
                backups[target] = backup
        for temporary, target in pairs:
            os.replace(temporary, target)
            done.append(target)
    except BaseException:
        for target in done:
            if backups.get(target) is not None:
                os.replace(backups[target], target)
            else:
                target.unlink(missing_ok=True)
        for target, backup in backups.items():
            if backup is not None and backup.exists() and not target.exists():
                os.replace(backup, target)
        raise
    finally:
        for temporary, _ in pairs:
            temporary.unlink(missing_ok=True)
        for backup in backups.values():
            if backup is not None:
                backup.unlink(missing_ok=True)


def write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    path = Path(path)
    temporary = temporary_sibling(path)
    try:
        temporary.write_text(text, encoding="utf-8")
    except BaseException:
        temporary.unlink(missing_ok=True)
        raise
    replace_together([(temporary, path)])
    return path
