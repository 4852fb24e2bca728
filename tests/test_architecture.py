"""Structural rules of the package (docs/theory/index.md and CONTRIBUTING.md).

* the float kernels in supercoil/core never import pint, pandas or matplotlib,
  nor the unit-aware layers;
* the rod and DNA domains do not import each other;
* no module imports another module's private names;
* no module is over 500 lines without a ``# long module: <why>`` line;
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


#: a module over 500 lines says why on a line of its own (``# long module: <why>``)
_LONG_MODULE = re.compile(r"^# long module: \S", re.MULTILINE)


def _over_500_lines(paths):
    """{path: lines} of the modules over 500 lines without a ``# long module:`` reason."""
    out = {}
    for p in paths:
        text = p.read_text()
        if (n := len(text.splitlines())) > 500 and not _LONG_MODULE.search(text):
            out[str(p)] = n
    return out


def test_no_module_over_500_lines():
    """Modules stay under 500 lines unless a line ``# long module: <why>`` says why."""
    big = _over_500_lines(_package_files())
    assert not big, f"modules over 500 lines without a '# long module:' reason: {big}"


def test_the_500_line_rule_accepts_only_a_stated_reason(tmp_path):
    body = "x = 1\n" * 501
    bare, reasoned, empty = (tmp_path / f"{n}.py" for n in ("bare", "reasoned", "empty"))
    bare.write_text(body)
    reasoned.write_text("# long module: one table of published constants\n" + body)
    empty.write_text("# long module:\n" + body)  # no reason given
    short = tmp_path / "short.py"
    short.write_text("x = 1\n" * 500)
    assert set(_over_500_lines([bare, reasoned, empty, short])) == {str(bare), str(empty)}


SHIPPED = ("supercoil", "docs", "examples", "parameters", "tests")
#: tests that name the forbidden paths in order to check they are absent
_CHECKERS = {"test_architecture.py", "test_readme.py", "test_docs.py"}
OUTSIDE = re.compile(r"\.\./shared|shared/reference|/work/|MODEL\.md")


def test_no_shipped_file_refers_outside_the_repository():
    offenders = []
    files = [ROOT / "README.md", ROOT / "CONTRIBUTING.md", ROOT / "pyproject.toml"]
    for d in SHIPPED:
        files += [p for p in (ROOT / d).rglob("*") if p.is_file()
                  and p.suffix in {".py", ".md", ".rst", ".toml", ".txt", ".csv", ".cfg"}]
    for p in files:
        if p.name in _CHECKERS or {"_generated", "_build"} & set(p.parts):
            continue  # the tests that check for these strings; docs build outputs
        for i, line in enumerate(p.read_text(errors="replace").splitlines(), 1):
            if OUTSIDE.search(line):
                offenders.append(f"{p.relative_to(ROOT)}:{i}")
    assert not offenders, ("shipped files must cite docs/theory/ or papers, never a path "
                           f"outside the repository: {offenders[:20]} ({len(offenders)} lines)")


def _code_lines(node):
    """Lines of a function without its docstring."""
    n = node.end_lineno - node.lineno + 1
    body = node.body
    if body and isinstance(body[0], ast.Expr) and isinstance(getattr(body[0], "value", None),
                                                             ast.Constant) \
            and isinstance(body[0].value.value, str):
        n -= body[0].end_lineno - body[0].lineno + 1
    return n


def test_no_function_over_80_lines_without_a_reason():
    """Functions stay under 80 lines of code (docstrings excluded) unless a comment
    ``# long function: <why>`` says why."""
    offenders = []
    for path in _package_files():
        src = path.read_text()
        lines = src.splitlines()
        for node in ast.walk(ast.parse(src)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and \
                    _code_lines(node) > 80:
                text = "\n".join(lines[node.lineno - 1:node.end_lineno])
                if "# long function:" not in text:
                    offenders.append(f"{path.relative_to(ROOT)}:{node.name} "
                                     f"({_code_lines(node)} lines)")
    assert not offenders, f"functions over 80 lines of code: {offenders}"


def _complexity(node):
    """McCabe complexity as radon counts it (nested functions apart)."""
    c = 1
    stack = list(ast.iter_child_nodes(node))
    while stack:
        n = stack.pop()
        if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef | ast.Lambda | ast.ClassDef):
            continue
        if isinstance(n, ast.If | ast.IfExp | ast.For | ast.AsyncFor | ast.While |
                      ast.ExceptHandler | ast.Assert):
            c += 1
        elif isinstance(n, ast.comprehension):
            c += 1 + len(n.ifs)
        elif isinstance(n, ast.BoolOp):
            c += len(n.values) - 1
        elif isinstance(n, ast.match_case):
            c += 1
        stack.extend(ast.iter_child_nodes(n))
    return c


def test_no_function_more_complex_than_radon_grade_c():
    """Cyclomatic complexity <= 20 (radon grade C) for every function."""
    offenders = []
    for path in _package_files():
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and \
                    (cc := _complexity(node)) > 20:
                offenders.append(f"{path.relative_to(ROOT)}:{node.name} ({cc})")
    assert not offenders, f"functions worse than radon grade C: {offenders}"


def test_contributing_maps_every_module():
    """CONTRIBUTING.md has one line per module of the package (the map a reader uses)."""
    text = (ROOT / "CONTRIBUTING.md").read_text()
    missing = [str(p.relative_to(ROOT)) for p in _package_files()
               if f"`{p.relative_to(ROOT)}`" not in text]
    assert not missing, f"modules missing from CONTRIBUTING.md's map: {missing}"
