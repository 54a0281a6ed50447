"""Files: the shipped data's paths, atomic output, and versioned JSON documents.

Public objects: ``shipped_path``, ``temporary_sibling``, ``replace_together``, ``write_together``,
``recover_folder``, ``write_text``, ``write_json``, ``read_json_document``.

Shipped data (``luts/basis.json``, ``luts/materials.json``, ``luts/spectral_ior.json``, the LUTs) is
found beside the installed packages, never by importing ``luts``: a folder named ``luts`` in the working
directory must not shadow it.

A reader (or a crash, Ctrl-C or kill) never sees a half-written file: the data go to a temporary
file in the destination folder, which is renamed over the target only when complete. Several files
that belong together (the basis and Schlick LUTs of one build) are renamed as a group; if the group
is interrupted part-way, the files already replaced are rolled back to their previous content.
"""

from __future__ import annotations

import contextlib
import glob
import json
import os
import re
import tempfile
from collections.abc import Callable, Iterator
from pathlib import Path

from .validation import ParameterError

try:
    import fcntl
except ImportError:  # Windows: no advisory locks; groups are still renamed together, but writers may interleave
    fcntl = None

__all__ = ["read_json_document", "recover_folder", "replace_together", "shipped_path", "temporary_sibling", "write_json",
           "write_text", "write_together"]


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


#: Written in the destination folder once every file of a group is complete, removed once all are renamed:
#: a process killed between the renames leaves it, and the next writer or reader finishes the group.
JOURNAL = ".fresnel-lut-journal.json"


@contextlib.contextmanager
def _folder_lock(folder: Path) -> Iterator[None]:
    """An exclusive advisory lock on the folder itself (no lock file is left behind): writers of one
    folder take turns, so a group of files is never interleaved with another group."""
    if fcntl is None:
        yield
        return
    handle = os.open(folder, os.O_RDONLY)
    try:
        fcntl.flock(handle, fcntl.LOCK_EX)
        yield
    finally:
        os.close(handle)


def _finish(folder: Path) -> None:
    """Complete an interrupted group (the lock held): rename the temporaries its journal lists, drop the journal."""
    journal = folder / JOURNAL
    try:
        pairs = json.loads(journal.read_text(encoding="utf-8"))
        pairs = [(Path(temporary), Path(target)) for temporary, target in pairs]
    except (OSError, ValueError, TypeError):
        journal.unlink(missing_ok=True)
        return
    for temporary, target in pairs:
        if temporary.exists():
            os.replace(temporary, target)
    _remove_stale_temporaries(target for _, target in pairs)
    journal.unlink(missing_ok=True)


def _remove_stale_temporaries(targets) -> None:
    """Temporaries a killed writer left for these targets: exactly ``.NAME.XXXXXXXX.tmp`` (this module's
    pattern), nothing else of the folder's; only called with the folder's lock held."""
    for target in map(Path, targets):
        pattern = re.compile(rf"^\.{re.escape(target.name)}\.[A-Za-z0-9_]{{8}}\.tmp$")
        for stale in target.parent.glob(f".{glob.escape(target.name)}.*.tmp"):
            if pattern.match(stale.name) and stale.is_file():
                stale.unlink(missing_ok=True)


def recover_folder(folder) -> None:
    """Finish a group of files that a killed process left half-renamed, and remove its temporaries."""
    folder = Path(folder)
    if (folder / JOURNAL).exists() and os.access(folder, os.W_OK):
        with _folder_lock(folder):
            _finish(folder)


def _make_folder(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; return those created, deepest first."""
    missing = []
    while not folder.exists():
        missing.append(folder)
        folder = folder.parent
    for path in reversed(missing):
        path.mkdir()
    return missing


def _one_line(error: BaseException, path: Path) -> BaseException:
    """The error as one line that names the file (disk full, permissions, a library's bare RuntimeError)."""
    if isinstance(error, (KeyboardInterrupt, SystemExit, ParameterError)):
        return error
    reason = error.strerror if isinstance(error, OSError) and error.strerror else str(error) or type(error).__name__
    return OSError(getattr(error, "errno", None) or 0, f"cannot write {path}: {reason}")


def write_together(writers: list[tuple[Path, Callable[[Path], None]]]) -> list[Path]:
    """Write a group of files as one transaction: ``writer(temporary)`` fills each file's temporary sibling,
    then all are renamed into place (:func:`replace_together`).

    The destination folder is locked for the transaction; an interrupted earlier group there is finished
    first and its temporaries removed. On any failure no target is replaced, the temporaries and the
    folders this call created are removed, and the error is one line naming the file.
    """
    targets = [Path(path) for path, _ in writers]
    folder = targets[0].parent
    created = _make_folder(folder)
    temporaries: list[Path] = []
    try:
        with _folder_lock(folder):
            _finish(folder)
            _remove_stale_temporaries(targets)
            for target, (_, writer) in zip(targets, writers):
                temporaries.append(temporary_sibling(target))
                try:
                    writer(temporaries[-1])
                except BaseException as error:
                    raise _one_line(error, target) from None
            # a journal cut short by a kill is unreadable and dropped: the renames had not begun
            (folder / JOURNAL).write_text(json.dumps([[str(t), str(p)] for t, p in zip(temporaries, targets)]),
                                          encoding="utf-8")
            try:
                replace_together(zip(temporaries, targets))
            except BaseException as error:
                raise _one_line(error, targets[0]) from None
            finally:
                (folder / JOURNAL).unlink(missing_ok=True)
    except BaseException:
        for temporary in temporaries:
            temporary.unlink(missing_ok=True)
        for path in created:  # deepest first; only if still empty
            with contextlib.suppress(OSError):
                path.rmdir()
        raise
    return targets


def write_text(path, text: str) -> Path:
    """Write ``text`` (UTF-8) to ``path`` atomically."""
    return write_together([(Path(path), lambda temporary: temporary.write_text(text, encoding="utf-8"))])[0]


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
