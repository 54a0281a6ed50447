"""Fuzz the inputs users and files give the project, and count what happens to each case.

Run from the repository root: ``.venv/bin/python -m benchmarks.fuzz [--cases N] [--seed S] [--out FILE]``.
Seeded mutations of valid inputs in ten categories — scene files, preset files (``materials.json``),
basis files (``basis.json``), CLI options and API calls; and (issue 26) crafted journals, stale tables, deeply nested
files, masked arrays and combinations of options — each end as one of:

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
from preintegrate import exr, formats, multiple_scattering

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
    "basis_albedo": lambda r: multiple_scattering.basis_albedo(_random_value(r), _random_value(r), _random_value(r)),
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
_SET = re.compile(r"ggx_(basis_rgba(_2)?|schlick_rgb|albedo_average|ltc)\.(exr|png|ktx2|h)$")


def _journal_document(rng) -> object:
    """A journal as a killed build leaves it, mutated: names outside the folder, absolute paths, odd values."""
    names = ["ggx_basis_rgba.exr", "ggx_schlick_rgb.exr", "ggx_albedo_average.exr", "../outside.txt", "/etc/hostname"]
    renames = []
    for _ in range(int(rng.integers(0, 4))):
        target = names[int(rng.integers(len(names)))]
        temporary = f".{target}.{''.join(rng.choice(list('abcdefgh12345678'), 8))}.tmp"
        renames.append([temporary if rng.random() < 0.7 else target, target])
    document = {
        "format": "fresnel-basis/journal",
        "version": 2,
        "renames": renames,
        "removals": [names[int(rng.integers(len(names)))] for _ in range(int(rng.integers(0, 3)))],
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
        "ggx_schlick_rgb.h",
        ".ggx_basis_rgba.exr.AbCdEf12.tmp",
        ".ggx_schlick_rgb.png.zzzzzzzz.tmp",
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
