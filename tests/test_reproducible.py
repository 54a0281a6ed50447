"""Every shipped artefact is reproducible: the command that made it gives the same bytes again, whatever the
number of BLAS threads the machine starts and whatever x86-64 CPU it runs on (README, "Reproducible files").

Compared byte for byte, each command run as users run it (a fresh process through the entry point, which pins numpy's
and OpenBLAS' kernels before numpy loads: in this test process numpy is loaded with whatever the CPU offers):
``luts/basis.json`` (``fresnel-lut basis``), ``luts/ggx_*.exr`` and the shader includes (``fresnel-lut build``),
``luts/materials.json`` (``fresnel-lut materials``); and one build under OPENBLAS_NUM_THREADS = 1 and 2 (the basis
build's Gram products and eigen-solves are where thread counts used to change the last bits: three content hashes
for one command). On an AVX-512 machine the unpinned commands gave other bytes for all three (2026-12).
"""

import os

import pytest

from basis.storage import shipped_path
from handoff.shipped import LTC_LUT
from handoff.tables import DEFAULT_BUILD_FILES
from tests.conftest import run_subprocess

ROOT = shipped_path("").parent


def command(argv, env=None):
    """The command in a fresh process; its result, checked to have succeeded."""
    result = run_subprocess(argv, cwd=ROOT, timeout=300, env=env)
    assert result.returncode == 0, result.stderr
    return result


def test_the_shipped_basis_rebuilds_to_the_same_bytes(tmp_path):
    command(["basis", "--out", tmp_path / "basis.json"])
    assert (tmp_path / "basis.json").read_bytes() == shipped_path("basis.json").read_bytes()


def test_the_shipped_luts_rebuild_to_the_same_bytes(tmp_path):
    """The tables, the area lights' LTC table (``make luts`` builds with ``--ltc``) and the shader includes generated
    from the same basis (issue 23: a test rebuilds the shipped includes byte-identical)."""
    command(["build", "--ltc", "--out", tmp_path])
    shipped = [*DEFAULT_BUILD_FILES, LTC_LUT]
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(shipped)
    for name in shipped:
        assert (tmp_path / name).read_bytes() == shipped_path(name).read_bytes(), name


def test_the_shipped_presets_refit_to_the_same_bytes(tmp_path):
    command(["materials", "--presets", tmp_path / "materials.json"])
    assert (tmp_path / "materials.json").read_bytes() == shipped_path("materials.json").read_bytes()


@pytest.mark.slow
def test_basis_bytes_do_not_depend_on_blas_threads(tmp_path):
    written = []
    for threads in ("1", "2"):
        path = tmp_path / f"basis-{threads}.json"
        environment = {**os.environ, "OPENBLAS_NUM_THREADS": threads, "OMP_NUM_THREADS": threads}
        command(["basis", "--count", "40000", "--out", path], env=environment)
        written.append(path.read_bytes())
    assert written[0] == written[1]
