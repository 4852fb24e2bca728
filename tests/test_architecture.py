"""Structural rules: the float kernels in supercoil/core never import pint."""

import ast
from pathlib import Path

CORE = Path(__file__).resolve().parent.parent / "supercoil" / "core"


def _imports(path):
    tree = ast.parse(path.read_text())
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (a.name for a in node.names)
        elif isinstance(node, ast.ImportFrom):
            yield node.module or ""
            if node.level:  # relative import: must stay inside core
                yield "." * node.level + (node.module or "")


def test_core_does_not_import_pint_or_the_unit_layer():
    offenders = []
    for path in CORE.rglob("*.py"):
        for name in _imports(path):
            if name.split(".")[0] in {"pint", "pandas", "matplotlib"}:
                offenders.append((path.name, name))
            if name.startswith("..") or (name.startswith("supercoil.") and not name.startswith(
                "supercoil.core"
            )):
                if name not in ("..exceptions", "supercoil.exceptions"):
                    offenders.append((path.name, name))
    assert not offenders, f"core must stay float-only: {offenders}"
