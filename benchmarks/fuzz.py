"""Fuzz the inputs users and files give the project, and count what happens to each case.

Run from the repository root: ``.venv/bin/python -m benchmarks.fuzz [--cases N] [--seed S] [--out FILE]``.
Seeded mutations of valid inputs in fourteen categories — scene files, preset files (``materials.json``),
basis files (``basis.json``), CLI options and API calls; (issue 26) crafted journals, stale tables, deeply nested
files, masked arrays and combinations of options; and (issue 36) hostile names into generated files, crafted output
folders, FIFOs and endless files where a file is read, and HTTP request lines to the look-development server — each
ends as one of:

* **refused**: a one-line error (exit status 2 and one ``fresnel-lut: error: …`` line, or a
  ``ParameterError`` whose message is one line);
* **accepted**: exit status 0, or a finite result;
* **crashed**: anything else — a traceback, another exception, a multi-line error, NaN or inf returned; and for
  the folder categories a broken promise: a reader that changed a file, a file outside the folder touched, a stale
  table or temporary of the set left beside a finished build, an unrelated file removed (a silent drop).

Crashed must be 0. The table goes to ``report/fuzz.md`` (or ``--out``) with the first cases of every crash.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import datetime
import hashlib
import io
import json
import os
import re
import shutil
import sys
import tempfile
import traceback
from pathlib import Path

import numpy as np

import basis
from basis.eigenbasis import Basis, shipped_basis_path
from basis.presets import material_preset, material_presets, shipped_presets_path
from basis.validation import ParameterError
from fresnel_lut import cli
from fresnel_lut.scene import read_scene
from handoff import exr, formats, shipped
from preintegrate import multiple_scattering

#: Values that break naive readers: every JSON/TOML type, non-finite and extreme numbers, odd text.
ODD = [
    None,
    True,
    False,
    "",
    "text",
    "0.3",
    "Gold",
    "\x00",
    "é" * 300,
    [],
    {},
    [1, 2],
    [1, 2, 3, 4],
    ["a", "b", "c"],
    [[1, 2, 3]],
    {"a": 1},
    0,
    -1,
    1,
    2,
    0.5,
    -0.5,
    1e-320,
    1e308,
    -1e308,
    float("nan"),
    float("inf"),
    float("-inf"),
    10**30,
    3.5,
    [0.1, 0.2, 0.3],
    [float("nan")] * 3,
]


class Outcome:
    def __init__(self):
        self.tried = self.refused = self.accepted = self.crashed = 0
        self.crashes: list[str] = []

    def add(self, kind: str, case: str = "") -> None:
        self.tried += 1
        setattr(self, kind, getattr(self, kind) + 1)
        if kind == "crashed" and len(self.crashes) < 5:
            self.crashes.append(case[:300])


def _api_outcome(outcome: Outcome, call, case: str) -> None:
    try:
        with np.errstate(all="ignore"):
            result = call()
    except ParameterError as error:
        outcome.add("refused" if len(str(error).splitlines()) == 1 else "crashed", f"{case}: multi-line {error!r}")
        return
    except Exception:  # noqa: BLE001 - every other exception is the crash this harness counts
        outcome.add("crashed", f"{case}: {' | '.join(traceback.format_exc().strip().splitlines()[-3:])}")
        return
    values = [
        np.asarray(part, dtype=float)
        for part in (result if isinstance(result, tuple) else (result,))
        if isinstance(part, (np.ndarray, float, int))
    ]
    finite = all(np.all(np.isfinite(value)) for value in values)
    outcome.add("accepted" if finite else "crashed", f"{case}: non-finite result")


def _cli_outcome(outcome: Outcome, argv: list[str]) -> None:
    error, output = io.StringIO(), io.StringIO()
    try:
        with contextlib.redirect_stderr(error), contextlib.redirect_stdout(output):
            try:
                status = cli.main([str(a) for a in argv])
            except SystemExit as exit_:
                status = exit_.code
    except Exception:  # noqa: BLE001
        outcome.add("crashed", f"{argv}: {' | '.join(traceback.format_exc().strip().splitlines()[-3:])}")
        return
    lines = error.getvalue().strip().splitlines()
    if status == 0:
        outcome.add("accepted")
    elif status == 2 and len(lines) == 1 and lines[0].startswith("fresnel-lut") and "Traceback" not in error.getvalue():
        outcome.add("refused")
    else:
        outcome.add("crashed", f"{argv}: status {status}: {error.getvalue()[:200]}")


def _mutate(rng, document, depth=0):
    """A copy of a JSON-like document with one value replaced, one key removed or one unknown key added."""
    document = copy.deepcopy(document)
    path, node = [], document
    while isinstance(node, (dict, list)) and node and rng.random() < 0.75:
        key = rng.choice(list(node)) if isinstance(node, dict) else int(rng.integers(len(node)))
        path.append(key)
        if not isinstance(node[key], (dict, list)):
            break
        node = node[key]
    if not path:
        return ODD[int(rng.integers(len(ODD)))]
    parent = document
    for key in path[:-1]:
        parent = parent[key]
    action = rng.random()
    if action < 0.7:
        parent[path[-1]] = copy.deepcopy(ODD[int(rng.integers(len(ODD)))])
    elif action < 0.85 and isinstance(parent, dict):
        parent.pop(path[-1])
    elif isinstance(parent, dict):
        parent["unexpected"] = ODD[int(rng.integers(len(ODD)))]
    else:
        parent.append(ODD[int(rng.integers(len(ODD)))])
    return document


def fuzz_presets(rng, count: int, folder: Path) -> Outcome:
    outcome = Outcome()
    shipped = json.loads(shipped_presets_path().read_text(encoding="utf-8"))
    for index in range(count):
        path = folder / f"presets{index}.json"
        if index % 10 == 0:
            path.write_bytes(rng.bytes(int(rng.integers(0, 64))))
        else:
            path.write_text(json.dumps(_mutate(rng, shipped)), encoding="utf-8")
        _api_outcome(
            outcome,
            lambda: (material_presets(path), material_preset("Gold", "sRGB", path)["coefficients"])[1],
            f"presets case {index}",
        )
    return outcome


def _rehash(document):
    try:
        digest = hashlib.sha256()
        for key in ("theta", "curves", "fit_angles"):
            digest.update(np.ascontiguousarray(np.asarray(document[key], dtype="<f8")).tobytes())
        document["content_hash"] = digest.hexdigest()[:16]
    except Exception:  # noqa: BLE001 - a document too broken to hash keeps its old hash
        pass
    return document


def fuzz_bases(rng, count: int, folder: Path) -> Outcome:
    outcome = Outcome()
    shipped = json.loads(shipped_basis_path().read_text(encoding="utf-8"))
    for index in range(count):
        document = _mutate(rng, shipped)
        if isinstance(document, dict) and rng.random() < 0.6:
            document = _rehash(document)
        path = folder / f"basis{index}.json"
        path.write_text(json.dumps(document), encoding="utf-8")
        _api_outcome(
            outcome, lambda: basis.coefficients_from_nk([1.5, 0.3], [0.0, 3.0], Basis.read(path)), f"basis case {index}"
        )
    return outcome


SCENE = {
    "tolerance": 0.0039,
    "space": "ACEScg",
    "size": 16,
    "material": [
        {"name": "a", "f0": [0.9, 0.6, 0.3], "roughness": [0.3, 0.5]},
        {"name": "b", "eta": 1.5, "kappa": 0.0, "roughness": 0.4},
        {"name": "c", "model": "f82", "f0": 0.9, "f82": 0.8, "roughness": 0.5},
        {"name": "d", "preset": "Gold", "roughness": [0.2, 0.3]},
        {"name": "e", "reflectivity": 0.5, "edge_tint": 0.2, "roughness": 0.6},
    ],
}


def fuzz_scenes(rng, count: int, folder: Path) -> Outcome:
    outcome = Outcome()
    for index in range(count):
        document = _mutate(rng, SCENE)
        path = folder / f"scene{index}.json"
        if index % 20 == 0:
            path = folder / f"scene{index}.toml"
            path.write_bytes(rng.bytes(int(rng.integers(0, 80))))
        else:
            try:
                path.write_text(json.dumps(document), encoding="utf-8")
            except ValueError:
                continue
        _api_outcome(outcome, lambda: read_scene(path).tolerance, f"scene case {index}: {json.dumps(document)[:160]}")
    return outcome


OPTIONS = {
    "build": ["--size", "--out", "--half", "--order", "--basis", "--model", "--exponent", "--alpha", "--eta-prime"],
    "coeffs": [
        "--eta",
        "--kappa",
        "--reflectivity",
        "--edge-tint",
        "--material",
        "--space",
        "--model",
        "--f0",
        "--f82",
        "--tint",
        "--r0",
        "--r90",
        "--exponent",
        "--eta-e",
        "--fit",
        "--json",
        "--basis",
        "--a",
        "--rs",
    ],
    "basis": ["--count", "--seed", "--grid-size", "--terms", "--fit-angles", "--out"],
    "scene": ["--out"],
}
VALUES = [
    "0",
    "1",
    "-1",
    "2",
    "8",
    "0.5",
    "1e308",
    "-1e-9",
    "-inf",
    "nan",
    "inf",
    "abc",
    "",
    "Gold",
    "f82",
    "schlick",
    "sRGB",
    "P3",
    "least-squares",
    "talk",
    "/dev/null",
    "3",
    "100",
    "64",
]


def fuzz_cli(rng, count: int, folder: Path) -> Outcome:
    outcome = Outcome()
    for index in range(count):
        command = list(OPTIONS)[int(rng.integers(len(OPTIONS)))]
        argv = [command]
        if command == "scene":
            argv.append(str(folder / "scene1.json") if rng.random() < 0.5 else VALUES[int(rng.integers(len(VALUES)))])
        for _ in range(int(rng.integers(0, 5))):
            option = OPTIONS[command][int(rng.integers(len(OPTIONS[command])))]
            argv.append(option)
            argv += [VALUES[int(rng.integers(len(VALUES)))] for _ in range(int(rng.choice([0, 1, 1, 3])))]
        if command in ("build", "basis", "scene") and "--out" not in argv:
            argv += ["--out", str(folder / f"out{index}" / ("b.json" if command == "basis" else ""))]
        if command == "basis":  # keep the training pass short
            argv += ["--count", str(int(rng.choice([100, 500])))]
        if command == "build" and "--size" not in argv:
            argv += ["--size", "4"]
        if command == "build" and "--order" not in argv:
            argv += ["--order", "4"]
        if command == "scene" and "--size" in argv:
            continue
        _cli_outcome(outcome, argv)
    return outcome


def _random_value(rng):
    choice = rng.random()
    if choice < 0.5:
        return ODD[int(rng.integers(len(ODD)))]
    shape = [(), (3,), (2, 3), (4,), (0,)][int(rng.integers(5))]
    return rng.uniform(-2.0, 5.0, shape)


API = {
    "fresnel_conductor": lambda r: basis.fresnel_conductor(_random_value(r), _random_value(r), _random_value(r)),
    "coefficients_from_nk": lambda r: basis.coefficients_from_nk(_random_value(r), _random_value(r)),
    "coefficients_least_squares": lambda r: basis.coefficients_least_squares(_random_value(r), _random_value(r)),
    "coefficients_from_gulbrandsen": lambda r: basis.coefficients_from_gulbrandsen(_random_value(r), _random_value(r)),
    "coefficients_from_samples": lambda r: basis.coefficients_from_samples(_random_value(r)),
    "reconstruct": lambda r: basis.reconstruct(_random_value(r), _random_value(r)),
    "material_coefficients": lambda r: basis.material_coefficients(_random_value(r), _random_value(r)),
    "gulbrandsen_to_nk": lambda r: basis.gulbrandsen_to_nk(_random_value(r), _random_value(r)),
    "nk_to_gulbrandsen": lambda r: basis.nk_to_gulbrandsen(_random_value(r), _random_value(r)),
    "coefficients_from_curve": lambda r: basis.coefficients_from_curve(lambda x: np.full(int(r.integers(1, 6)), 0.5)),
    "compensated_albedo": lambda r: multiple_scattering.compensated_albedo(
        _random_value(r), _random_value(r), _random_value(r)
    ),
    "basis_albedo": lambda r: multiple_scattering.basis_albedo(
        _random_value(r), _random_value(r), _random_value(r), shipped.shipped_tables()
    ),
    "average_albedo": lambda r: multiple_scattering.average_albedo(_random_value(r)),
    "ktx2_bytes": lambda r: formats.ktx2_bytes(_random_value(r), {}, half=bool(r.integers(2))),
}


def fuzz_api(rng, count: int) -> Outcome:
    outcome = Outcome()
    names = list(API)
    for index in range(count):
        name = names[index % len(names)]
        _api_outcome(outcome, lambda: API[name](rng), f"{name} case {index}")
    return outcome


def _snapshot(folder: Path) -> dict[str, str]:
    """name → SHA-256 of every entry of ``folder`` (links by their target)."""
    found = {}
    for path in sorted(folder.iterdir()):
        if path.is_symlink():
            found[path.name] = "link:" + os.readlink(path)
        elif path.is_file():
            found[path.name] = hashlib.sha256(path.read_bytes()).hexdigest()
        else:
            found[path.name] = "folder"
    return found


_BUILD = ["build", "--size", "4", "--order", "4"]
_SET = re.compile(r"ggx_(basis_rgba(_2)?|schlick_rgba?|albedo_average|ltc)\.(exr|png|ktx2|h)$")


def _journal_document(rng) -> object:
    """A journal as a killed build leaves it, mutated: names outside the folder, absolute paths, odd values."""
    names = ["ggx_basis_rgba.exr", "ggx_schlick_rgba.exr", "ggx_albedo_average.exr", "../outside.txt", "/etc/hostname"]
    renames = []
    for _ in range(int(rng.integers(0, 4))):
        target = names[int(rng.integers(len(names)))]
        temporary = f".{target}.{''.join(rng.choice(list('abcdefgh12345678'), 8))}.tmp"
        renames.append([temporary if rng.random() < 0.7 else target, target])
    removals = [names[int(rng.integers(len(names)))] for _ in range(int(rng.integers(0, 3)))]
    if rng.random() < 0.5:  # the format before journals proved their files
        document = {"format": "fresnel-basis/journal", "version": 2, "renames": renames, "removals": removals}
    else:  # today's, with made-up identities (device, inode, change time, size)
        identity = lambda: [int(value) for value in rng.integers(0, 2**40, 4)]  # noqa: E731
        document = {
            "format": "fresnel-basis/journal",
            "version": 3,
            "renames": [[*pair, identity()] for pair in renames],
            "removals": [[name, identity()] for name in removals],
        }
    return _mutate(rng, document) if rng.random() < 0.5 else document


def fuzz_journals(rng, count: int, folder: Path, base: Path) -> Outcome:
    """A built folder with a crafted journal (and some of its temporaries): reading a table changes nothing, a
    build finishes or refuses with one line, and neither touches the file beside the folder."""
    outcome = Outcome()
    outside = folder / "outside.txt"
    for index in range(count):
        case = folder / f"journal{index}"
        shutil.copytree(base, case)
        document = _journal_document(rng)
        (case / ".fresnel-lut-journal.json").write_text(json.dumps(document), encoding="utf-8")
        renames = document.get("renames") if isinstance(document, dict) else None
        for pair in renames if isinstance(renames, list) else []:
            if (
                isinstance(pair, list)
                and pair
                and isinstance(pair[0], str)
                and "/" not in pair[0]
                and rng.random() < 0.6
            ):
                with contextlib.suppress(OSError, ValueError):
                    (case / pair[0]).write_bytes(rng.bytes(32))
        outside.write_text("keep me", encoding="utf-8")
        before = _snapshot(case)
        _api_outcome(outcome, lambda: exr.read_lut(case / "ggx_basis_rgba.exr")[0], f"journal case {index} read")
        if _snapshot(case) != before:
            outcome.add("crashed", f"journal case {index}: reading a table changed the folder: {document}")
        _cli_outcome(outcome, [*_BUILD, "--out", str(case)])
        if outside.read_text(encoding="utf-8") != "keep me":
            outcome.add("crashed", f"journal case {index}: a file outside the folder changed: {document}")
        shutil.rmtree(case)
    return outcome


def fuzz_stale_tables(rng, count: int, folder: Path, base: Path) -> Outcome:
    """A folder holding the set of other builds (a second basis table, other formats, temporaries) and a file of
    the user's: a build in some formats leaves exactly its own set and the user's file."""
    outcome = Outcome()
    stale = [
        "ggx_basis_rgba_2.exr",
        "ggx_basis_rgba_2.png",
        "ggx_basis_rgba.ktx2",
        "ggx_schlick_rgba.h",
        ".ggx_basis_rgba.exr.AbCdEf12.tmp",
        ".ggx_schlick_rgba.png.zzzzzzzz.tmp",
    ]
    choices = ["exr", "exr,ktx2", "png16", "exr,png16,header", "ktx2"]
    for index in range(count):
        case = folder / f"stale{index}"
        shutil.copytree(base, case)
        for name in rng.choice(stale, size=int(rng.integers(1, len(stale))), replace=False):
            (case / name).write_bytes(rng.bytes(16))
        (case / "notes.txt").write_text("mine", encoding="utf-8")
        formats_asked = choices[int(rng.integers(len(choices)))]
        _cli_outcome(outcome, [*_BUILD, "--format", formats_asked, "--out", str(case)])
        names = {path.name for path in case.iterdir()}
        suffixes = {"exr": ".exr", "ktx2": ".ktx2", "png16": ".png", "header": ".h"}
        wanted = {suffixes[name] for name in formats_asked.split(",")}
        leftovers = sorted(
            name
            for name in names
            if (_SET.fullmatch(name) and Path(name).suffix not in wanted) or name.endswith(".tmp")
        )
        leftovers += sorted(name for name in names if name.startswith("ggx_basis_rgba_2"))
        if leftovers or "notes.txt" not in names:
            outcome.add(
                "crashed", f"stale case {index} ({formats_asked}): left {leftovers}, notes kept: {'notes.txt' in names}"
            )
        shutil.rmtree(case)
    return outcome


#: What a hostile name is made of: line breaks of every kind, comment delimiters, a preprocessor line, backslashes,
#: NUL, a bidi override, non-Latin-1 text and the marker that must never reach code.
_HOSTILE_PARTS = [
    "\n",
    "\r",
    "\r\n",
    "\u2028",
    "\u2029",
    "\x0b",
    "\x0c",
    "\x85",
    "*/",
    "/*",
    "#define",
    "#pragma",
    "\\",
    "\x00",
    "\u202e",
    "\u91d1",
    "\u00fc",
    "\U0001f600",
    "`",
    '"',
    "float injected() { return 1.0; }",
    "injected",
    " ",
]


def _hostile_name(rng) -> str:
    return "".join(_HOSTILE_PARTS[int(index)] for index in rng.integers(0, len(_HOSTILE_PARTS), 6)) + "injected"


def _inert_everywhere(files: dict[str, bytes]) -> str:
    """'' where no written file carries the hostile text as anything but a comment or an attribute, else why."""
    for name, data in files.items():
        if name.endswith((".glsl", ".hlsl", ".wgsl")):
            text = data.decode("utf-8")
            for line in text.splitlines():
                if "injected" in line and (not line.lstrip().startswith("//") or line.endswith("\\")):
                    return f"{name}: code line {line[:80]!r}"
            if not text.isascii() or "\r" in text or "\x00" in text:
                return f"{name}: a control or non-ASCII character"
        elif name.endswith(".h"):
            text = data.decode("utf-8")
            comment, _, rest = text.partition("*/")
            if "injected" in rest or "*/" in rest or not text.isascii():
                return f"{name}: the comment closes early or holds non-ASCII text"
        elif name.endswith(".md"):
            title = data.decode("utf-8").splitlines()[0]
            if not title.isascii():
                return f"{name}: title {title[:80]!r}"
    return ""


def fuzz_generated_names(rng, count: int, folder: Path) -> Outcome:
    """Issue 36: hostile text as a command line (the includes' comment, every table format's attributes) and as a
    scene file's name (through ``fresnel-lut scene``): every file written carries it inert, and reads back."""
    from handoff.shaders import shader_includes
    from handoff.tables import Table, write_tables

    outcome = Outcome()
    for index in range(count):
        name = _hostile_name(rng)
        case = folder / f"names{index}"
        try:
            files = {file: text.encode("utf-8") for file, text in shader_includes(command=f"fresnel-lut scene {name}")}
            table = Table("ggx_fuzzed", np.full((2, 3, 1), 0.5), ("Y",), {"generator": name, "channels": "Y"})
            for path in write_tables([table], case, list(formats.FORMATS)):
                files[path.name] = path.read_bytes()
            exr.read_lut(case / "ggx_fuzzed.exr")
        except Exception:  # noqa: BLE001 - every exception is a crash here: the text must be written, not refused
            outcome.add("crashed", f"names case {index} {name!r}: {traceback.format_exc().strip().splitlines()[-1]}")
            continue
        problem = _inert_everywhere(files)
        outcome.add("crashed" if problem else "accepted", f"names case {index} {name!r}: {problem}")
        shutil.rmtree(case, ignore_errors=True)
    for index in range(max(1, count // 20)):  # the slow path: a real scene file so named, through the command
        name = _hostile_name(rng).replace("/", "").replace("\x00", "")
        case = folder / f"scene_names{index}"
        case.mkdir()
        scene = case / name
        scene.write_text('[[material]]\nname = "g"\npreset = "Gold"\nroughness = [0.3, 0.5]\n', encoding="utf-8")
        _cli_outcome(outcome, ["scene", "--out", str(case / "out"), "--format", "exr,header", "--", str(scene)])
        written = {path.name: path.read_bytes() for path in (case / "out").iterdir()} if (case / "out").exists() else {}
        problem = _inert_everywhere(written)
        if problem:
            outcome.add("crashed", f"scene named {name!r}: {problem}")
        shutil.rmtree(case, ignore_errors=True)
    return outcome


#: A user's files in an output folder, which no command may replace or remove.
_USER_FILES = {"notes.txt": b"a user's notes", "basis.json": b"{}", "materials.json": b"{}", ".keep": b""}


def fuzz_crafted_folders(rng, count: int, folder: Path, base: Path) -> Outcome:
    """Issue 36: a built folder with a user's files, a crafted journal naming them (v2 or v3, some as FIFOs or links
    to /dev/zero) and a crafted ``scene_coefficients.json`` listing the build's tables: a build and a scene into it
    end (within a bound) with 0 or one line, and leave the user's files and the build's tables as they were."""
    outcome = Outcome()
    targets = ["notes.txt", "basis.json", "materials.json", ".keep", "ggx_basis_rgba.exr", "ggx_ltc.exr"]
    (folder / "gold.toml").write_text('[[material]]\nname = "g"\npreset = "Gold"\nroughness = 0.5\n', encoding="utf-8")
    for index in range(count):
        case = folder / f"crafted{index}"
        shutil.copytree(base, case)
        for name, data in _USER_FILES.items():
            (case / name).write_bytes(data)
        journal = case / ".fresnel-lut-journal.json"
        kind = rng.random()
        if kind < 0.2:
            os.mkfifo(journal)
        elif kind < 0.3:
            journal.symlink_to("/dev/zero")
        else:
            chosen = [targets[int(i)] for i in rng.integers(0, len(targets), 3)]
            identity = [int(value) for value in rng.integers(0, 2**40, 4)]
            for target in chosen:
                (case / f".{target}.abcdefgh.tmp").write_bytes(rng.bytes(16))
            journal.write_text(
                json.dumps(
                    {
                        "format": "fresnel-basis/journal",
                        "version": int(rng.choice([2, 3])),
                        "renames": [[f".{target}.abcdefgh.tmp", target, identity] for target in chosen],
                        "removals": [[target, identity] for target in chosen],
                    }
                ),
                encoding="utf-8",
            )
        (case / "scene_coefficients.json").write_text(
            json.dumps({"materials": {"m": {"lut": targets[int(rng.integers(len(targets)))]}}}), encoding="utf-8"
        )
        kept = {name: (case / name).read_bytes() for name in ("ggx_basis_rgba.exr", "ggx_schlick_rgba.exr")}
        _cli_outcome_within(outcome, ["scene", str(folder / "gold.toml"), "--out", str(case)], 60)
        changed = [name for name, data in kept.items() if (case / name).read_bytes() != data]
        _cli_outcome_within(outcome, [*_BUILD, "--out", str(case)], 60)
        changed += [
            name
            for name, data in _USER_FILES.items()
            if not (case / name).is_file() or (case / name).read_bytes() != data
        ]
        if changed:
            outcome.add("crashed", f"crafted case {index}: {changed} replaced or removed")
        shutil.rmtree(case, ignore_errors=True)
    return outcome


def _within(seconds: float, call):
    """(finished, the call's result or exception): the call in a daemon thread, abandoned after ``seconds``."""
    import threading

    box: dict = {}

    def target():
        try:
            box["result"] = call()
        except BaseException as error:  # noqa: BLE001 - handed back to the caller
            box["error"] = error

    worker = threading.Thread(target=target, daemon=True)
    worker.start()
    worker.join(seconds)
    return not worker.is_alive(), box


def _cli_outcome_within(outcome: Outcome, argv: list[str], seconds: float) -> None:
    finished, _ = _within(seconds, lambda: _cli_outcome(outcome, argv))
    if not finished:
        outcome.add("crashed", f"{argv}: still running after {seconds} s")


def fuzz_special_files(rng, count: int, folder: Path) -> Outcome:
    """Issue 36: FIFOs, devices that never end, links to them and folders where a basis, presets, scene, table or
    environment file is expected: each is refused with one line within a second, never read."""
    from basis.presets import material_presets
    from fresnel_lut.view import read_environment

    readers = {
        "basis": lambda path: Basis.read(path),
        "presets": lambda path: material_presets(path),
        "scene": lambda path: read_scene(path),
        "table": lambda path: exr.read_lut(path),
        "environment": lambda path: read_environment(path),
    }
    outcome = Outcome()
    for index in range(count):
        kind = ["fifo", "zero", "link", "folder", "urandom"][int(rng.integers(5))]
        path = folder / f"special{index}.json"
        if kind == "fifo":
            os.mkfifo(path)
        elif kind == "folder":
            path.mkdir()
        elif kind == "link":
            path.symlink_to("/dev/zero")
        else:
            path = Path("/dev/zero" if kind == "zero" else "/dev/urandom")
        reader = list(readers)[int(rng.integers(len(readers)))]
        finished, box = _within(5.0, lambda: readers[reader](path))
        if not finished:
            outcome.add("crashed", f"{reader} of a {kind}: still reading after 5 s")
        elif isinstance(box.get("error"), ParameterError) and len(str(box["error"]).splitlines()) == 1:
            outcome.add("refused")
        else:
            outcome.add("crashed", f"{reader} of a {kind}: {box.get('error') or 'accepted'!r}")
        if kind == "folder":
            path.rmdir()
        elif kind in ("fifo", "link"):
            path.unlink()
    return outcome


def _request_line(rng) -> bytes:
    """A request as a browser, a scanner or an attacker sends it: odd methods, paths, versions, Host headers."""
    methods = [b"GET", b"HEAD", b"POST", b"BREW", b"", b"G\x00T", b"get"]
    paths = [
        b"/",
        b"/config.json",
        b"http://[/",
        b"/%00",
        b"/..%2f..%2fetc/passwd",
        b"*",
        b"/" + b"a" * 5000,
        b"\xff\xfe",
    ]
    versions = [b"HTTP/1.1", b"HTTP/1.0", b"HTTP/9.9", b"", b"HTTP/1.1 extra", b"FTP/1.0"]
    hosts = [b"127.0.0.1", b"localhost", b"evil.example", b"[::1", b"", b"127.0.0.1:1", b"a" * 300]
    pick = lambda options: options[int(rng.integers(len(options)))]  # noqa: E731
    line = b" ".join(part for part in (pick(methods), pick(paths), pick(versions)) if part)
    headers = b"" if rng.random() < 0.2 else b"Host: " + pick(hosts) + b"\r\n"
    if rng.random() < 0.2:
        headers += bytes(rng.integers(0, 256, int(rng.integers(1, 200)), dtype=np.uint8))
    return line + b"\r\n" + headers + b"\r\n"


def fuzz_http_requests(rng, count: int) -> Outcome:
    """Issue 36: request lines and headers sent to ``fresnel-lut view``'s server as they are: every one gets an HTTP
    status line (or, for a client that sends nothing readable, a closed connection), nothing is printed, and the
    server still serves the page afterwards."""
    import socket

    from fresnel_lut.view import serving

    outcome = Outcome()
    files = {"/": (b"page", "text/html"), "/config.json": (b"{}", "application/json")}
    printed = io.StringIO()
    with contextlib.redirect_stderr(printed), serving(files) as server:
        port = server.server_address[1]
        for index in range(count):
            request = _request_line(rng)
            try:
                with socket.create_connection(("127.0.0.1", port), timeout=5) as connection:
                    connection.sendall(request)
                    connection.shutdown(socket.SHUT_WR)
                    answer = b""
                    while chunk := connection.recv(65536):
                        answer += chunk
            except OSError as error:
                outcome.add("crashed", f"request {request[:60]!r}: {error}")
                continue
            if re.match(rb"HTTP/1\.[01] [1-5]\d\d ", answer):
                outcome.add("refused" if not answer.startswith(b"HTTP/1.0 200") else "accepted")
            else:
                outcome.add("crashed", f"request {request[:60]!r}: answered {answer[:60]!r}")
        with socket.create_connection(("127.0.0.1", port), timeout=5) as connection:
            connection.sendall(b"GET / HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n")
            alive = connection.recv(64).startswith(b"HTTP/1.0 200")
    if not alive or printed.getvalue():
        outcome.add("crashed", f"after the requests: serving {alive}, printed {printed.getvalue()[:200]!r}")
    return outcome


def _nested(rng, depth: int):
    value = 0.5
    for _ in range(depth):
        value = [value] if rng.random() < 0.5 else {"a": value}
    return value


def fuzz_nested_files(rng, count: int, folder: Path) -> Outcome:
    """Basis, preset and scene files nested 2 … 100 000 deep (JSON and TOML): refused with one line, never a
    RecursionError."""
    outcome = Outcome()
    readers = {
        "basis": lambda path: Basis.read(path),
        "presets": lambda path: material_presets(path),
        "scene": lambda path: read_scene(path).tolerance,
    }
    for index in range(count):
        kind = list(readers)[index % len(readers)]
        depth = int(10 ** rng.uniform(0.3, 5.0))
        if kind == "scene" and rng.random() < 0.5:
            path = folder / f"nested{index}.toml"
            path.write_text("tolerance = " + "[" * depth + "1" + "]" * depth + "\n", encoding="utf-8")
        else:
            path = folder / f"nested{index}.json"
            path.write_text(
                "[" * depth + "1" + "]" * depth
                if rng.random() < 0.5
                else json.dumps({"curves": _nested(rng, min(depth, 900))}),
                encoding="utf-8",
            )
        _api_outcome(outcome, lambda: readers[kind](path), f"nested {kind} case {index} (depth {depth})")
    return outcome


MASKED = {
    "coefficients_from_nk": lambda eta, other: basis.coefficients_from_nk(eta, other),
    "fresnel_conductor": lambda eta, other: basis.fresnel_conductor(other, eta, other),
    "coefficients_from_gulbrandsen": lambda eta, other: basis.coefficients_from_gulbrandsen(other, other),
    "reconstruct": lambda eta, other: basis.reconstruct(np.ma.stack([eta] * 4, axis=-1), other),
    "average_albedo": lambda eta, other: multiple_scattering.average_albedo(other),
}


def fuzz_masked_arrays(rng, count: int) -> Outcome:
    """API calls given numpy masked arrays: refused where an entry is masked (its hidden value would be used), the
    plain values used where none is."""
    outcome = Outcome()
    names = list(MASKED)
    for index in range(count):
        name = names[index % len(names)]
        shape = (int(rng.integers(1, 5)),)
        mask = rng.random(shape) < (0.0 if rng.random() < 0.3 else 0.5)
        eta = np.ma.array(rng.uniform(0.5, 3.0, shape), mask=mask)
        other = np.ma.array(rng.uniform(0.0, 1.0, shape), mask=mask if rng.random() < 0.5 else np.zeros(shape, bool))
        _api_outcome(outcome, lambda: MASKED[name](eta, other), f"masked {name} case {index} (mask {mask.tolist()})")
    return outcome


COMBINATIONS = {
    "build": ["--ltc", "--ltc-size", "--format", "--half", "--visibility", "--model", "--basis", "--exponent"],
    "coeffs": ["--list-materials", "--json", "--material", "--space", "--basis", "--model", "--f0", "--fit"],
    "report": ["--quick", "--materials", "--fidelity"],
}
COMBINATION_VALUES = [
    "6",
    "2",
    "1",
    "exr,ktx2",
    "png16",
    "header",
    "separable",
    "height-correlated",
    "Gold",
    "sRGB",
    "f82",
    "schlick",
    "least-squares",
    "nope",
    "0.5",
    "-1",
]


def fuzz_option_combinations(rng, count: int, folder: Path) -> Outcome:
    """Options that go together or do not (``--ltc`` with ``--model``, ``--ltc-size`` alone, ``report --quick
    --materials``, ``coeffs --list-materials --json`` …): each either runs or is refused with one line, none is
    ignored without a word (the refusals are the project's own checks, counted as refused)."""
    outcome = Outcome()
    for index in range(count):
        command = list(COMBINATIONS)[int(rng.integers(len(COMBINATIONS)))]
        argv = [command]
        for option in rng.choice(COMBINATIONS[command], size=int(rng.integers(1, 4)), replace=False):
            argv.append(str(option))
            if option not in ("--ltc", "--half", "--json", "--list-materials", "--quick", "--materials", "--fidelity"):
                argv.append(COMBINATION_VALUES[int(rng.integers(len(COMBINATION_VALUES)))])
        if command == "report":
            if "--materials" not in argv or len(argv) < 3:
                continue  # a report that would run takes minutes: only the combinations it must refuse
            argv += ["--out", str(folder / f"report{index}")]
        if command == "build":
            argv += ["--size", "4", "--order", "4", "--out", str(folder / f"combination{index}")]
            if "--ltc" in argv and "--ltc-size" not in argv:
                argv += ["--ltc-size", "6"]  # the default 64 x 64 fit takes half a minute (the rebuild test runs it)
            if "--ltc-size" in argv:
                position = argv.index("--ltc-size") + 1
                if position < len(argv) and argv[position].lstrip("-").isdigit() and int(argv[position]) > 6:
                    argv[position] = "6"
        _cli_outcome(outcome, argv)
    return outcome


@contextlib.contextmanager
def _working_folder(folder: Path):
    """Relative output paths that the mutated options name land in the scratch folder, never in the checkout."""
    previous = Path.cwd()
    os.chdir(folder)
    try:
        yield
    finally:
        os.chdir(previous)


def fuzz(cases: int = 1000, seed: int = 17) -> dict[str, Outcome]:
    rng = np.random.default_rng(seed)
    with tempfile.TemporaryDirectory(prefix="fresnel-fuzz-") as scratch, _working_folder(Path(scratch)):
        folder = Path(scratch)
        (folder / "scene1.json").write_text(json.dumps(SCENE), encoding="utf-8")
        base = folder / "base"
        with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
            assert cli.main([*_BUILD, "--out", str(base)]) == 0
        return {
            "scene files": fuzz_scenes(rng, cases, folder),
            "preset files": fuzz_presets(rng, cases, folder),
            "basis files": fuzz_bases(rng, cases // 2, folder),
            "CLI options": fuzz_cli(rng, cases, folder),
            "API calls": fuzz_api(rng, 2 * cases),
            "journals": fuzz_journals(rng, max(1, cases // 10), folder, base),
            "stale tables": fuzz_stale_tables(rng, max(1, cases // 10), folder, base),
            "nested files": fuzz_nested_files(rng, max(1, cases // 5), folder),
            "masked arrays": fuzz_masked_arrays(rng, cases),
            "option combinations": fuzz_option_combinations(rng, max(1, cases // 5), folder),
            "names into generated files": fuzz_generated_names(rng, max(1, cases // 10), folder),
            "crafted folders": fuzz_crafted_folders(rng, max(1, cases // 20), folder, base),
            "FIFOs, devices, endless files": fuzz_special_files(rng, max(1, cases // 10), folder),
            "HTTP requests": fuzz_http_requests(rng, cases),
        }


def markdown(results: dict[str, Outcome], seed: int) -> str:
    lines = [
        "# Fuzzing",
        "",
        f"`python -m benchmarks.fuzz --seed {seed}`, {datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M} UTC: "
        "seeded mutations of valid inputs; refused = one-line error, accepted = exit 0 or a finite result, "
        "crashed = anything else.",
        "",
        "| category | tried | refused with one line | accepted | crashed |",
        "|---|---:|---:|---:|---:|",
    ]
    for name, outcome in results.items():
        lines.append(f"| {name} | {outcome.tried} | {outcome.refused} | {outcome.accepted} | {outcome.crashed} |")
    total = sum(outcome.crashed for outcome in results.values())
    lines += ["", f"Crashed in all: {total}."]
    for name, outcome in results.items():
        for crash in outcome.crashes:
            lines += ["", f"- {name}: `{crash}`"]
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--cases", type=int, default=1000, help="cases per category (basis files: half, API calls: twice)"
    )
    parser.add_argument("--seed", type=int, default=17)
    parser.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[1] / "report" / "fuzz.md")
    arguments = parser.parse_args(argv)
    results = fuzz(arguments.cases, arguments.seed)
    text = markdown(results, arguments.seed)
    from basis.storage import write_text

    write_text(arguments.out, text)
    print(text)
    return 1 if any(outcome.crashed for outcome in results.values()) else 0


if __name__ == "__main__":
    sys.exit(main())
