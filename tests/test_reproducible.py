"""Every shipped artefact is reproducible: the command that made it gives the same bytes again, whatever the
number of BLAS threads the machine starts (README, "Reproducible files").

Compared byte for byte: ``luts/basis.json`` (``fresnel-lut basis``), ``luts/ggx_*.exr`` (``fresnel-lut
build``), ``luts/materials.json`` (``fresnel-lut materials``); and one build under OPENBLAS_NUM_THREADS = 1
and 2 in fresh processes (the basis build's Gram products and eigen-solves are where thread counts used to
change the last bits: three content hashes for one command).
"""

import os
import subprocess
import sys

import pytest

from basis.storage import shipped_path
from preintegrate.lut import LTC_LUT
from preintegrate.tables import DEFAULT_BUILD_FILES
from tests.conftest import run

ROOT = shipped_path("").parent


def test_the_shipped_basis_rebuilds_to_the_same_bytes(tmp_path):
    assert run(["basis", "--out", tmp_path / "basis.json"]) == 0
    assert (tmp_path / "basis.json").read_bytes() == shipped_path("basis.json").read_bytes()


def test_the_shipped_luts_rebuild_to_the_same_bytes(tmp_path, capsys):
    """The tables, the area lights' LTC table (``make luts`` builds with ``--ltc``) and the shader includes generated
    from the same basis (issue 23: a test rebuilds the shipped includes byte-identical)."""
    assert run(["build", "--ltc", "--out", tmp_path]) == 0
    shipped = [*DEFAULT_BUILD_FILES, LTC_LUT]
    assert sorted(path.name for path in tmp_path.iterdir()) == sorted(shipped)
    for name in shipped:
        assert (tmp_path / name).read_bytes() == shipped_path(name).read_bytes(), name


def test_the_shipped_presets_refit_to_the_same_bytes(tmp_path, capsys):
    assert run(["materials", "--presets", tmp_path / "materials.json"]) == 0
    assert (tmp_path / "materials.json").read_bytes() == shipped_path("materials.json").read_bytes()


@pytest.mark.slow
def test_basis_bytes_do_not_depend_on_blas_threads(tmp_path):
    written = []
    for threads in ("1", "2"):
        path = tmp_path / f"basis-{threads}.json"
        environment = {**os.environ, "OPENBLAS_NUM_THREADS": threads, "OMP_NUM_THREADS": threads}
        subprocess.run(
            [sys.executable, "-m", "fresnel_lut.cli", "basis", "--count", "40000", "--out", str(path)],
            cwd=ROOT,
            env=environment,
            capture_output=True,
            check=True,
            timeout=300,
        )
        written.append(path.read_bytes())
    assert written[0] == written[1]
