"""Sphinx configuration of the supercoil documentation.

Build (the ``docs`` extra: ``pip install '.[docs]'``)::

    sphinx-build -W -b html docs /tmp/supercoil-html

Pages are Markdown (MyST) or reStructuredText. Three pages are generated here
at build time, into ``docs/_generated/`` (not in git), so that they follow the
code without edits:

* the API reference: one page per name of ``supercoil.__all__``;
* the examples gallery: every ``examples/*.py`` with its docstring, the figure
  it writes (if ``docs/figures/`` has it) and its source;
* the theory toctree is a ``:glob:`` over ``docs/theory/*.md``, so new theory
  pages appear without edits.
"""

from __future__ import annotations

import ast
import re
import inspect
import sys
from pathlib import Path

DOCS = Path(__file__).resolve().parent
ROOT = DOCS.parent
sys.path.insert(0, str(ROOT))

import supercoil  # noqa: E402

project = "supercoil"
author = "the supercoil developers"
copyright = "2026, the supercoil developers"  # noqa: A001
version = release = supercoil.__version__

extensions = [
    "myst_parser",
    "numpydoc",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinx.ext.viewcode",
]
source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
# The generated fragments are included by api.rst and theory/index.md, not pages of their own.
exclude_patterns = ["_build", "**/.ipynb_checkpoints", "_generated/api_names.rst",
                    "_generated/theory_toctree.md"]
root_doc = "index"

# MyST: $...$ / $$...$$ math, heading anchors (docs/theory/li-zhao.md#slope links
# from the code and README resolve to the heading "Slope").
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_dmath_double_inline = True

# numpydoc renders the docstrings; members are listed by autodoc, not numpydoc.
numpydoc_show_class_members = False
numpydoc_xref_param_type = False
numpydoc_validation_checks = set()
autodoc_default_options = {"members": True, "member-order": "bysource"}
autodoc_typehints = "none"
# Broken internal references fail the -W build.
nitpicky = False

html_theme = "alabaster"
html_static_path = []
html_title = f"supercoil {release}"
html_theme_options = {"description": "double helices of twisted filaments", "fixed_sidebar": True}

GENERATED = DOCS / "_generated"


def _kind(obj):
    if inspect.ismodule(obj):
        return "module"
    if inspect.isclass(obj):
        return "exception" if issubclass(obj, BaseException) else "class"
    if callable(obj):
        return "function"
    return "data"


def _summary(obj):
    doc = inspect.getdoc(obj) if not isinstance(obj, str | int | float) else None
    line = (doc or "").strip().splitlines()[0] if doc else ""
    return line.replace("|", "/").replace("`", "")


def write_api_pages():
    """One page per public name of ``supercoil.__all__`` plus the summary tables."""
    out = GENERATED / "api"
    out.mkdir(parents=True, exist_ok=True)
    for old in out.glob("*.rst"):
        old.unlink()
    groups = {"function": [], "class": [], "exception": [], "module": [], "data": []}
    for name in sorted(supercoil.__all__, key=str.lower):
        obj = getattr(supercoil, name)
        kind = _kind(obj)
        groups[kind].append(name)
        title = f"supercoil.{name}"
        if kind == "module":
            body = f".. automodule:: {obj.__name__}\n   :members:\n"
        elif kind == "function":
            body = f".. autofunction:: supercoil.{name}\n"
        elif kind in ("class", "exception"):
            body = f".. autoclass:: supercoil.{name}\n   :members:\n   :show-inheritance:\n"
        else:
            body = (f".. py:data:: supercoil.{name}\n\n   ``{type(obj).__module__}."
                    f"{type(obj).__qualname__}``{_data_note(name, obj)}\n")
        (out / f"{name}.rst").write_text(f"{title}\n{'=' * len(title)}\n\n{body}")
    lines = []
    heads = {"function": "Functions", "class": "Classes", "exception": "Errors and warnings",
             "module": "Modules", "data": "Data"}
    for kind, names in groups.items():
        if not names:
            continue
        lines += [heads[kind], "-" * len(heads[kind]), "", ".. list-table::", "   :widths: 30 70",
                  ""]
        for name in names:
            obj = getattr(supercoil, name)
            summary = _summary(obj) if kind != "data" else _data_note(name, obj).strip(" :")
            lines += [f"   * - :doc:`supercoil.{name} <_generated/api/{name}>`", f"     - {summary}"]
        lines.append("")
    lines += [".. toctree::", "   :hidden:", "   :glob:", "", "   _generated/api/*", ""]
    (GENERATED / "api_names.rst").write_text("\n".join(lines))


