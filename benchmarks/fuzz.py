"""Fuzz the inputs users and files give the project, and count what happens to each case.

Run from the repository root: ``.venv/bin/python -m benchmarks.fuzz [--cases N] [--seed S] [--out FILE]``.
Seeded mutations of valid inputs in five categories — scene files, preset files (``materials.json``),
basis files (``basis.json``), CLI options and API calls — each end as one of:

* **refused**: a one-line error (exit status 2 and one ``fresnel-lut: error: …`` line, or a
  ``ParameterError`` whose message is one line);
* **accepted**: exit status 0, or a finite result;
* **crashed**: anything else — a traceback, another exception, a multi-line error, NaN or inf returned.

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
from preintegrate import formats, multiple_scattering

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
        return {
            "scene files": fuzz_scenes(rng, cases, folder),
            "preset files": fuzz_presets(rng, cases, folder),
            "basis files": fuzz_bases(rng, cases // 2, folder),
            "CLI options": fuzz_cli(rng, cases, folder),
            "API calls": fuzz_api(rng, 2 * cases),
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
