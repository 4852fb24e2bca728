"""``supercoil docs``: build the documentation site; write a shipped sample data set.

    supercoil docs build [--out DIR] [--source DIR]   # sphinx-build -W -b html (docs extra)
    supercoil docs dataset [NAME] [--out DIR]         # NAME.csv from supercoil.datasets
    supercoil docs figures [--quick] [--skip-bench]   # rerun the scripts behind the docs'
                                                      # numbers and figures (docs_figures)

``build`` needs the documentation extra (``pip install '.[docs]'``) and a source
checkout (``docs/`` of the working folder, else of the checkout the package is
in, or ``--source``); it builds warning-free or fails. ``dataset`` without a name
lists the data sets.
"""

from __future__ import annotations

import importlib.util
import shutil
import sys
import time
from pathlib import Path


def register(sub):
    p = sub.add_parser("docs", help="build the documentation site; write a sample data set",
                       description=__doc__.splitlines()[0])
    actions = p.add_subparsers(dest="action", metavar="ACTION")
    b = actions.add_parser("build", help="build the HTML site with sphinx-build -W")
    b.add_argument("--out", default="docs_html", help="output folder (default: docs_html)")
    b.add_argument("--source", default=None,
                   help="the docs/ folder (default: docs/ of the working folder, else of the "
                   "checkout this package is in)")
    d = actions.add_parser("dataset", help="write a shipped sample data set as CSV")
    d.add_argument("name", nargs="?", help="data set name; omit to list them")
    d.add_argument("--out", default=".", help="output folder (default: .)")
    from supercoil.commands import docs_figures

    docs_figures.add_parser(actions)
    p.set_defaults(func=run, _parser=p)


def run(args) -> int:
    if args.action == "build":
        return _build(args)
    if args.action == "dataset":
        return _dataset(args)
    if args.action == "figures":
        from supercoil.commands import docs_figures

        return docs_figures.run(args)
    args._parser.print_help(sys.stderr)  # a missing action is a usage error, as in supercoil
    print("supercoil docs: error: an ACTION is required", file=sys.stderr)
    return 2


def _dataset(args) -> int:
    from supercoil.datasets import available_datasets, dataset_path

    if not args.name:
        print("\n".join(available_datasets()))
        return 0
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    target = out / f"{args.name}.csv"
    shutil.copyfile(dataset_path(args.name), target)  # DataError names an unknown set
    print(f"wrote {target}")
    return 0


def _build(args) -> int:
    from supercoil.commands._common import source_checkout

    # default: docs/ of the working folder (the repository, after ``pip install .``), else
    # docs/ of the checkout the package is in (an editable install), so that a module of the
    # same name in the working folder does not shadow the installed package
    root = source_checkout(None, needs=("docs/conf.py",)) if not args.source else None
    source = Path(args.source) if args.source else (root or Path.cwd()) / "docs"
    if not (source / "conf.py").is_file():
        print(f"supercoil docs build: error: no Sphinx sources at {source} (docs/conf.py): "
              "the documentation builds from a source checkout; run the command in the "
              "repository, or pass --source", file=sys.stderr)
        return 2
    missing = [name for name in ("sphinx", "numpydoc", "myst_parser")
               if importlib.util.find_spec(name) is None]
    if missing:
        print(f"supercoil docs: error: {', '.join(missing)} not installed: the documentation "
              "extra is needed, pip install 'supercoil[docs]'", file=sys.stderr)
        return 2
    from sphinx.cmd.build import build_main

    t0 = time.perf_counter()
    status = build_main(["-W", "--keep-going", "-q", "-b", "html", str(source), str(args.out)])
    if status == 0:
        print(f"wrote {Path(args.out) / 'index.html'} in {time.perf_counter() - t0:.1f} s")
    return int(status)
