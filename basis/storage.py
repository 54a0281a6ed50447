"""Files: the shipped data's paths, atomic output, and versioned JSON documents.

Public objects: ``shipped_path``, ``temporary_sibling``, ``replace_together``, ``write_together``,
``Journal``, ``read_journal``, ``unfinished_group``, ``recover_folder``, ``write_text``, ``write_json``,
``read_regular_file``, ``check_regular_file``, ``reading_folder``, ``read_json_document``, ``nesting_depth``, ``MAX_NESTING``,
``MAX_DOCUMENT_BYTES``, ``MAX_TABLE_BYTES``, ``FolderWarning``, ``DuplicateKeyError``, ``parse_json``.

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

A journal proves each file it names: it records the identity (device, inode, change time, size) of every temporary
to rename and every file to remove, taken by the writer that made them. Recovery renames or removes only a file that
is still that very file, so a journal crafted by hand, copied in or unpacked from an archive (which makes new files)
moves nothing: it can neither replace a user's ``notes.txt`` nor remove a ``basis.json``.

Every file read is first checked to be a regular file of bounded size (:func:`read_regular_file`,
:func:`check_regular_file`): a FIFO, a device such as ``/dev/zero`` or an endless file is refused at once instead
of hanging the reader or filling the memory.
"""

from __future__ import annotations

import contextlib
import dataclasses
import json
import os
import re
import stat
import tempfile
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path

from .validation import ParameterError

try:
    import fcntl
except ImportError:  # Windows: no advisory locks; groups are still renamed together, but writers may interleave
    fcntl = None

