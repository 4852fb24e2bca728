"""Structural rules of the package (docs/theory/index.md and CONTRIBUTING.md).

* the float kernels in supercoil/core never import pint, pandas or matplotlib,
  nor the unit-aware layers;
* the rod and DNA domains do not import each other;
* no module imports another module's private names, nor reads another module's private
  attributes (``obj._name`` where ``_name`` is not defined in the module);
* no module is over 500 lines without a ``# long module: <why>`` line;
* no shipped file refers to a path outside the repository;
* no comment or docstring of the package holds a machine timing or an issue number;
* no module switches on the type of a concrete DNA model or interaction outside that
  class's own module, nor probes a model or interaction for hidden hooks (``hasattr``,
  ``getattr`` with a default, the ``OPTIONS`` table): capabilities are declared on the
  bases (``supercoil/dna/models/base.py``, ``supercoil/dna/interactions/base.py``).
"""

import ast
import functools
import io
import itertools
import re
import textwrap
import tokenize
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


@functools.cache
def _parse(path):
    """The AST of a file, parsed once per session (the rules only read it)."""
    return ast.parse(path.read_text())


_WALKS = {}


def _walk(tree):
    """``list(ast.walk(tree))``, made once per tree: every rule walks the same package
    trees (the tree is kept with its nodes, so that its id stays its own)."""
    if id(tree) not in _WALKS:
        _WALKS[id(tree)] = (tree, list(ast.walk(tree)))
    return _WALKS[id(tree)][1]


def _imports(path):
    """(absolute module, imported names) of every import in ``path``."""
    tree = _parse(path)
    mod = _module_name(path)
    pkg = mod.split(".") if path.name == "__init__.py" else mod.split(".")[:-1]
    for node in _walk(tree):
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


#: private-looking names that are other libraries' documented or unavoidable API:
#: namedtuple's public methods; pint's quantity internals (the unit layer's fast paths,
#: supercoil/units.py, and the registry check of a quantity); argparse's parser tree
#: (no public way to walk the sub-parsers)
FOREIGN_PRIVATE_API = {"_replace", "_asdict", "_fields", "_make",
                       "_units", "_magnitude", "_REGISTRY", "_is_multiplicative",
                       "_actions", "_SubParsersAction"}


def _is_private(name):
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _defined_names(tree):
    """Every name a module binds: defs, classes, assignments (also to attributes),
    imports, arguments and keywords."""
    out = set()
    for node in _walk(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            out.add(node.name)
        elif isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store):
            out.add(node.id)
        elif isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Store | ast.Del):
            out.add(node.attr)
        elif isinstance(node, ast.alias):
            out.add((node.asname or node.name).split(".")[0])
        elif isinstance(node, ast.arg):
            out.add(node.arg)
        elif isinstance(node, ast.keyword) and node.arg:
            out.add(node.arg)
    return out


def private_attribute_reads(source, allowed=FOREIGN_PRIVATE_API):
    """``(line, name)`` of each read of another module's private attribute in ``source``:
    ``obj._name`` (or ``getattr``/``hasattr(obj, "_name")``) with ``obj`` not ``self``,
    ``cls`` or ``super()``, and ``_name`` bound nowhere in the module (``source`` may be
    its AST)."""
    tree = _tree(source)
    own = _defined_names(tree) | set(allowed)
    found = []
    for node in _walk(tree):
        name = None
        if isinstance(node, ast.Attribute) and isinstance(node.ctx, ast.Load):
            v = node.value
            if isinstance(v, ast.Name) and v.id in ("self", "cls"):
                continue
            if isinstance(v, ast.Call) and isinstance(v.func, ast.Name) and v.func.id == "super":
                continue
            name = node.attr
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
              and node.func.id in ("getattr", "hasattr", "setattr") and len(node.args) >= 2
              and isinstance(node.args[1], ast.Constant) and isinstance(node.args[1].value, str)):
            name = node.args[1].value
        if name and _is_private(name) and name not in own:
            found.append((node.lineno, name))
    return found


def test_no_module_reads_private_attributes_of_another():
    offenders = [f"{path.relative_to(ROOT)}:{line}: {name}" for path in _package_files()
                 for line, name in private_attribute_reads(_parse(path))]
    assert not offenders, f"private attributes of other modules read: {offenders}"


def test_the_private_attribute_rule_catches_a_bad_snippet():
    bad = ("def report(result):\n"
           "    start = result._core['start']\n"
           "    return getattr(result, '_spec', None), start\n")
    assert sorted(private_attribute_reads(bad)) == [(2, "_core"), (3, "_spec")]
    good = ("class A:\n"
            "    def __init__(self):\n"
            "        self._x = 1\n"
            "    def same(self, other):\n"
            "        return other._x + self._x + other.__class__.__name__.__len__()\n"
            "def f(t):\n"
            "    return t._replace(a=1)\n")
    assert private_attribute_reads(good) == []


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
        for node in _walk(_parse(path)):
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
        for node in _walk(_parse(path)):
            if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef) and \
                    (cc := _complexity(node)) > 20:
                offenders.append(f"{path.relative_to(ROOT)}:{node.name} ({cc})")
    assert not offenders, f"functions worse than radon grade C: {offenders}"


