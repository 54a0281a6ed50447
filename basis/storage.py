"""Files: the shipped data's paths, atomic output, and versioned JSON documents.

Public objects: ``shipped_path``, ``temporary_sibling``, ``replace_together``, ``write_text``,
``write_json``, ``read_json_document``.

Shipped data (``luts/basis.json``, ``luts/materials.json``, ``luts/spectral_ior.json``, the LUTs) is
found beside the installed packages, never by importing ``luts``: a folder named ``luts`` in the working
directory must not shadow it.

A reader (or a crash, Ctrl-C or kill) never sees a half-written file: the data go to a temporary
file in the destination folder, which is renamed over the target only when complete. Several files
that belong together (the basis and Schlick LUTs of one build) are renamed as a group; if the group
is interrupted part-way, the files already replaced are rolled back to their previous content.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path

from .validation import ParameterError

__all__ = ["read_json_document", "replace_together", "shipped_path", "temporary_sibling", "write_json", "write_text"]


def shipped_path(name: str) -> Path:
    """Path of a file shipped in ``luts/`` (``luts`` is installed next to ``basis``)."""
    return Path(__file__).resolve().parent.parent / "luts" / name


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


def write_json(path, document: dict) -> Path:
    """Write a JSON document atomically: one space of indent, UTF-8 text kept as is, a final newline."""
    return write_text(path, json.dumps(document, indent=1, ensure_ascii=False) + "\n")


def read_json_document(path, what: str, format_tag: str | None = None, version: int | None = None,
                       error=ParameterError) -> dict:
    """Read the JSON document ``what`` (e.g. "basis file") and check its ``format`` tag and ``version``
    where given; every failure raises ``error`` with one line that names the file."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{what} {path} does not exist") from None
    except (OSError, UnicodeDecodeError) as cause:
        raise error(f"cannot read {what} {path}: {cause}") from None
    try:
        document = json.loads(text)
    except json.JSONDecodeError as cause:
        raise error(f"cannot read {what} {path}: not valid JSON (truncated?): {cause}") from None
    if format_tag is not None:
        found = document.get("format") if isinstance(document, dict) else type(document).__name__
        if found != format_tag or (version is not None and document.get("version") != version):
            expected = format_tag if version is None else f"{format_tag} v{version}"
            raise error(f"{what} {path} is not a {expected} file (format {found!r})")
    return document
