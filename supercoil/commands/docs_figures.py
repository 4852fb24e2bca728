"""``supercoil docs figures``: rerun every script that writes a number or figure of the docs.

    supercoil docs figures [--quick] [--skip-bench] [--root DIR] [--work DIR]

runs, each into its own folder under ``--work`` (default: a temporary folder),

* every ``examples/*.py`` with ``--out`` (and ``--quick`` if given),
* ``supercoil validate``,
* ``supercoil bench`` (unless ``--skip-bench``),
* the main job, ``supercoil hat --params dna`` (li-zhao) and the same with
  ``--model free-energy``,

then copies into ``docs/figures/`` every PNG they wrote that the README or a page
under ``docs/`` shows (``docs/figures/hat_curves.png`` is the main job's own
``hat_curve.png``), writes the generated blocks ``docs/generated/NAME.md`` from
the tables they wrote (the source tables go to ``docs/generated/data/NAME.csv``),
and rewrites every block

    <!-- generated: NAME -->
    ...
    <!-- end generated: NAME -->

of ``README.md`` with the content of ``docs/generated/NAME.md`` (one trailing newline
stripped). ``tests/test_readme_numbers.py`` checks, without running any script, that
the README's blocks are those files.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: ``<!-- generated: NAME -->`` newline, content, newline, ``<!-- end generated: NAME -->``
BLOCK = re.compile(r"<!-- generated: (?P<name>[\w-]+) -->\n(?P<body>.*?)\n?"
                   r"<!-- end generated: (?P=name) -->", re.S)
#: the main job: the README's set-up command (li-zhao), and the free-energy model beside it
MAIN_JOB_MODELS = ("li-zhao", "free-energy")
#: what a source checkout holds (``--root``)
CHECKOUT = ("README.md", "examples", "docs")


def add_parser(actions):
    """Add the ``figures`` action to the ``supercoil docs`` action subparsers."""
    f = actions.add_parser(
        "figures", help="rerun the examples, validate, bench and the main job; rewrite "
        "docs/figures, docs/generated and the README's generated blocks",
        description=__doc__.splitlines()[0])
    f.add_argument("--quick", action="store_true",
                   help="the examples' and the bench's smaller runs (for a quick look)")
    f.add_argument("--skip-bench", action="store_true",
                   help="keep docs/generated/headline.md and the bench figures as they are")
    f.add_argument("--root", default=None,
                   help="the source checkout (default: the working folder if it is one, else "
                   "the checkout this package is in)")
    f.add_argument("--work", default=None,
                   help="folder for the scripts' outputs (default: a temporary folder)")
    return f


# ---- running the scripts --------------------------------------------------------------------


def _run(argv, root, log, label):
    """Run ``argv`` (a Python script or ``-m supercoil.cli``) with the checkout importable."""
    env = dict(os.environ, MPLBACKEND="Agg",
               PYTHONPATH=os.pathsep.join([str(root), os.environ.get("PYTHONPATH", "")]))
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, *map(str, argv)], cwd=root, env=env,
                          capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError(f"{label} failed (exit status {proc.returncode}):\n"
                           f"{proc.stderr[-3000:]}")
    log(f"  {label}: {time.perf_counter() - t0:.1f} s")
    return proc


def run_scripts(root: Path, work: Path, quick: bool, skip_bench: bool, log) -> dict:
    """Run every script; returns ``{name: output folder}`` (``examples/<stem>``, ...)."""
    quick_flag = ["--quick"] if quick else []
    folders = {}
    for script in sorted((root / "examples").glob("*.py")):
        out = folders[f"examples/{script.stem}"] = work / "examples" / script.stem
        _run([script, "--out", out, *quick_flag], root, log, f"examples/{script.name}")
    out = folders["validate"] = work / "validate"
    _run(["-m", "supercoil.cli", "validate", "--out", out], root, log, "supercoil validate")
    if not skip_bench:
        out = folders["bench"] = work / "bench"
        _run(["-m", "supercoil.cli", "bench", "--out", out, *quick_flag], root, log,
             "supercoil bench")
    for model in MAIN_JOB_MODELS:
        out = folders[f"main-job/{model}"] = work / "main-job" / model
        proc = _run(["-m", "supercoil.cli", "hat", "--params", "dna", "--model", model,
                     "--out", out], root, log, f"supercoil hat --params dna --model {model}")
        if proc.stderr.strip():  # the main job must not warn: the user who runs it sees no noise
            raise RuntimeError(f"the main job ({model}) wrote to stderr:\n{proc.stderr}")
    return folders


def shown_figures(root: Path) -> set[str]:
    """Names of the ``docs/figures/*.png`` files that README.md or a docs page shows."""
    texts = [(root / "README.md").read_text()]
    texts += [p.read_text() for p in (root / "docs").rglob("*.md")]
    texts += [p.read_text() for p in (root / "docs").rglob("*.rst")]
    return {m for t in texts for m in re.findall(r"figures/([\w.-]+\.png)", t)}


def copy_figures(root: Path, folders: dict, log) -> list[str]:
    """Copy the figures the scripts wrote into docs/figures; the main job's last.

    Copied: every PNG that the README or a docs page shows, or that docs/figures already
    holds (the examples gallery shows those); a script's other PNGs stay in ``--work``.
    """
    target = root / "docs" / "figures"
    wanted = shown_figures(root) | {p.name for p in target.glob("*.png")}
    found = {}
    for name, folder in folders.items():
        if name.startswith("main-job/"):
            continue
        for png in sorted(Path(folder).rglob("*.png")):
            if png.name in wanted:
                found[png.name] = png
    # the README's main-job figure is what `supercoil hat` itself writes
    found["hat_curves.png"] = Path(folders["main-job/li-zhao"]) / "hat_curve.png"
    target.mkdir(parents=True, exist_ok=True)
    for name, png in sorted(found.items()):
        shutil.copyfile(png, target / name)
    missing = sorted(wanted - set(found) - {p.name for p in target.glob("*.png")})
    if missing:
        log(f"  shown but written by no script: {', '.join(missing)}")
    return sorted(found)


# ---- the generated blocks ---------------------------------------------------------------------


def write_generated(root: Path, folders: dict, log) -> dict:
    """Write docs/generated/NAME.md (and data/NAME.csv) from the scripts' outputs."""
    from supercoil.commands import docs_tables as t
    from supercoil.tables import read_csv, write_csv

    gen = root / "docs" / "generated"
    (gen / "data").mkdir(parents=True, exist_ok=True)
    tables = {
        "validation": t.validation_summary(read_csv(Path(folders["validate"])
                                                    / "validation.csv")),
        "main-job": t.main_job_table({m: read_csv(Path(folders[f"main-job/{m}"])
                                                  / "buckling.csv") for m in MAIN_JOB_MODELS}),
        "fit-example": t.fit_example_table(read_csv(
            Path(folders["examples/fit_tweezers_data"]) / "fit_parameters.csv")),
    }
    written = {}
    for name, table in tables.items():  # rendered from the kept CSV, as the test does
        written[name] = t.RENDERERS[name](read_csv(write_csv(table, gen / "data" / f"{name}.csv")))
    written["models"] = t.models_markdown()
    if "bench" in folders:
        written["headline"] = (Path(folders["bench"]) / "headline.md").read_text()
    for name, text in written.items():
        (gen / f"{name}.md").write_text(text if text.endswith("\n") else text + "\n")
        log(f"  wrote docs/generated/{name}.md")
    return written


def fill_blocks(text: str, generated: Path) -> tuple[str, list[str]]:
    """``text`` with every generated block replaced by its file; and the block names."""
    names = []

    def replace(match):
        name = match["name"]
        names.append(name)
        path = generated / f"{name}.md"
        if not path.is_file():
            raise FileNotFoundError(f"README block {name!r} has no file {path}")
        body = path.read_text().removesuffix("\n")
        return f"<!-- generated: {name} -->\n{body}\n<!-- end generated: {name} -->"

    return BLOCK.sub(replace, text), names


def run(args) -> int:
    """The ``figures`` action of ``supercoil docs``."""
    from supercoil.commands._common import is_source_checkout, source_checkout

    # default: the working folder if it is the checkout (``pip install .`` puts the package
    # outside it), else the checkout the package is in (an editable install)
    root = source_checkout(args.root, needs=CHECKOUT)
    if root is None or not is_source_checkout(root, CHECKOUT):
        where = (f"{root} is not" if root is not None
                 else "neither the working folder nor the package's folder is")
        print(f"supercoil docs figures: error: {where} a source checkout (README.md, "
              "examples/ and docs/): run the command in the repository, or pass --root",
              file=sys.stderr)
        return 2

    def log(msg):
        print(msg, file=sys.stderr)

    with tempfile.TemporaryDirectory(prefix="supercoil-docs-") as tmp:
        work = Path(args.work) if args.work else Path(tmp)
        log(f"running the scripts into {work}")
        try:
            folders = run_scripts(root, work, args.quick, args.skip_bench, log)
        except RuntimeError as exc:
            print(f"supercoil docs figures: error: {exc}", file=sys.stderr)
            return 2
        figures = copy_figures(root, folders, log)
        write_generated(root, folders, log)
    readme = root / "README.md"
    text, names = fill_blocks(readme.read_text(), root / "docs" / "generated")
    readme.write_text(text)
    print(f"wrote {len(figures)} figures into docs/figures, "
          f"{len(list((root / 'docs' / 'generated').glob('*.md')))} files into docs/generated; "
          f"README blocks rewritten: {', '.join(names) or 'none'}")
    return 0