#: placeholder rows of CONTRIBUTING.md's map: one row stands for every module it matches
#: (a model is its own file and its kernel of the same name: adding one adds no row)
PLACEHOLDER_ROWS = {
    "supercoil/dna/models/<model>.py": lambda rel: (
        rel.parent == Path("supercoil/dna/models") and rel.stem not in ("__init__", "base")),
    "supercoil/dna/interactions/<interaction>.py": lambda rel: (
        rel.parent == Path("supercoil/dna/interactions")
        and rel.stem not in ("__init__", "base")),
    "supercoil/core/dna/<model>.py": lambda rel: (
        rel.parent == Path("supercoil/core/dna")
        and (ROOT / "supercoil/dna/models" / rel.name).is_file()),
}


def _unmapped(text, relpaths):
    """Modules (paths relative to the root) that have neither a row nor a placeholder row."""
    rows = [rule for row, rule in PLACEHOLDER_ROWS.items() if f"`{row}`" in text]
    return [str(rel) for rel in relpaths
            if f"`{rel}`" not in text and not any(rule(rel) for rule in rows)]


def test_contributing_maps_every_module():
    """CONTRIBUTING.md has one line per module of the package (the map a reader uses);
    a model and its kernel are covered by the placeholder rows."""
    text = (ROOT / "CONTRIBUTING.md").read_text()
    missing = _unmapped(text, [p.relative_to(ROOT) for p in _package_files()])
    assert not missing, f"modules missing from CONTRIBUTING.md's map: {missing}"


# --- dated text: machine timings and issue numbers in comments and docstrings -----------
#: a duration in ns/us/ms, or a decimal or approximate number of seconds
_DURATION = re.compile(r"\d(?:[\d.,]*\d)?(?:e-?\d+)?\s?(?:ns|us|µs|ms)\b"
                       r"|(?:~\s?|about )\d+(?:\.\d+)?\s?s\b(?![\^(])"
                       r"|\b\d+\.\d+\s?s\b(?![\^(])")
_SMALL_DURATION = re.compile(r"\d(?:[\d.,]*\d)?(?:e-?\d+)?\s?(?:ns|us|µs|ms)\b")
#: words that make a duration a property of the data or a chosen limit, not a measurement
#: of the machine (a sampling interval, a settling time, a benchmark's target or budget)
_PHYSICAL = re.compile(r"\b(?:every|late|poll\w*|sampl\w*|interval|frames?|exposure|"
                       r"settl\w*|delay|targets?|until|budget|timeout|at least)\b", re.I)
_COST = re.compile(r"\b(?:at import|instead of|of its|costs?|costing|takes?|took|taking|spends?|"
                   r"spent|CPU|wall|measured|faster|slower|against|per (?:call|point|force|"
                   r"fit|molecule|curve|hat curve|fault|worker|step|solve))\b|->|(?:~\s?|about )\d",
                   re.I)
_MACHINE = re.compile(r"\b(?:this|the benchmark|the 2-core|on the) (?:VM|machine)\b|\bAMD EPYC\b",
                      re.I)
_ISSUE = re.compile(r"\bissues? #?\d+|\bround \d+\b|(?:^|[\s(])#\d+\b", re.I)


def _comments_and_docstrings(src):
    """(line, text) of every comment and docstring line of a module's source."""
    out = [(tok.start[0], tok.string) for tok in tokenize.generate_tokens(io.StringIO(src).readline)
           if tok.type == tokenize.COMMENT]
    for node in ast.walk(ast.parse(src)):
        if not isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        body = node.body
        # the docstring, and attribute docstrings (a string right after an assignment)
        strings = [body[0]] if body else []
        strings += [b for a, b in itertools.pairwise(body)
                    if isinstance(a, ast.Assign | ast.AnnAssign)]
        for s in strings:
            if isinstance(s, ast.Expr) and isinstance(s.value, ast.Constant) \
                    and isinstance(s.value.value, str):
                out += [(s.lineno + i, line) for i, line in enumerate(s.value.value.splitlines())]
    return out


