"""The bad inputs of the command line, as data: every option fuzzed (negative, zero, NaN, inf, huge, strings, empty and
missing values) and corrupt or foreign basis files. ``tests/stability/test_faults.py`` checks each case's contract
(exit 2, one line naming the option, nothing written) and ``benchmarks/stability_table.py`` tallies them.

Public objects: ``BASES``, ``FUZZ``, ``FLOAT_OPTIONS``, ``BAD_BASIS``, ``with_option``, ``valid_triple``, ``option_named``,
``rehashed``, ``write_file``, ``exr_file``.
"""

from __future__ import annotations

import hashlib
import json

import numpy as np

from basis.eigenbasis import shipped_basis_path
from handoff import exr

__all__ = [
    "BAD_BASIS",
    "BASES",
    "FLOAT_OPTIONS",
    "FUZZ",
    "exr_file",
    "option_named",
    "rehashed",
    "valid_triple",
    "with_option",
    "write_file",
]

# Each case: (base argv, option, bad value or None for a missing value, fragment the error must contain).
#: Values of the wrong type or form: argparse refuses them ("invalid int value", "expected one argument").
NOT_INTEGERS = ["nan", "inf", "-inf", "1e9", "1.5", "x", "", "0x10", "2**10"]
#: argparse reads "-inf", "-1e999", "-1e-9" as option names, not negative numbers: "expected 3 arguments".
NOT_FLOATS = ["x", "", "0x1p3", "1,5", "-inf", "-1e999", "-1e-9"]
#: Non-finite values of the right type: refused by the library, whose message says "must be finite".
NON_FINITE = ["nan", "inf", "1e999", "NaN", "Infinity"]

# ----------------------------------------------------------------------------- the fuzz table
# Each case: (base argv, option, bad value or None for a missing value, fragment the error must contain).
BASES = {
    "build": ["build", "--size", "4"],
    "basis": ["basis", "--count", "100", "--out", "fuzz-basis.json"],
    "coeffs_nk": ["coeffs", "--eta", "1.5", "1.5", "1.5", "--kappa", "0", "0", "0"],
    "coeffs_gulbrandsen": ["coeffs", "--reflectivity", "0.5", "0.5", "0.5", "--edge-tint", "0", "0", "0"],
}
INTEGER_OPTIONS = {  # option: (base, out-of-range values of the right type)
    "--size": ("build", ["0", "1", "-5", "8193", "99999999999999999999999"]),
    "--order": ("build", ["0", "1", "-1", "513", "10000000000"]),
    "--count": ("basis", ["0", "-1", "99", "100000001", "99999999999999999999999"]),
    "--grid-size": ("basis", ["0", "15", "-16", "65537"]),
    "--terms": ("basis", ["0", "1", "-3", "17", "1000"]),
    "--seed": ("basis", []),  # every integer is a valid seed except negative ones: see test_negative_seed
}
CHOICE_OPTIONS = {"--fit-angles": ("basis", ["", "bogus", "TALK", "1.3", "nan", "auto,talk"])}
FLOAT_OPTIONS = {  # option: (base, out-of-range values of the right type), each tried in channel R, G or B
    "--eta": ("coeffs_nk", ["0", "-1", "1e7", "1e-9", "-0.5"]),
    "--kappa": ("coeffs_nk", ["-1", "1e7", "-0.000001"]),
    "--reflectivity": ("coeffs_gulbrandsen", ["-0.1", "1", "1.5", "1.0000000001"]),
    "--edge-tint": ("coeffs_gulbrandsen", ["-0.5", "1.1", "2"]),
}


def with_option(base, option, values):
    """base argv with ``option`` set to ``values`` (a list), replacing it if present."""
    argv = list(BASES[base])
    if option in argv:
        start = argv.index(option)
        end = start + 1
        while end < len(argv) and not argv[end].startswith("--"):
            end += 1
        del argv[start:end]
    return argv + [option, *values]


def valid_triple(option):
    """Valid values of a three-channel option."""
    return {"--eta": ["1.5"] * 3, "--kappa": ["0"] * 3, "--reflectivity": ["0.5"] * 3, "--edge-tint": ["0"] * 3}[option]


