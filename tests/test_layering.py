"""The import structure the design fixes, read from the code (ast) and from a fresh interpreter:

* ``basis`` never imports ``preintegrate`` or ``handoff`` (Fresnel curves know nothing of GGX or of files for
  engines);
* the integrals (``preintegrate``) never import the hand-off (``handoff``: tables in files, formats, shader text):
  they read and write no files;
* none of ``basis``, ``preintegrate`` and ``handoff`` imports the application layer ``fresnel_lut`` (the command,
  scenes, the renderer, the report);
* no product module imports the report (``fresnel_lut.report``); only the CLI may, inside a command;
* no private name (``_name``) is imported from another module of the project;
* ``import basis`` and ``from basis import coefficients_from_nk`` load neither colour-science nor matplotlib.
"""

import ast
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = ("basis", "preintegrate", "handoff", "fresnel_lut")
MODULES = sorted(path for package in PACKAGES for path in (ROOT / package).rglob("*.py"))


def _module_name(path: Path) -> str:
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> list[tuple[int, str, list[str]]]:
    """(line, absolute module, imported names) of every import of a project module in ``path``."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            found.append((node.lineno, target, [alias.name for alias in node.names]))
        elif isinstance(node, ast.Import):
            found += [(node.lineno, alias.name, []) for alias in node.names]
    return [(line, target, names) for line, target, names in found if target.split(".")[0] in PACKAGES]


def _is_report(module: str) -> bool:
    return module == "fresnel_lut.report" or module.startswith("fresnel_lut.report.")


def test_the_tree_is_read():
    assert len(MODULES) > 30 and any(_is_report(_module_name(path)) for path in MODULES)


@pytest.mark.parametrize("path", MODULES, ids=lambda path: str(path.relative_to(ROOT)))
def test_layering(path):
    me = _module_name(path)
    problems = []
    for line, target, names in _imports(path):
        targets = [target] + [f"{target}.{name}" for name in names]
        if me.startswith("basis") and target.startswith(("preintegrate", "handoff")):
            problems.append(f"line {line}: basis imports {target}")
        if me.startswith("preintegrate") and target.startswith("handoff"):
            problems.append(f"line {line}: the integrals import the hand-off ({target})")
        if not me.startswith("fresnel_lut") and target.startswith("fresnel_lut"):
            problems.append(f"line {line}: the core imports the application layer ({target})")
        if not _is_report(me) and me != "fresnel_lut.cli" and any(_is_report(t) for t in targets):
            problems.append(f"line {line}: a product module imports the report ({target})")
        private = [name for name in names if name.startswith("_") and not name.startswith("__")]
        if private and target != me:
            problems.append(f"line {line}: private names {private} imported from {target}")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("statement", ["import basis", "from basis import coefficients_from_nk, material_coefficients"])
def test_import_basis_is_light(statement):
    code = f"import sys; {statement}; print(' '.join(m for m in ('colour', 'matplotlib') if m in sys.modules))"
    completed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, check=True)
    assert completed.stdout.strip() == "", f"{statement!r} loads {completed.stdout.strip()}"
