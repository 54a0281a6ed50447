"""Files: the shipped data's paths, atomic output, and versioned JSON documents.

Public objects: ``shipped_path``, ``temporary_sibling``, ``replace_together``, ``write_together``,
``Journal``, ``read_journal``, ``unfinished_group``, ``recover_folder``, ``write_text``, ``write_json``,
``read_json_document``, ``nesting_depth``, ``MAX_NESTING``.

Shipped data (``luts/basis.json``, ``luts/materials.json``, ``luts/spectral_ior.json``, the LUTs) is
found beside the installed packages, never by importing ``luts``: a folder named ``luts`` in the working
directory must not shadow it.

A reader (or a crash, Ctrl-C or kill) never sees a half-written file: the data go to a temporary
file in the destination folder, which is renamed over the target only when complete. Several files
that belong together (the basis and Schlick LUTs of one build) are renamed as a group; if the group
is interrupted part-way, the files already replaced are rolled back to their previous content. A process
killed between those renames leaves a journal (``.fresnel-lut-journal.json``, names relative to its folder)
from which the next writer of the folder finishes the group; a reader never renames, removes or writes
anything: it refuses a file of a half-renamed group instead (:func:`unfinished_group`).
"""

from __future__ import annotations

import contextlib
import dataclasses
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

__all__ = [
    "MAX_NESTING",
    "nesting_depth",
    "Journal",
    "read_journal",
    "read_json_document",
    "recover_folder",
    "replace_together",
    "shipped_path",
    "temporary_sibling",
    "unfinished_group",
    "write_json",
    "write_text",
    "write_together",
]


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
#: a process killed between the renames leaves it, and the next writer of the folder finishes the group.
JOURNAL = ".fresnel-lut-journal.json"
JOURNAL_FORMAT = "fresnel-basis/journal"
JOURNAL_VERSION = 2


#: The names :func:`temporary_sibling` gives: ``.TARGET.XXXXXXXX.tmp`` (``mkstemp``'s eight characters).
_TEMPORARY = re.compile(r"\.(?P<target>.+)\.[A-Za-z0-9_]{8}\.tmp")


def _temporary_of(name: str) -> str | None:
    """The target whose temporary ``name`` is, or None where it is not one of this module's temporaries."""
    match = _TEMPORARY.fullmatch(name)
    return match.group("target") if match else None


def _plain_name(name) -> bool:
    """A file name of the folder itself: no separator, not ``.`` or ``..``, not the journal."""
    return (
        isinstance(name, str)
        and name not in ("", ".", "..", JOURNAL)
        and "/" not in name
        and "\\" not in name
        and "\x00" not in name
        and Path(name).name == name
    )


@dataclasses.dataclass(frozen=True)
class Journal:
    """An unfinished group of a folder: (temporary, target) names to rename, then names to remove.

    Every name is relative to the journal's folder, and a temporary is always named as this module names
    the temporaries of its target: a journal can neither reach outside its folder nor rename a file that
    a writer of this project did not make.
    """

    folder: Path
    renames: tuple[tuple[str, str], ...]
    removals: tuple[str, ...] = ()

    @property
    def targets(self) -> set[str]:
        """Every name the group replaces or removes."""
        return {target for _, target in self.renames} | set(self.removals)

    def pending(self) -> bool:
        """Whether some rename or removal has not happened yet (the group is half done)."""
        return any((self.folder / temporary).is_file() for temporary, _ in self.renames) or any(
            os.path.lexists(self.folder / name) for name in self.removals
        )

    def text(self) -> str:
        return json.dumps(
            {
                "format": JOURNAL_FORMAT,
                "version": JOURNAL_VERSION,
                "renames": [list(pair) for pair in self.renames],
                "removals": list(self.removals),
            }
        )


def read_journal(folder) -> Journal | None:
    """The folder's journal, or None where there is none or it is not one of this project's (unreadable,
    cut short by a kill before the renames began, or naming anything but its own folder's temporaries)."""
    folder = Path(folder)
    try:
        document = json.loads((folder / JOURNAL).read_text(encoding="utf-8"))
    except (OSError, ValueError, RecursionError):
        return None
    if (
        not isinstance(document, dict)
        or document.get("format") != JOURNAL_FORMAT
        or document.get("version") != JOURNAL_VERSION
    ):
        return None
    renames, removals = document.get("renames"), document.get("removals", [])
    if not isinstance(renames, list) or not isinstance(removals, list):
        return None
    for pair in renames:
        if not (
            isinstance(pair, list)
            and len(pair) == 2
            and all(map(_plain_name, pair))
            and _temporary_of(pair[0]) == pair[1]
        ):
            return None
    if not all(map(_plain_name, removals)):
        return None
    return Journal(folder, tuple(tuple(pair) for pair in renames), tuple(removals))


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
    """Complete an interrupted group (the lock held): rename the temporaries its journal lists, remove the
    names it removes, drop the journal. A journal that is not this project's is dropped without acting on it."""
    journal = read_journal(folder)
    if journal is not None:
        for temporary, target in journal.renames:
            source = folder / temporary
            if source.is_file() and not source.is_symlink():
                os.replace(source, folder / target)
        for name in journal.removals:
            _remove_file(folder / name)
        _remove_stale_temporaries(folder, lambda name: name in journal.targets)
    (folder / JOURNAL).unlink(missing_ok=True)