__all__ = [
    "MAX_DOCUMENT_BYTES",
    "MAX_NESTING",
    "MAX_TABLE_BYTES",
    "DuplicateKeyError",
    "FolderWarning",
    "parse_json",
    "check_regular_file",
    "read_regular_file",
    "reading_folder",
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
JOURNAL_VERSION = 3
#: A journal lists a build's files (a dozen names and their identities): anything larger is not one.
MAX_JOURNAL_BYTES = 1 << 16
#: Largest JSON document read (a basis of 8 terms on the largest grid is about 2 MB).
MAX_DOCUMENT_BYTES = 1 << 26
#: Largest table file read (a float32 RGBA table of 8192 x 8192 texels is 1 GiB before compression).
MAX_TABLE_BYTES = 1 << 31


class FolderWarning(UserWarning):
    """Something in an output folder that is not this project's was left alone (a journal that is no regular file)."""


def read_regular_file(path, what: str, limit: int, error=ParameterError, follow_links: bool = True) -> bytes:
    """The bytes of ``path``, a regular file of at most ``limit`` bytes, else ``error`` with one line naming it.

    The file is opened without blocking and checked on the open descriptor before a byte is read: a FIFO (whose
    open would wait for a writer), a device (``/dev/zero`` never ends), a folder or a file over ``limit`` is refused
    at once. ``follow_links=False`` refuses a symbolic link too.
    """
    with _opened_regular(path, what, limit, error, follow_links) as (handle, size):
        chunks, total = [], 0
        while total <= limit:
            chunk = os.read(handle, min(1 << 20, limit + 1 - total))
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
        if total > limit:
            raise error(f"{what} {path} grew past {limit:,} bytes while it was read")
        return b"".join(chunks)


def check_regular_file(path, what: str, limit: int, error=ParameterError) -> Path:
    """``path`` where it is a regular file of at most ``limit`` bytes (as :func:`read_regular_file` checks), for a
    library that opens the file by name itself (OpenEXR)."""
    with _opened_regular(path, what, limit, error, True):
        return Path(path)


@contextlib.contextmanager
def _opened_regular(path, what: str, limit: int, error, follow_links: bool) -> Iterator[tuple[int, int]]:
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
    if not follow_links:
        flags |= getattr(os, "O_NOFOLLOW", 0)
    try:
        handle = os.open(path, flags)
    except FileNotFoundError:
        raise error(f"{what} {path} does not exist") from None
    except OSError as cause:
        if not follow_links and os.path.islink(path):
            raise error(f"{what} {path} is a symbolic link, not a regular file: refused unread") from None
        raise error(f"cannot read {what} {path}: {cause.strerror or cause}") from None
    try:
        info = os.fstat(handle)
        if not stat.S_ISREG(info.st_mode):
            kind = (
                "a folder"
                if stat.S_ISDIR(info.st_mode)
                else "a FIFO"
                if stat.S_ISFIFO(info.st_mode)
                else "a device"
                if stat.S_ISCHR(info.st_mode) or stat.S_ISBLK(info.st_mode)
                else "not a regular file"
            )
            raise error(f"{what} {path} is {kind}, not a regular file: refused unread")
        if info.st_size > limit:
            raise error(f"{what} {path} is {info.st_size:,} bytes, more than the {limit:,} such a file can be")
        yield handle, info.st_size
    finally:
        os.close(handle)


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


def _identity(path: Path) -> tuple[int, int, int, int] | None:
    """(device, inode, change time in ns, size) of the file or link ``path``, None where there is none. A copy, an
    archive's unpacking or any edit makes another identity; only the file itself keeps it."""
    try:
        info = os.lstat(path)
    except OSError:
        return None
    return (info.st_dev, info.st_ino, info.st_ctime_ns, info.st_size)


def _is_identity(value) -> bool:
    return isinstance(value, list) and len(value) == 4 and all(type(item) is int and item >= 0 for item in value)


@dataclasses.dataclass(frozen=True)
class Journal:
    """An unfinished group of a folder: (temporary, target) names to rename, then names to remove, each with the
    identity of the file the writer made or chose to remove (:func:`_identity`).

    Every name is relative to the journal's folder, a temporary is always named as this module names the
    temporaries of its target, and a file is acted on only while it is the very file the writer recorded: a
    journal can neither reach outside its folder nor rename or remove a file that a writer of this project did not
    make or choose.
    """

    folder: Path
    renames: tuple[tuple[str, str, tuple[int, ...]], ...]
    removals: tuple[tuple[str, tuple[int, ...]], ...] = ()

    @classmethod
    def of(cls, folder: Path, renames, removals=()) -> "Journal":
        """The journal of (temporary, target) paths to rename and names to remove in ``folder``, as they are now."""
        return cls(
            folder,
            tuple(
                (Path(temporary).name, Path(target).name, _identity(Path(temporary))) for temporary, target in renames
            ),
            tuple((name, _identity(folder / name)) for name in removals),
        )

    @property
    def targets(self) -> set[str]:
        """Every name the group replaces or removes."""
        return {target for _, target, _ in self.renames} | {name for name, _ in self.removals}

    def _proven(self, name: str, identity) -> bool:
        return identity is not None and _identity(self.folder / name) == tuple(identity)

    def proven_renames(self) -> list[tuple[str, str]]:
        """The (temporary, target) pairs whose temporary is still the file the writer made."""
        return [
            (temporary, target) for temporary, target, identity in self.renames if self._proven(temporary, identity)
        ]

    def proven_removals(self) -> list[str]:
        """The names still the file the writer chose to remove."""
        return [name for name, identity in self.removals if self._proven(name, identity)]

    def pending(self) -> bool:
        """Whether some rename or removal has not happened yet (the group is half done)."""
        return bool(self.proven_renames() or self.proven_removals())

    def text(self) -> str:
        return json.dumps(
            {
                "format": JOURNAL_FORMAT,
                "version": JOURNAL_VERSION,
                "renames": [[temporary, target, list(identity)] for temporary, target, identity in self.renames],
                "removals": [[name, list(identity)] for name, identity in self.removals],
            }
        )


def read_journal(folder) -> Journal | None:
    """The folder's journal, or None where there is none or it is not one of this project's (not a small regular
    file, unreadable, cut short by a kill before the renames began, or naming anything but its own folder's
    temporaries with their identities). A journal that is no regular file (a FIFO, a link to a device) is ignored
    with a :class:`FolderWarning`, unopened."""
    folder = Path(folder)
    path = folder / JOURNAL
    if not os.path.lexists(path):
        return None
    try:
        data = read_regular_file(path, "journal", MAX_JOURNAL_BYTES, follow_links=False)
        document = parse_json(data.decode("utf-8"))
    except ParameterError as refused:
        warnings.warn(f"{refused}; ignored", FolderWarning, stacklevel=2)
        return None
    except (ValueError, RecursionError):
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
    for entry in renames:
        if not (
            isinstance(entry, list)
            and len(entry) == 3
            and all(map(_plain_name, entry[:2]))
            and _temporary_of(entry[0]) == entry[1]
            and _is_identity(entry[2])
        ):
            return None
    for entry in removals:
        if not (isinstance(entry, list) and len(entry) == 2 and _plain_name(entry[0]) and _is_identity(entry[1])):
            return None
    return Journal(
        folder,
        tuple((temporary, target, tuple(identity)) for temporary, target, identity in renames),
        tuple((name, tuple(identity)) for name, identity in removals),
    )


@contextlib.contextmanager
def _folder_lock(folder: Path, shared: bool = False) -> Iterator[None]:
    """An advisory lock on the folder itself (no lock file is left behind): exclusive for a writer, so that writers
    of one folder take turns and a group of files is never interleaved with another group; shared for a reader
    (:func:`reading_folder`)."""
    if fcntl is None:
        yield
        return
    try:
        handle = os.open(folder, os.O_RDONLY)
    except OSError:
        if not shared:
            raise
        yield  # a folder this reader may search but not list: it reads without the lock
        return
    try:
        fcntl.flock(handle, fcntl.LOCK_SH if shared else fcntl.LOCK_EX)
        yield
    finally:
        os.close(handle)


@contextlib.contextmanager
def reading_folder(folder) -> Iterator[None]:
    """Hold off the folder's writers while a reader checks and reads its files: a writer renaming its group holds the
    folder exclusively, so the reader waits for it and then sees the whole new set (or, before it, the old one);
    a half-renamed group it finds under this lock is a killed writer's (:func:`unfinished_group`)."""
    with _folder_lock(Path(folder), shared=True):
        yield


def _finish(folder: Path) -> None:
    """Complete an interrupted group (the lock held): rename the temporaries its journal lists, remove the names it
    removes and drop the journal, acting only on the files the journal proves (:class:`Journal`). A journal that
    is not this project's is dropped (a link or FIFO of its name is removed unopened) without acting on it."""
    if (folder / JOURNAL).is_dir() and not (folder / JOURNAL).is_symlink():
        raise ParameterError(
            f"{folder / JOURNAL} is a folder: this project's writers keep their journal under that name; move it away"
        )
    journal = read_journal(folder)
    if journal is not None and journal.pending():
        for temporary, target in journal.proven_renames():
            os.replace(folder / temporary, folder / target)
        for name in journal.proven_removals():
            _remove_file(folder / name)
        # the backups the killed writer made of the group's targets (a journal that proves a file is its writer's)
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
    with warnings.catch_warnings():  # a reader says nothing of a folder's odd files; the next writer warns
        warnings.simplefilter("ignore", FolderWarning)
        journal = read_journal(path.parent)
    return journal if journal is not None and path.name in journal.targets and journal.pending() else None


def recover_folder(folder) -> None:
    """Finish a group of files that a killed process left half-renamed, and remove its temporaries: a
    writer's action (every write into the folder does it first); readers never call it."""
    folder = Path(folder)
    if os.path.lexists(folder / JOURNAL) and os.access(folder, os.W_OK):
        with _folder_lock(folder):
            _finish(folder)


def _make_folder(folder: Path) -> list[Path]:
    """Create ``folder`` and its missing parents; return those this call created, deepest first. One that another
    writer creates meanwhile (two builds into a new folder race to make it) is used as it is and is not this call's
    to remove."""
    missing = []
    while not folder.exists():
        missing.append(folder)
        folder = folder.parent
    created = []
    for path in reversed(missing):
        try:
            path.mkdir()
        except FileExistsError:
            if not path.is_dir():
                raise
            continue
        created.append(path)
    return created[::-1]


def _one_line(error: BaseException, path: Path) -> BaseException:
    """The error as one line that names the file (disk full, permissions, a library's bare RuntimeError)."""
    if isinstance(error, (KeyboardInterrupt, SystemExit, ParameterError)):
        return error
    reason = error.strerror if isinstance(error, OSError) and error.strerror else str(error) or type(error).__name__
    errno = getattr(error, "errno", None)
    return OSError(errno, f"cannot write {path}: {reason}") if errno else OSError(f"cannot write {path}: {reason}")


def _write_journal(folder: Path, journal: Journal) -> None:
    """The journal, written to a temporary and renamed over the journal's name, so that whatever stood there (a link,
    a FIFO) is replaced, never written through; a kill before the rename leaves no journal (the renames had not
    begun)."""
    temporary = temporary_sibling(folder / JOURNAL)
    try:
        temporary.write_text(journal.text(), encoding="utf-8")
        os.replace(temporary, folder / JOURNAL)
    finally:
        temporary.unlink(missing_ok=True)


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
            journal = Journal.of(folder, zip(temporaries, targets), removals)
            try:
                _write_journal(folder, journal)
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


class DuplicateKeyError(ValueError):
    """A JSON object names one key twice (the last would silently win)."""


def _unique_keys(pairs: list[tuple[str, object]]) -> dict:
    keys = [key for key, _ in pairs]
    if len(set(keys)) != len(keys):
        twice = sorted({key for key in keys if keys.count(key) > 1})
        names = ", ".join(map(repr, twice))
        raise DuplicateKeyError(
            f"the keys {names} appear twice" if len(twice) > 1 else f"the key {names} appears twice"
        )
    return dict(pairs)


def parse_json(text: str):
    """``json.loads`` that refuses an object naming a key twice (:class:`DuplicateKeyError`): every JSON file this
    project reads (basis, presets, spectral data, scenes, journals) is parsed by it.

    >>> parse_json('{"a": 1, "b": 2}')
    {'a': 1, 'b': 2}
    >>> parse_json('{"a": 1, "a": 2}')
    Traceback (most recent call last):
    ...
    basis.storage.DuplicateKeyError: the key 'a' appears twice
    """
    return json.loads(text, object_pairs_hook=_unique_keys)


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
    data = read_regular_file(path, what, MAX_DOCUMENT_BYTES, error)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as cause:
        raise error(f"cannot read {what} {path}: not UTF-8 text ({cause})") from None
    try:
        document = parse_json(text)
    except json.JSONDecodeError as cause:
        raise error(f"cannot read {what} {path}: not valid JSON (truncated?): {cause}") from None
    except DuplicateKeyError as cause:
        raise error(f"cannot read {what} {path}: {cause} in one object") from None
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
