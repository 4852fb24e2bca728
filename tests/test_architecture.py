"""Structural rules of the package (docs/theory/index.md and CONTRIBUTING.md).

* the float kernels in supercoil/core never import pint, pandas or matplotlib,
  nor the unit-aware layers;
* the rod and DNA domains do not import each other;
* no module imports another module's private names;
* no module is over 500 lines;
* no shipped file refers to a path outside the repository.
"""

import ast
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PKG = ROOT / "supercoil"
CORE = PKG / "core"


def _module_name(path):
    rel = path.relative_to(ROOT).with_suffix("")
    parts = list(rel.parts)
    if parts[-1] == "__init__":
        parts = parts[:-1]
    return ".".join(parts)


def _imports(path):
    """(absolute module, imported names) of every import in ``path``."""
    tree = ast.parse(path.read_text())
    mod = _module_name(path)
    pkg = mod.split(".") if path.name == "__init__.py" else mod.split(".")[:-1]
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name, ()
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg[: len(pkg) - node.level + 1]
                name = ".".join(base + ([node.module] if node.module else []))
            else:
                name = node.module or ""
            yield name, tuple(a.name for a in node.names)


def _package_files():
    return sorted(PKG.rglob("*.py"))


def test_core_does_not_import_pint_or_the_unit_layer():
    offenders = []
    for path in CORE.rglob("*.py"):
        for name, _ in _imports(path):
            top = name.split(".")[0]
            if top in {"pint", "pandas", "matplotlib"}:
                offenders.append((path.name, name))
            if top == "supercoil" and not (name.startswith("supercoil.core")
                                           or name == "supercoil.exceptions"):
                offenders.append((path.name, name))
    assert not offenders, f"core must stay float-only: {offenders}"


def test_rod_and_dna_do_not_import_each_other():
    offenders = []
    for domain, other in (("rod", "dna"), ("dna", "rod")):
        for path in (PKG / domain).rglob("*.py"):
            for name, _ in _imports(path):
                if name.startswith(f"supercoil.{other}") or name.startswith(
                        f"supercoil.core.{other}"):
                    offenders.append((str(path.relative_to(ROOT)), name))
    assert not offenders, f"rod and dna are separate domains: {offenders}"


def test_no_module_imports_private_names_of_another():
    offenders = []
    for path in _package_files():
        for name, names in _imports(path):
            if not name.startswith("supercoil"):
                continue
            for n in names:
                if n.startswith("_") and not n.startswith("__"):
                    offenders.append((str(path.relative_to(ROOT)), f"{name}.{n}"))
    assert not offenders, f"private names imported across modules: {offenders}"


def test_no_module_over_500_lines():
    big = {str(p.relative_to(ROOT)): n for p in _package_files()
           if (n := len(p.read_text().splitlines())) > 500}
    assert not big, f"modules over 500 lines: {big}"


SHIPPED = ("supercoil", "docs", "examples", "parameters", "tests")
OUTSIDE = re.compile(r"\.\./shared|shared/reference|/work/|MODEL\.md")


def test_no_shipped_file_refers_outside_the_repository():
    offenders = []
    files = [ROOT / "README.md", ROOT / "CONTRIBUTING.md", ROOT / "pyproject.toml"]
    for d in SHIPPED:
        files += [p for p in (ROOT / d).rglob("*") if p.is_file()
                  and p.suffix in {".py", ".md", ".rst", ".toml", ".txt", ".csv", ".cfg"}]
    for p in files:
        if p == Path(__file__).resolve():
            continue
        for i, line in enumerate(p.read_text(errors="replace").splitlines(), 1):
            if OUTSIDE.search(line):
                offenders.append(f"{p.relative_to(ROOT)}:{i}")
    assert not offenders, ("shipped files must cite docs/theory/ or papers, never a path "
                           f"outside the repository: {offenders[:20]} ({len(offenders)} lines)")