def _remove_file(path: Path) -> None:
    """Remove a file (or a link) of a group; a folder of that name is not ours and stays."""
    if path.is_symlink() or path.is_file():
        path.unlink(missing_ok=True)


def _remove_stale_temporaries(folder: Path, owned: Callable[[str], bool]) -> None:
    """Temporaries a killed writer left in ``folder`` for the names ``owned`` accepts: exactly
    ``.NAME.XXXXXXXX.tmp`` (this module's pattern), nothing else of the folder's; only with the lock held."""
    for stale in folder.glob(".*.tmp"):
        target = _temporary_of(stale.name)
        if target is not None and owned(target) and stale.is_file() and not stale.is_symlink():
            stale.unlink(missing_ok=True)


def unfinished_group(path) -> Journal | None:
    """The half-renamed group ``path`` belongs to, if a killed writer left one in its folder; reads only."""
    path = Path(path)
    journal = read_journal(path.parent)
    return journal if journal is not None and path.name in journal.targets and journal.pending() else None


def recover_folder(folder) -> None:
    """Finish a group of files that a killed process left half-renamed, and remove its temporaries: a
    writer's action (every write into the folder does it first); readers never call it."""
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
    errno = getattr(error, "errno", None)
    return OSError(errno, f"cannot write {path}: {reason}") if errno else OSError(f"cannot write {path}: {reason}")


def write_together(writers: list[tuple[Path, Callable[[Path], None]]], owned: str | None = None) -> list[Path]:
    """Write a group of files as one transaction: ``writer(temporary)`` fills each file's temporary sibling,
    then all are renamed into place (:func:`replace_together`).

    Every target lies in one folder. The folder is locked for the transaction; an interrupted earlier group
    there is finished first. ``owned``, a regular expression of file names, is the set this group owns
    (a build's tables in every format): the files of the folder it matches that the group does not write are
    removed once the renames are done, and so are the temporaries a killed writer left for any of them. On
    any failure no target is replaced, the temporaries and the folders this call created are removed, and
    the error is one line naming the file.
    """
    targets = [Path(path) for path, _ in writers]
    folder = targets[0].parent
    if any(target.parent != folder for target in targets):
        raise ParameterError(f"a group of files lies in one folder, got {sorted({str(t.parent) for t in targets})}")
    names = {target.name for target in targets}
    owns = re.compile(owned).fullmatch if owned is not None else (lambda name: False)
    created = _make_folder(folder)
    temporaries: list[Path] = []
    try:
        with _folder_lock(folder):
            _finish(folder)
            _remove_stale_temporaries(folder, lambda name: name in names or owns(name))
            for target, (_, writer) in zip(targets, writers):
                temporaries.append(temporary_sibling(target))
                try:
                    writer(temporaries[-1])
                except BaseException as error:
                    raise _one_line(error, target) from None
            removals = sorted(
                path.name
                for path in folder.iterdir()
                if owns(path.name) and path.name not in names and (path.is_file() or path.is_symlink())
            )
            journal = Journal(folder, tuple((t.name, p.name) for t, p in zip(temporaries, targets)), tuple(removals))
            try:
                # a journal cut short by a kill is unreadable and dropped: the renames had not begun
                (folder / JOURNAL).write_text(journal.text(), encoding="utf-8")
                replace_together(zip(temporaries, targets))
            except BaseException as error:  # nothing is renamed (replace_together rolls back): no group to finish
                (folder / JOURNAL).unlink(missing_ok=True)
                raise _one_line(error, targets[0]) from None
            try:
                for name in removals:
                    _remove_file(folder / name)
            except BaseException as error:  # the journal stays: the next writer finishes the removals
                raise _one_line(error, folder / removals[0]) from None
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


#: Deepest nesting of lists and tables a document of this project may have (the deepest has 5).
MAX_NESTING = 32


def nesting_depth(document) -> int:
    """How deeply lists and dicts nest in a parsed JSON or TOML document (iteratively: no recursion limit)."""
    deepest, stack = 0, [(document, 1)]
    while stack:
        item, depth = stack.pop()
        if isinstance(item, (list, dict)):
            deepest = max(deepest, depth)
            stack.extend((child, depth + 1) for child in (item.values() if isinstance(item, dict) else item))
    return deepest


def read_json_document(
    path, what: str, format_tag: str | None = None, version: int | None = None, error=ParameterError
) -> dict:
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
    except RecursionError:
        raise error(f"cannot read {what} {path}: nested deeper than Python's parser allows") from None
    if nesting_depth(document) > MAX_NESTING:
        raise error(f"cannot read {what} {path}: nested deeper than {MAX_NESTING} levels (no file of this project is)")
    if format_tag is not None:
        found = document.get("format") if isinstance(document, dict) else type(document).__name__
        if found != format_tag or (version is not None and document.get("version") != version):
            expected = format_tag if version is None else f"{format_tag} v{version}"
            raise error(f"{what} {path} is not a {expected} file (format {found!r})")
    return document
