"""Engines' packages from the npm registry, fetched by name and pinned version (``npm pack`` into the ignored
``build/npm/``, once) for the benchmarks and tests that compare with them or run inside them.

Public objects: ``NPM_CACHE``, ``NpmError``, ``npm_tarball``, ``npm_unpacked``.
"""

from __future__ import annotations

import re
import shutil
import subprocess
import tarfile
from pathlib import Path

__all__ = ["NPM_CACHE", "NpmError", "npm_tarball", "npm_unpacked"]

NPM_CACHE = Path(__file__).resolve().parents[1] / "build" / "npm"


class NpmError(RuntimeError):
    """npm is missing, or the package could not be fetched."""


def npm_tarball(package: str, version: str) -> Path:
    """The tarball of ``package@version``, fetched once with ``npm pack`` into :data:`NPM_CACHE`."""
    tarball = NPM_CACHE / f"{re.sub(r'^@', '', package).replace('/', '-')}-{version}.tgz"
    if tarball.is_file():
        return tarball
    npm = shutil.which("npm")
    if npm is None:
        raise NpmError(f"npm is not installed: {package}@{version} is fetched with npm pack (make test installs npm)")
    NPM_CACHE.mkdir(parents=True, exist_ok=True)
    completed = subprocess.run(
        [npm, "pack", f"{package}@{version}", "--pack-destination", str(NPM_CACHE), "--silent"],
        capture_output=True,
        text=True,
        timeout=600,
    )
    if completed.returncode != 0 or not tarball.is_file():
        raise NpmError(f"npm pack {package}@{version} failed: {completed.stderr.strip()[-500:]}")
    return tarball


def npm_unpacked(package: str, version: str) -> Path:
    """The folder of ``package@version``'s files (its tarball's ``package/``), unpacked once beside the tarball."""
    tarball = npm_tarball(package, version)
    folder = tarball.with_suffix("")
    if not (folder / "package" / "package.json").is_file():
        partial = folder.with_name(folder.name + ".partial")
        shutil.rmtree(partial, ignore_errors=True)
        with tarfile.open(tarball) as archive:
            archive.extractall(partial, filter="data")
        shutil.rmtree(folder, ignore_errors=True)
        partial.rename(folder)
    return folder / "package"
