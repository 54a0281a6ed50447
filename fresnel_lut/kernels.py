"""The numeric kernels the ``fresnel-lut`` command runs on, pinned so that the files it writes are the same bytes on
every x86-64 machine with AVX2 and FMA (README, "Reproducible files").

numpy dispatches its float64 loops (exp, log, sin, cos, power) to AVX-512 code where the CPU has it, and OpenBLAS
picks its kernels per CPU (SkylakeX, Zen, Haswell); each rounds the last bits its own way. On an AVX-512 machine the
same ``fresnel-lut build`` gave other bytes for the LTC table and the shader includes, ``fresnel-lut basis`` and
``fresnel-lut materials`` other files (2026-12, an AMD EPYC with AVX-512 against the AVX2 machine that built them).
Before numpy loads, :func:`pin_numeric_kernels` turns numpy's AVX-512 dispatch off and asks OpenBLAS for its Haswell
kernels (AVX2 and FMA: x86-64-v3). A value the user set for either variable is kept; on other CPUs (no AVX2, ARM)
nothing is pinned and their last bits may differ, which the content hashes then show. The pinning acts only in a
process that has not imported numpy yet: the command's (``fresnel_lut.entry``), not a Python session that calls the
library. No numpy or other third-party import here.

Public objects: ``pin_numeric_kernels``, ``NUMPY_DISABLED``, ``OPENBLAS_CORE``.
"""

from __future__ import annotations

import os
import platform
import sys
import warnings
from pathlib import Path

__all__ = ["NUMPY_DISABLED", "OPENBLAS_CORE", "pin_numeric_kernels"]

#: numpy's names for its AVX-512 dispatch targets: ``X86_V4`` and the two above it from numpy 2.4, the ``AVX512*``
#: names before it. numpy warns about a name its build does not dispatch, and that warning is silenced.
NUMPY_DISABLED = "X86_V4 AVX512F AVX512CD AVX512_KNL AVX512_KNM AVX512_SKX AVX512_CLX AVX512_CNL AVX512_ICL AVX512_SPR"
#: OpenBLAS' kernel set for AVX2 and FMA CPUs (``OPENBLAS_CORETYPE``; its builds with DYNAMIC_ARCH, as numpy's and
#: scipy's wheels are, honour it).
OPENBLAS_CORE = "Haswell"
_CPU_FLAGS = Path("/proc/cpuinfo")


def pin_numeric_kernels(environ: dict[str, str] | None = None, cpu_flags: set[str] | None = None) -> bool:
    """Set ``NPY_DISABLE_CPU_FEATURES`` and ``OPENBLAS_CORETYPE`` in ``environ`` (default ``os.environ``) where the
    CPU (``cpu_flags``, default: read from ``/proc/cpuinfo``) has AVX2 and FMA and numpy is not loaded yet; whether
    it pinned them. Values already set are left as they are.

    >>> environment = {}
    >>> pin_numeric_kernels(environment, cpu_flags={"avx2", "fma", "avx512f"})
    True
    >>> environment["OPENBLAS_CORETYPE"], environment["NPY_DISABLE_CPU_FEATURES"].split()[0]
    ('Haswell', 'X86_V4')
    >>> pin_numeric_kernels({}, cpu_flags={"sse4_2"})  # OpenBLAS' Haswell kernels would not run there
    False
    """
    environ = os.environ if environ is None else environ
    if environ is os.environ and "numpy" in sys.modules:
        return False  # too late: numpy and its OpenBLAS read these when they load
    flags = _read_cpu_flags() if cpu_flags is None else cpu_flags
    if not {"avx2", "fma"} <= flags:
        return False
    environ.setdefault("NPY_DISABLE_CPU_FEATURES", NUMPY_DISABLED)
    environ.setdefault("OPENBLAS_CORETYPE", OPENBLAS_CORE)
    if environ is os.environ:
        warnings.filterwarnings("ignore", message="You cannot disable CPU feature")
    return True


def _read_cpu_flags() -> set[str]:
    """The CPU's feature flags on x86-64 Linux; empty elsewhere (nothing is pinned there)."""
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return set()
    try:
        text = _CPU_FLAGS.read_text(encoding="ascii", errors="replace")
    except OSError:
        return set()
    for line in text.splitlines():
        if line.startswith("flags"):
            return set(line.partition(":")[2].split())
    return set()
