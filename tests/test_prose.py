"""Prose that runs or is checked (issue 22): every module's "Public objects" line names exactly its ``__all__``, and
every ``:mod:``/``:func:``/``:class:``/``:data:``/``:meth:`` reference to a project object resolves (docstrings had
named modules renamed long ago: ``basis.approximations``, ``basis.files``). The docstring examples themselves run
through ``--doctest-modules`` (pyproject.toml)."""

import ast
import importlib
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("basis", "preintegrate", "handoff", "fresnel_lut")
MODULES = sorted(path for package in PACKAGES for path in (ROOT / package).rglob("*.py"))
REFERENCE = re.compile(r":(?:mod|func|class|data|meth):`~?((?:basis|preintegrate|handoff|fresnel_lut)(?:\.\w+)*)`")


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _resolves(target: str) -> bool:
    parts = target.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            found = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for name in parts[cut:]:
            if not hasattr(found, name):
                return False
            found = getattr(found, name)
        return True
    return False


@pytest.mark.parametrize("path", MODULES, ids=lambda path: str(path.relative_to(ROOT)))
def test_public_objects_line_is_the_modules_all(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    exported = next(
        (
            set(ast.literal_eval(node.value))
            for node in tree.body
            if isinstance(node, ast.Assign) and any(getattr(target, "id", None) == "__all__" for target in node.targets)
        ),
        None,
    )
    line = re.search(r"Public objects:(.*?)(?:\n\n|$)", ast.get_docstring(tree) or "", re.S)
    if exported is None:
        assert line is None, "a Public objects line without __all__"
        return
    assert line is not None, f"__all__ {sorted(exported)} but no Public objects line"
    assert set(re.findall(r"``(\w+)``", line.group(1))) == exported


@pytest.mark.parametrize("path", MODULES, ids=lambda path: str(path.relative_to(ROOT)))
def test_references_to_project_objects_resolve(path):
    unresolved = sorted(
        {target for target in REFERENCE.findall(path.read_text(encoding="utf-8")) if not _resolves(target)}
    )
    assert not unresolved, f"{_module_name(path)} names objects that do not exist: {unresolved}"