def _data_note(name, obj):
    if name == "ureg":
        return ": the package's one pint unit registry (build every input with it)."
    if name == "__version__":
        return f": the package version, ``{obj}``."
    return ""


def write_gallery():
    """The examples gallery: docstring, figure and source of every ``examples/*.py``."""
    GENERATED.mkdir(parents=True, exist_ok=True)
    lines = ["# Examples gallery", "",
             "Every script in `examples/` writes its figures and tables with "
             "`python examples/NAME.py --out DIR` (add `--quick` for a smaller run), and every "
             "script runs in the test suite (`tests/test_examples.py`). The figures shown are "
             "the ones in `docs/figures/`, written by these scripts.", ""]
    for script in sorted((ROOT / "examples").glob("*.py")):
        if script.name.startswith("_"):
            continue
        tree = ast.parse(script.read_text())
        doc = ast.get_docstring(tree) or ""
        first, _, rest = doc.partition("\n")
        lines += [f"## {script.stem}", "", first.strip(), ""]
        if rest.strip():
            lines += ["```text", rest.strip(), "```", ""]
        for png in sorted((DOCS / "figures").glob("*.png")):
            if f'"{png.name}' in script.read_text() or f"'{png.name}" in script.read_text():
                lines += [f"![{png.stem}](../figures/{png.name})", ""]
        rel = Path("..") / ".." / "examples" / script.name
        lines += [f"```{{literalinclude}} {rel.as_posix()}", ":language: python", "```", ""]
    (GENERATED / "gallery.md").write_text("\n".join(lines))


write_api_pages()
write_gallery()


#: the theory pages in reading order; any other page in docs/theory/ follows them
THEORY_ORDER = ["conventions", "geometry", "contact", "smooth", "rough", "design", "spinning",
                "plectoneme", "li-zhao", "models", "fitting", "limits", "corrections"]


def write_theory_toctree():
    """Toctree of docs/theory/: the pages of THEORY_ORDER, then every other page present."""
    present = sorted(p.stem for p in (DOCS / "theory").glob("*.md") if p.stem != "index")
    order = [p for p in THEORY_ORDER if p in present]
    order += [p for p in present if p not in order]
    GENERATED.mkdir(parents=True, exist_ok=True)
    (GENERATED / "theory_toctree.md").write_text(
        "```{toctree}\n:maxdepth: 2\n\n" + "\n".join(order) + "\n```\n")


write_theory_toctree()


def write_benchmarks():
    """The benchmark headlines: the README's "Speed and accuracy" section, figures re-pointed."""
    import re

    text = (ROOT / "README.md").read_text()
    match = re.search(r"^## (Speed and accuracy|Benchmarks?)[^\n]*\n(.*?)(?=^## |\Z)", text,
                      re.M | re.S)
    body = match.group(2) if match else (
        "The README has no benchmark section; run `supercoil bench --out DIR`.\n")
    body = body.replace("](docs/figures/", "](../figures/")
    intro = ("`supercoil bench --out DIR` measures every solver and writes the work-precision "
             "charts, the stability map and the headline numbers (this page is the README's "
             "benchmark section, copied when the documentation is built).\n\n")
    (GENERATED / "benchmarks.md").write_text("# Benchmarks\n\n" + intro + body)


write_benchmarks()


def _escape_pipes(line):
    """Escape ``|`` outside inline literals (``|N|`` in a docstring is not a substitution)."""
    parts = line.split("``")
    for i in range(0, len(parts), 2):
        parts[i] = re.sub(r"(?<!\\)\|", r"\\|", parts[i])
    return "``".join(parts)


def _process_docstring(app, what, name, obj, options, lines):
    lines[:] = [_escape_pipes(line) for line in lines]


def setup(app):
    app.connect("autodoc-process-docstring", _process_docstring, priority=400)