def _cases():
    cases = {}
    for option, (base, out_of_range) in INTEGER_OPTIONS.items():
        for value in out_of_range:
            cases[f"{option}={value}"] = (with_option(base, option, [value]), "range")
        for value in NOT_INTEGERS:
            cases[f"{option}={value!r}"] = (with_option(base, option, [value]), "type")
        cases[f"{option} missing"] = (with_option(base, option, []), "type")
    for option, (base, out_of_range) in CHOICE_OPTIONS.items():
        for value in out_of_range:
            cases[f"{option}={value!r}"] = (with_option(base, option, [value]), "range")
        cases[f"{option} missing"] = (with_option(base, option, []), "type")
    for option, (base, out_of_range) in FLOAT_OPTIONS.items():
        kinds = {
            **{value: "range" for value in out_of_range},
            **{value: "type" for value in NOT_FLOATS},
            **{value: "nonfinite" for value in NON_FINITE},
        }
        for index, (value, kind) in enumerate(kinds.items()):
            triple = valid_triple(option)
            triple[index % 3] = value  # the bad value in channel R, G or B in turn
            cases[f"{option}[{index % 3}]={value!r}"] = (with_option(base, option, triple), kind)
        cases[f"{option} two values"] = (with_option(base, option, ["1", "1"]), "type")
        cases[f"{option} four values"] = (with_option(base, option, ["1", "1", "1", "1"]), "usage")
        cases[f"{option} missing"] = (with_option(base, option, []), "type")
    cases["build --half 1"] = (["build", "--size", "4", "--half", "1"], "usage")
    cases["coeffs --json x"] = (BASES["coeffs_nk"] + ["--json", "x"], "usage")
    cases["coeffs eta without kappa"] = (["coeffs", "--eta", "1", "1", "1"], "usage")
    cases["coeffs edge-tint without reflectivity"] = (["coeffs", "--edge-tint", "0", "0", "0"], "usage")
    cases["coeffs both materials"] = (
        BASES["coeffs_nk"] + ["--reflectivity", "0.5", "0.5", "0.5", "--edge-tint", "0", "0", "0"],
        "usage",
    )
    cases["unknown command"] = (["bogus"], "type")
    cases["report unknown option"] = (["report", "--bogus"], "type")
    cases["report --out missing"] = (["report", "--out"], "type")
    return cases


FUZZ = _cases()


def option_named(line: str, argv) -> bool:
    """The error line names one of the options given (as --name, name or name_with_underscores) or the command."""
    names = [item for item in argv if item.startswith("--")] or argv[:1]
    return any(name in line or name.lstrip("-") in line or name.lstrip("-").replace("-", "_") in line for name in names)


def _shipped_text():
    return shipped_basis_path().read_text(encoding="utf-8")


def rehashed(edit):
    """The shipped basis with ``edit(data)`` applied and its content hash recomputed (a consistent-looking file)."""
    data = json.loads(_shipped_text())
    edit(data)
    # The documented hash (Basis.content_hash): SHA-256 of the little-endian float64 bytes, first 16 hex digits;
    # recomputed here because Basis itself refuses to hold a degenerate basis.
    digest = hashlib.sha256()
    for key in ("theta", "curves", "fit_angles"):
        digest.update(np.ascontiguousarray(np.asarray(data[key], dtype="<f8")).tobytes())
    data["content_hash"] = digest.hexdigest()[:16]
    return json.dumps(data)


def _edited(old, new):
    text = _shipped_text()
    assert text.count(old) == 1
    return text.replace(old, new)


def write_file(folder, name, content):
    """``content`` (bytes or text) written to ``folder/name``; the path."""
    path = folder / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode("utf-8"))
    return path


def exr_file(folder):
    """A valid EXR of this project's (not a basis file) in ``folder``; its path."""
    path = folder / "lut.exr"
    exr.write_lut(path, np.zeros((4, 4, 1)), ("R",), {"channels": "R"})
    return path


def _nan_curve(data):
    data["curves"][2][7] = float("nan")


BAD_BASIS = {
    "empty file": lambda d: write_file(d, "b.json", b""),
    "EXR file": exr_file,
    "PNG bytes": lambda d: write_file(d, "b.json", b"\x89PNG\r\n\x1a\n" + bytes(64)),
    "latin-1 bytes": lambda d: write_file(d, "b.json", '{"format": "é"}'.encode("latin-1")),
    "UTF-16 JSON": lambda d: write_file(d, "b.json", _shipped_text().encode("utf-16")),
    "JSON list": lambda d: write_file(d, "b.json", "[1, 2, 3]"),
    "JSON null": lambda d: write_file(d, "b.json", "null"),
    "foreign format": lambda d: write_file(d, "b.json", json.dumps({"format": "other/thing@1", "curves": []})),
    "no format": lambda d: write_file(
        d, "b.json", json.dumps({k: v for k, v in json.loads(_shipped_text()).items() if k != "format"})
    ),
    "truncated 10%": lambda d: write_file(d, "b.json", _shipped_text()[: len(_shipped_text()) // 10]),
    "truncated 99%": lambda d: write_file(d, "b.json", _shipped_text()[: len(_shipped_text()) * 99 // 100]),
    "hash mismatch in fit angle": lambda d: write_file(
        d, "b.json", _edited('"fit_angles": [\n  0.0,', '"fit_angles": [\n  0.001,')
    ),
    "NaN token": lambda d: write_file(d, "b.json", _edited('"theta": [\n  0.0,', '"theta": [\n  NaN,')),
    "1e999 token": lambda d: write_file(d, "b.json", _edited('"theta": [\n  0.0,', '"theta": [\n  1e999,')),
    "directory": lambda d: (d / "a_folder").mkdir() or d / "a_folder",
    "empty path": lambda d: "",
    "missing": lambda d: d / "nope.json",
}
