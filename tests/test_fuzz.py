"""A short run of the fuzz harness (benchmarks/fuzz.py): scene, preset and basis files, CLI options and API
calls mutated from valid inputs; none may crash (a traceback, another exception, a multi-line error or a
non-finite result). The full run (5,500 cases) writes report/fuzz.md."""

from benchmarks.fuzz import fuzz


def test_no_fuzzed_input_crashes():
    results = fuzz(cases=80, seed=2026)
    assert {name: outcome.crashed for name, outcome in results.items()} == dict.fromkeys(results, 0), {
        name: outcome.crashes for name, outcome in results.items()
    }
    for outcome in results.values():
        assert outcome.tried > 0 and outcome.refused > 0
