"""fresnel_lut.kernels: the command pins numpy's and OpenBLAS' kernels before numpy loads, as the libraries
themselves report them (threadpoolctl's view of OpenBLAS, numpy's own table of dispatched features)."""

import json
import os
import subprocess
import sys

import pytest

from fresnel_lut.kernels import _read_cpu_flags, pin_numeric_kernels

REPORT = """
import json, sys
from fresnel_lut.kernels import pin_numeric_kernels
pinned = pin_numeric_kernels()
import numpy
from numpy._core._multiarray_umath import __cpu_features__ as features
from threadpoolctl import threadpool_info
print(json.dumps({"pinned": pinned, "openblas": sorted({i["architecture"] for i in threadpool_info() if i["internal_api"] == "openblas"}),
                  "avx512": sorted(name for name, on in features.items() if on and name in ("X86_V4", "AVX512_SKX", "AVX512_ICL", "AVX512_SPR"))}))
"""


def report(env=None):
    result = subprocess.run([sys.executable, "-c", REPORT], capture_output=True, text=True, timeout=120, env=env)
    assert result.returncode == 0, result.stderr
    assert "cannot disable" not in result.stderr  # numpy's warning for names its build does not know is silenced
    return json.loads(result.stdout)


@pytest.mark.skipif(not {"avx2", "fma"} <= _read_cpu_flags(), reason="pins only on x86-64 CPUs with AVX2 and FMA")
def test_a_fresh_process_runs_openblas_haswell_kernels_and_no_avx512_loops():
    seen = report()
    assert seen["pinned"] is True
    assert seen["openblas"] == ["Haswell"]  # numpy's and scipy's OpenBLAS alike
    assert seen["avx512"] == []


def test_a_setting_the_user_made_is_kept():
    environment = {"OPENBLAS_CORETYPE": "Zen"}
    assert pin_numeric_kernels(environment, cpu_flags={"avx2", "fma"})
    assert environment["OPENBLAS_CORETYPE"] == "Zen"
    assert "X86_V4" in environment["NPY_DISABLE_CPU_FEATURES"].split()


def test_nothing_is_pinned_once_numpy_is_loaded(monkeypatch):
    import numpy  # noqa: F401  (this test process has it loaded already)

    monkeypatch.delenv("OPENBLAS_CORETYPE", raising=False)
    assert pin_numeric_kernels(cpu_flags={"avx2", "fma"}) is False
    assert "OPENBLAS_CORETYPE" not in os.environ
