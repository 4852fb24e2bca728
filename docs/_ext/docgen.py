"""Pages of the documentation generated at build time (called by docs/conf.py).

Everything here writes into one output folder (``docs/_generated/`` for the build,
a temporary folder in ``tests/test_docs.py``):

* ``api/<name>.rst`` for every name of ``supercoil.__all__`` and ``api_names.rst``,
  the summary tables and the hidden toctree included by ``docs/api.rst``;
* ``traces/<name>.rst`` and ``traces_names.rst``: the same for ``supercoil.traces``
  (:data:`SUBPACKAGES`), the recordings' readers, outside ``supercoil.__all__``;
* ``gallery.md``: every ``examples/*.py`` with its docstring, figure and source;
* ``theory_toctree.md``: the theory pages in reading order, then any other page
  present in ``docs/theory/`` (pages added by later work appear without edits);
* ``benchmarks.md``: the README's benchmark section with the figure links re-pointed.

:func:`escape_pipes` is the docstring hook of conf.py.
"""

from __future__ import annotations

import ast
import inspect
import re
from pathlib import Path

import supercoil

DOCS = Path(__file__).resolve().parent.parent
ROOT = DOCS.parent




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


def write_api_pages(out_dir):
    """One page per public name of ``supercoil.__all__`` plus the summary tables."""
    out = out_dir / "api"
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
            lines += [f"   * - :doc:`supercoil.{name} <_generated/api/{name}>`",
                      f"     - {summary}"]
        lines.append("")
    lines += [".. toctree::", "   :hidden:", "   :glob:", "", "   _generated/api/*", ""]
    (out_dir / "api_names.rst").write_text("\n".join(lines))


#: subpackages outside ``supercoil.__all__`` with API pages of their own: module -> folder
SUBPACKAGES = {"supercoil.traces": "traces"}


def write_subpackage_pages(out_dir):
    """One page per name of each :data:`SUBPACKAGES` module's ``__all__`` and its summary
    table (``<folder>_names.rst``, included by ``docs/api.rst``)."""
    import importlib

    for module_name, folder in SUBPACKAGES.items():
        module = importlib.import_module(module_name)
        out = out_dir / folder
        out.mkdir(parents=True, exist_ok=True)
        for old in out.glob("*.rst"):
            old.unlink()
        lines = [".. list-table::", "   :widths: 30 70", ""]
        for name in sorted(module.__all__, key=str.lower):
            obj = getattr(module, name)
            kind = _kind(obj)
            title = f"{module_name}.{name}"
            if kind == "function":
                body = f".. autofunction:: {title}\n"
            elif kind in ("class", "exception"):
                body = f".. autoclass:: {title}\n   :members:\n   :show-inheritance:\n"
            else:
                body = f".. autodata:: {title}\n   :no-value:\n"
            (out / f"{name}.rst").write_text(f"{title}\n{'=' * len(title)}\n\n{body}")
            summary = _summary(obj) if kind != "data" else "the trace table's column units"
            lines += [f"   * - :doc:`{title} <_generated/{folder}/{name}>`",
                      f"     - {summary}"]
        lines += ["", ".. toctree::", "   :hidden:", "   :glob:", "",
                  f"   _generated/{folder}/*", ""]
        (out_dir / f"{folder}_names.rst").write_text("\n".join(lines))


def _data_note(name, obj):
    if name == "ureg":
        return ": the package's one pint unit registry (build every input with it)."
    if name == "__version__":
        return f": the package version, ``{obj}``."
    return ""


def write_gallery(out_dir):
    """The examples gallery: docstring, figure and source of every ``examples/*.py``."""
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
    (out_dir / "gallery.md").write_text("\n".join(lines))




#: the theory pages in reading order; any other page in docs/theory/ follows them
THEORY_ORDER = ["conventions", "geometry", "contact", "smooth", "rough", "design", "spinning",
                "plectoneme", "li-zhao", "models", "fitting", "limits", "corrections"]


def write_theory_toctree(out_dir):
    """Toctree of docs/theory/: the pages of THEORY_ORDER, then every other page present."""
    present = sorted(p.stem for p in (DOCS / "theory").glob("*.md") if p.stem != "index")
    order = [p for p in THEORY_ORDER if p in present]
    order += [p for p in present if p not in order]
    (out_dir / "theory_toctree.md").write_text(
        "```{toctree}\n:maxdepth: 2\n\n" + "\n".join(order) + "\n```\n")




def write_benchmarks(out_dir):
    """The benchmark headlines: the README's "Speed and accuracy" section, figures re-pointed."""
    text = (ROOT / "README.md").read_text()
    match = re.search(r"^## (Speed and accuracy|Benchmarks?)[^\n]*\n(.*?)(?=^## |\Z)", text,
                      re.M | re.S)
    body = match.group(2) if match else (
        "The README has no benchmark section; run `supercoil bench --out DIR`.\n")
    body = body.replace("](docs/figures/", "](../figures/")
    intro = ("`supercoil bench --out DIR` measures every solver and writes the work-precision "
             "charts, the stability map and the headline numbers (this page is the README's "
             "benchmark section, copied when the documentation is built).\n\n")
    (out_dir / "benchmarks.md").write_text("# Benchmarks\n\n" + intro + body)


def generate(out):
    """Write every generated page into the folder ``out`` (created)."""
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    for write in (write_api_pages, write_subpackage_pages, write_gallery, write_theory_toctree,
                  write_benchmarks):
        write(out)


def escape_pipes(line):
    """Escape ``|`` outside inline literals (``|N|`` in a docstring is not a substitution)."""
    parts = line.split("``")
    for i in range(0, len(parts), 2):
        parts[i] = re.sub(r"(?<!\\)\|", r"\\|", parts[i])
    return "``".join(parts)
