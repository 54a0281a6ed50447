"""A short run of the fuzz harness (benchmarks/fuzz.py): scene, preset and basis files, CLI options and API
calls mutated from valid inputs, crafted journals, stale tables, nested files, masked arrays and option
combinations, hostile names into generated files, crafted output folders, FIFOs and endless files, and HTTP request
lines to the page's server; none may crash (a traceback, another exception, a multi-line error, a non-finite result, or a folder
promise broken). The full run (``python -m benchmarks.fuzz``) writes report/fuzz.md."""

from benchmarks.fuzz import fuzz


def test_no_fuzzed_input_crashes():
    results = fuzz(cases=80, seed=2026)
    assert {name: outcome.crashed for name, outcome in results.items()} == dict.fromkeys(results, 0), {
        name: outcome.crashes for name, outcome in results.items()
    }
    # stale tables, crafted journals and folders, hostile names: every build must accept them (and stay safe)
    accepted_only = ("stale tables", "journals", "names into generated files", "crafted folders")
    for name, outcome in results.items():
        assert outcome.tried > 0 and (outcome.refused > 0 or name in accepted_only), name