def _dated_text(src):
    """(line, kind, text) of each comment or docstring line with an issue number or a
    machine timing (timings belong in the bench output, reasons in plain words)."""
    bad = []
    if not (_ISSUE.search(src) or _MACHINE.search(src) or _DURATION.search(src)):
        return bad  # nothing to look at (most modules): no tokenizing
    for n, text in _comments_and_docstrings(src):
        if _ISSUE.search(text):
            bad.append((n, "issue number", text.strip()))
        elif _MACHINE.search(text) or (not _PHYSICAL.search(text) and (
                _SMALL_DURATION.search(text) or (_DURATION.search(text) and _COST.search(text)))):
            bad.append((n, "machine timing", text.strip()))
    return sorted(bad)


def test_no_issue_numbers_or_machine_timings_in_comments_and_docstrings():
    offenders = [f"{p.relative_to(ROOT)}:{n}: {kind}: {text}"
                 for p in _package_files() for n, kind, text in _dated_text(p.read_text())]
    assert not offenders, "dated text in the package:\n" + "\n".join(offenders)


def test_the_dated_text_rule_catches_timings_and_issue_numbers():
    bad = textwrap.dedent('''\
    """Fast path (issue 23): the kernel takes 1.2 ms.
    112 ms per hat curve on this VM.
    """
    x = 1  # see #20 and round 3
    y = 2  # costs ~2 s at 1e6 points
    ''')
    kinds = [kind for _, kind, _ in _dated_text(bad)]
    assert kinds == ["issue number", "machine timing", "issue number", "machine timing"]
    good = textwrap.dedent('''\
    """Newton needs 7-8 evaluations against 127-146: about 15 times faster.

    The motor is polled every 50 ms; settling time 1 s; slack S = 2 s; (docs/x.md#2-tail).
    """
    z = 1  # target: under 2 ms
    t = 2  # the mean of repeats until 20 ms of CPU
    ''')
    assert _dated_text(good) == []


def test_the_map_rule_fails_on_an_unmapped_module():
    rel = [Path("supercoil/dna/models/new_model.py"), Path("supercoil/core/dna/new_model.py"),
           Path("supercoil/core/dna/phases.py"), Path("supercoil/dna/models/base.py")]
    text = "`supercoil/dna/models/<model>.py` `supercoil/core/dna/<model>.py`"
    # a kernel without a model file of its name, and the base, need their own rows
    assert _unmapped(text, rel) == ["supercoil/core/dna/new_model.py",
                                    "supercoil/core/dna/phases.py",
                                    "supercoil/dna/models/base.py"]
    assert _unmapped("", rel[:1]) == ["supercoil/dna/models/new_model.py"]


# ---- the model contract: no type switches, no hidden hooks ------------------------------

#: the bases of the plug-in contracts (their capabilities are the only thing callers read)
CONTRACT_BASES = {"DNAModel", "Interaction"}
#: names of variables that hold a model or an interaction (or the calls that return one)
_MODELISH = re.compile(r"^(m|model|models|inter|interaction|interactions|rec|recorder)$|"
                       r"(_model|_interaction)$")
_MODEL_GETTERS = {"get_model", "get_interaction", "resolve_model"}
#: members too generic to mark a probe by their name alone (plain data has them too)
_GENERIC = {"name", "summary", "parameters", "values"}


@functools.cache
def _parsed():
    """``[(path, module name, AST)]`` of the package, parsed once for the contract rules."""
    return [(p, _module_name(p), _parse(p)) for p in _package_files()]


def _tree(source):
    return source if isinstance(source, ast.AST) else ast.parse(source)


def _classes():
    """``{class name: (module, base names, member names)}`` of the package's classes."""
    out = {}
    for _, module, tree in _parsed():
        for node in tree.body:
            if isinstance(node, ast.ClassDef):
                bases = [b.id if isinstance(b, ast.Name) else getattr(b, "attr", "")
                         for b in node.bases]
                members = {n.name for n in node.body
                           if isinstance(n, ast.FunctionDef | ast.AsyncFunctionDef)}
                for n in node.body:
                    targets = n.targets if isinstance(n, ast.Assign) else \
                        [n.target] if isinstance(n, ast.AnnAssign) else []
                    members |= {t.id for t in targets if isinstance(t, ast.Name)}
                out[node.name] = (module, bases, members)
    return out


def contract_classes(classes=None):
    """``({concrete model/interaction class: its module}, their member names)``."""
    classes = _classes() if classes is None else classes
    family = set(CONTRACT_BASES)
    grew = True
    while grew:
        new = {c for c, (_, bases, _) in classes.items() if set(bases) & family} - family
        family |= new
        grew = bool(new)
    concrete = {c: classes[c][0] for c in family - CONTRACT_BASES if c in classes}
    members = set().union(*(classes[c][2] for c in family if c in classes))
    members = {m for m in members if not m.startswith("__")} - _GENERIC
    return concrete, members


def _last_name(node):
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    return None


def type_switches(source, module, concrete):
    """``type(x) is C`` / ``isinstance(x, C)`` / ``issubclass(x, C)`` on a concrete model
    or interaction class C outside C's own module: ``[(line, text)]``."""
    out = []
    for node in _walk(_tree(source)):
        named = []
        if isinstance(node, ast.Compare):
            sides = [node.left, *node.comparators]
            if any(isinstance(s, ast.Call) and _last_name(s.func) == "type" for s in sides):
                for s in sides:
                    named += s.elts if isinstance(s, ast.Tuple | ast.List | ast.Set) else [s]
        elif isinstance(node, ast.Call) and _last_name(node.func) in ("isinstance",
                                                                      "issubclass"):
            if len(node.args) == 2:
                cls = node.args[1]
                named = list(cls.elts) if isinstance(cls, ast.Tuple) else [cls]
        for n in named:
            c = _last_name(n)
            if c in concrete and concrete[c] != module:
                out.append((node.lineno, ast.unparse(node)))
    return out


def _modelish(node):
    """Whether an expression names a model or an interaction (by variable or getter)."""
    if isinstance(node, ast.Call):
        return _last_name(node.func) in _MODEL_GETTERS
    name = _last_name(node)
    return bool(name and _MODELISH.search(name))


def hidden_hooks(source, module, members):
    """Capability probes: ``hasattr(x, a)`` or ``getattr(x, a, default)`` on a model or
    interaction (or for one of their members), and reads of the ``OPTIONS`` table outside
    the parameters module: ``[(line, text)]``."""
    out = []
    for node in _walk(_tree(source)):
        if isinstance(node, ast.Attribute) and node.attr == "OPTIONS" and \
                module != "supercoil.dna.model_parameters":
            out.append((node.lineno, ast.unparse(node)))
        if not isinstance(node, ast.Call):
            continue
        fn = _last_name(node.func)
        if not ((fn == "hasattr" and len(node.args) == 2)
                or (fn == "getattr" and len(node.args) == 3)):
            continue
        obj, attr = node.args[0], node.args[1]
        attr = attr.value if isinstance(attr, ast.Constant) else None
        if _modelish(obj) or attr == "OPTIONS" or attr in members:
            out.append((node.lineno, ast.unparse(node)))
    return out


def test_no_type_switch_on_a_concrete_model_or_interaction():
    """Callers read declared capabilities or call methods of the base, never test a class."""
    concrete, _ = contract_classes()
    assert {"LiZhao", "FreeEnergy", "HardCore", "Screened"} <= set(concrete)
    offenders = [f"{p.relative_to(ROOT)}:{line}: {text}" for p, module, tree in _parsed()
                 for line, text in type_switches(tree, module, concrete)]
    assert not offenders, f"type switches on concrete models/interactions: {offenders}"


def test_no_hidden_capability_hooks():
    _, members = contract_classes()
    offenders = [f"{p.relative_to(ROOT)}:{line}: {text}" for p, module, tree in _parsed()
                 for line, text in hidden_hooks(tree, module, members)]
    assert not offenders, f"hidden capability hooks on models/interactions: {offenders}"


def test_the_contract_rules_fail_on_bad_snippets():
    concrete = {"LiZhao": "supercoil.dna.models.li_zhao",
                "HardCore": "supercoil.dna.interactions.hard_core"}
    where = "supercoil.dna.fitting.simulate"
    for bad in ("if type(m) is LiZhao:\n    pass", "ok = type(m) == LiZhao",
                "ok = type(m) in (LiZhao, int)", "ok = isinstance(inter, HardCore)",
                "ok = isinstance(x, (int, models.LiZhao))", "ok = issubclass(cls, LiZhao)"):
        assert type_switches(bad, where, concrete), bad
    own = "ok = type(other) is LiZhao"  # in the class's own module (equality): allowed
    assert not type_switches(own, "supercoil.dna.models.li_zhao", concrete)
    assert not type_switches("ok = isinstance(x, DNAModel) and type(x) is int", where,
                             concrete)
    for bad in ("ok = hasattr(m, 'slope_validity')", "o = getattr(model, 'OPTIONS', {})",
                "o = m.OPTIONS['end_loop']", "o = getattr(get_model(n), 'OPTIONS', {})",
                "o = getattr(interaction, 'interaction', interaction)",
                "o = getattr(inter, '_inter', inter)", "ok = hasattr(x, 'has_free_energy')"):
        assert hidden_hooks(bad, where, {"slope_validity", "has_free_energy"}), bad
    for good in ("ok = hasattr(value, '_units')", "o = getattr(m, 'name')",
                 "o = getattr(points, 'summary', None)", "o = m.options()"):
        assert not hidden_hooks(good, where, {"slope_validity"}), good
    assert not hidden_hooks("OPTIONS = {}\no = self.OPTIONS", "supercoil.dna.model_parameters",
                            set())
