"""The documentation sources: references resolve, tutorials run, generated pages are complete.

The Sphinx build itself (``sphinx-build -W``) runs in ``.ci/run``, not here; these
tests check what can be checked without Sphinx, quickly.
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import os
import re
from pathlib import Path

import matplotlib.pyplot as plt
import pytest
from fresh_scripts import background_job

import supercoil

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
THEORY = DOCS / "theory"
#: theory pages written by other work in progress: cited before they exist is allowed
PENDING_PAGES = {"free-energy", "marko2007", "end-loop", "screened-interaction", "recordings"}
CITATION = re.compile(r"docs/theory/([a-z0-9_-]+)\.md(?:#([a-z0-9_-]+))?")
MD_LINK = re.compile(r"\]\(((?!https?://)[^)\s#]*\.md)?(?:#([^)\s]+))?\)")
PAGES = sorted(p for p in DOCS.rglob("*.md")
               if not p.relative_to(DOCS).parts[0].startswith("_"))  # not the build's
#: the pages whose code runs in the suite: the tutorials and the getting-started page
TUTORIALS = [*sorted((DOCS / "tutorials").glob("*.md")), DOCS / "getting-started.md"]
#: a ```bash line that is a supercoil command (set-up and activation lines are not run)
DOC_COMMAND = re.compile(r"^supercoil ")


def _slugs(heading):
    """Anchors a heading gets: MyST's (``myst_heading_anchors``) and GitHub's."""
    text = re.sub(r"[`*$\\]", "", heading.strip().lower())
    github = re.sub(r"[^\w\- ]", "", text).replace(" ", "-")
    myst = re.sub(r"[^\w\- ]", "-", text).replace(" ", "-")
    return {github, myst}


def anchors(page, html=True):
    """Every anchor of a Markdown page: headings (outside code fences), ``(label)=`` targets
    and (``html``) ``<a id="...">`` tags, which Sphinx keeps in the HTML but MyST links
    cannot resolve."""
    out, fenced = set(), False
    for line in page.read_text().splitlines():
        if line.startswith("```"):
            fenced = not fenced
        elif not fenced and (m := re.match(r"^#{1,6} (.+)$", line)):
            out |= _slugs(m.group(1))
        elif not fenced and (m := re.match(r"^\(([\w-]+)\)=\s*$", line)):
            out.add(m.group(1))
        if html:
            out |= set(re.findall(r'<a id="([\w-]+)"', line))
    return out


def citing_files():
    files = [*(ROOT / "supercoil").rglob("*.py"), *(ROOT / "examples").glob("*.py"),
             *PAGES, ROOT / "README.md", ROOT / "CONTRIBUTING.md"]
    return [f for f in files if f.is_file()]


def test_anchor_slugs_follow_the_heading_text():
    assert _slugs("Moroz-Nelson") == {"moroz-nelson"}
    assert "the-papers-profile" in _slugs("The paper's profile")
    assert anchors(THEORY / "geometry.md") >= {"rigidities", "linking-number", "partials"}


def test_every_theory_citation_resolves():
    """``docs/theory/<page>.md#<section>`` in code, examples, README and docs exist."""
    missing = []
    for path in citing_files():
        for page, anchor in CITATION.findall(path.read_text()):
            target = THEORY / f"{page}.md"
            if not target.is_file():
                if page not in PENDING_PAGES:
                    missing.append(f"{path.relative_to(ROOT)}: {page}.md")
            elif anchor and anchor not in anchors(target):
                missing.append(f"{path.relative_to(ROOT)}: {page}.md#{anchor}")
    assert not missing, missing


@pytest.mark.parametrize("page", PAGES, ids=[str(p.relative_to(DOCS)) for p in PAGES])
def test_markdown_links_between_pages_resolve(page):
    text = re.sub(r"```.*?```", "", page.read_text(), flags=re.S)
    for target, anchor in MD_LINK.findall(text):
        dest = (page.parent / target).resolve() if target else page
        assert dest.is_file(), f"{page.name} links to missing {target}"
        if anchor:
            assert anchor in anchors(dest, html=False), f"{page.name}: {target}#{anchor}"


def test_docs_cite_nothing_outside_the_repository():
    for page in [*PAGES, DOCS / "conf.py", DOCS / "api.rst"]:
        text = page.read_text()
        for forbidden in ("../shared", "MODEL.md", "/work/", "SCREENED-INTERACTION"):
            assert forbidden not in text, f"{page.relative_to(ROOT)} mentions {forbidden}"


def test_theory_has_the_pages_the_package_needs():
    needed = {"index", "conventions", "geometry", "contact", "smooth", "rough", "design",
              "spinning", "plectoneme", "li-zhao", "models", "fitting", "limits", "corrections"}
    assert needed <= {p.stem for p in THEORY.glob("*.md")}


def _doc_commands(page):
    """The ``supercoil`` lines of a page's ```bash blocks, in order."""
    blocks = re.findall(r"^```bash\n(.*?)^```", page.read_text(), re.M | re.S)
    return [line for block in blocks for line in block.splitlines() if DOC_COMMAND.match(line)]


def _run_command(command, cwd):
    """Run a page's command line as bash expands it (``$(python ...)`` with this Python),
    in-process through :func:`supercoil.cli.main`; returns the exit status."""
    import subprocess
    import sys

    from supercoil import cli

    bindir = cwd / "bin"
    bindir.mkdir(exist_ok=True)
    (bindir / "python").write_text(f'#!/bin/sh\nexec "{sys.executable}" "$@"\n')
    (bindir / "python").chmod(0o755)
    env = dict(os.environ, PATH=f"{bindir}{os.pathsep}{os.environ.get('PATH', '')}",
               PYTHONPATH=str(ROOT), MPLBACKEND="Agg")
    proc = subprocess.run(["bash", "-c", f"printf '%s\\0' {command}"], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=60, check=True)
    argv = proc.stdout.split("\0")[:-1]
    err = io.StringIO()
    with contextlib.redirect_stderr(err):
        status = cli.main(argv[1:])
    assert status == 0, (command, err.getvalue()[-2000:])


def run_page(page):
    """Run a page as a reader would, in the current folder: its Python blocks in order in
    one namespace, then its ``supercoil`` command lines; returns the namespace."""
    blocks = re.findall(r"^```python\n(.*?)^```", page.read_text(), re.M | re.S)
    assert blocks, f"{page.name} has no Python code"
    namespace = {"__name__": "__tutorial__"}
    with contextlib.redirect_stdout(io.StringIO()):
        for i, block in enumerate(blocks):
            exec(compile(block, f"{page.name} block {i}", "exec"), namespace)
        for command in _doc_commands(page):
            _run_command(command, Path.cwd())
    plt.close("all")
    return namespace


#: what the tests read of a tutorial's namespace (pickled by :func:`tutorial_process`)
KEPT = ("fit", "intervals", "table")


def tutorial_process(page, kept):
    """The process of the job ``tutorial:<page>``: :func:`run_page` in the current folder,
    then the names of :data:`KEPT` that the page defined, pickled to ``kept``."""
    import pickle

    from supercoil.datasets.published import ENV_VAR

    # the tutorials run on their synthetic stand-ins; the real files are the opt-in tests'
    os.environ.pop(ENV_VAR, None)
    namespace = run_page(Path(page))
    with open(kept, "wb") as f:
        pickle.dump({k: namespace[k] for k in KEPT if k in namespace}, f)


def _tutorial_job(page):
    def job(lane, folder):
        proc = lane.call(__file__, "tutorial_process", page, folder / ".kept.pkl",
                         timeout=600, cwd=folder)
        return proc, folder
    return job


for _page in TUTORIALS:
    background_job(f"tutorial:{_page.stem}", _tutorial_job(_page))


@pytest.mark.parametrize("page", [
    pytest.param(p, marks=pytest.mark.background(f"tutorial:{p.stem}"), id=p.stem)
    for p in TUTORIALS])
def test_tutorial_code_runs(page, background):
    """The Python blocks of a tutorial run in order in one namespace (a reader's session),
    then its command lines: in a fresh interpreter of the background lane (the job
    ``tutorial:<page>``, warnings are errors as here)."""
    import pickle

    proc, folder = background.result(f"tutorial:{page.stem}")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    with open(folder / ".kept.pkl", "rb") as f:
        namespace = pickle.load(f)
    if page.stem == "own-data":  # on the stand-in the fit recovers what it was made with
        from supercoil.datasets.published import SYNTHETIC_LENGTH_NM, SYNTHETIC_TORQUE_SCALE

        fit, intervals = namespace["fit"], namespace["intervals"]
        for name, true in (("length", SYNTHETIC_LENGTH_NM),
                           ("torque_scale", SYNTHETIC_TORQUE_SCALE),
                           ("plectoneme_twist_persistence", 24.0), ("turns_offset", 0.6)):
            pull = (fit.parameters[name].m - true) / fit.stderr[name].m
            assert abs(pull) < 5, (name, pull)
        for name in ("length", "torque_scale"):  # the 2-sigma profile interval holds it
            row = intervals.loc[name]
            true = SYNTHETIC_LENGTH_NM if name == "length" else SYNTHETIC_TORQUE_SCALE
            assert row["lower_2sigma"] < true < row["upper_2sigma"]
        assert any("from the torque zero crossing" in n for n in fit.notes)
        assert (folder / "profile_P.png").is_file()
        table = namespace["table"]  # the recording's beads, made with C_t = 95 nm
        ok = table[table["success"]]
        assert len(ok) == 3
        assert (abs(ok["twist_persistence"] - 95) < 5 * ok["twist_persistence_stderr"]).all()


def test_every_page_with_commands_runs_them():
    """The command lines of the docs are run by test_tutorial_code_runs (its pages)."""
    pages = [p for p in PAGES if _doc_commands(p)]
    assert set(pages) <= set(TUTORIALS), sorted(set(pages) - set(TUTORIALS))


def _docgen():
    spec = importlib.util.spec_from_file_location("docgen", DOCS / "_ext" / "docgen.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_generated_pages_cover_every_public_name_example_and_theory_page(tmp_path):
    _docgen().generate(tmp_path)
    names = {p.stem for p in (tmp_path / "api").glob("*.rst")}
    assert names == set(supercoil.__all__)
    table = (tmp_path / "api_names.rst").read_text()
    for name in supercoil.__all__:
        assert f"<_generated/api/{name}>" in table
    api = tmp_path / "api"
    assert ".. autofunction:: supercoil.hat_curve" in (api / "hat_curve.rst").read_text()
    assert ".. autoclass:: supercoil.DNA" in (api / "DNA.rst").read_text()
    gallery = (tmp_path / "gallery.md").read_text()
    for script in (ROOT / "examples").glob("[!_]*.py"):
        assert f"## {script.stem}" in gallery
    toc = (tmp_path / "theory_toctree.md").read_text().splitlines()
    listed = [line for line in toc if line and not line.startswith((":", "```"))]
    assert sorted(listed) == sorted(p.stem for p in THEORY.glob("*.md") if p.stem != "index")
    assert listed[0] == "conventions"
    assert "| measurement |" in (tmp_path / "benchmarks.md").read_text()
    # supercoil.traces (outside supercoil.__all__) has its pages too
    from supercoil import traces

    assert {p.stem for p in (tmp_path / "traces").glob("*.rst")} == set(traces.__all__)
    assert ".. autofunction:: supercoil.traces.read_magscope" in (
        tmp_path / "traces" / "read_magscope.rst").read_text()
    assert "<_generated/traces/rotation_curves>" in (tmp_path / "traces_names.rst").read_text()
    assert ".. include:: _generated/traces_names.rst" in (DOCS / "api.rst").read_text()


# ---- supercoil docs (supercoil/commands/docs.py) --------------------------------------------


def _docs_cli(argv):
    import argparse

    from supercoil.commands import docs

    parser = argparse.ArgumentParser(prog="supercoil")
    docs.register(parser.add_subparsers(dest="command"))
    args = parser.parse_args(["docs", *argv])
    return args.func(args)


def test_docs_dataset_writes_the_shipped_file(tmp_path, capsys):
    from supercoil.datasets import dataset_path

    assert _docs_cli(["dataset"]) == 0
    assert "rotation_curves" in capsys.readouterr().out.split()
    assert _docs_cli(["dataset", "rotation_curves", "--out", str(tmp_path)]) == 0
    written = tmp_path / "rotation_curves.csv"
    assert written.read_bytes() == dataset_path("rotation_curves").read_bytes()
    with pytest.raises(supercoil.DataError, match="no sample data set"):
        _docs_cli(["dataset", "nope", "--out", str(tmp_path)])


def test_docs_build_without_sources_says_so(tmp_path, capsys):
    assert _docs_cli(["build", "--source", str(tmp_path), "--out", str(tmp_path / "h")]) == 2
    assert "no Sphinx sources" in capsys.readouterr().err
    assert not (tmp_path / "h").exists()


def test_docstring_pipes_are_escaped_outside_literals():
    escape = _docgen().escape_pipes
    assert escape("2 pi |N| = x") == r"2 pi \|N\| = x"
    assert escape("``2 pi |N|`` and |N|") == r"``2 pi |N|`` and \|N\|"
    assert escape(r"already \|N\|") == r"already \|N\|"


# --- "Implements docs/theory/<page>.md (<label>, ...)" lines of the kernels ---------------
IMPLEMENTS = re.compile(r"Implements docs/theory/([a-z0-9_-]+)\.md \(([^()]+)\)")
#: a numbered equation of a page, ``\tag{GE1}``
TAG = re.compile(r"\\tag\{([^}]+)\}")
#: the paper's labels cited on a page, ``[eq da/ds]`` or ``[eq alpha def, Eq curvature1]``
PAPER_LABELS = re.compile(r"\[([^\]\n]+)\]")
#: the pages of the DNA models: every numbered equation there has an implementing function
DNA_MODEL_PAGES = ("plectoneme", "li-zhao", "free-energy", "marko2007", "end-loop", "ensemble",
                   "melting", "screened-interaction", "models")


def equation_labels(text):
    """Labels of a theory page: its ``\\tag`` numbers and the paper labels it cites."""
    labels = set(TAG.findall(text))
    for group in PAPER_LABELS.findall(text):
        labels |= {x.strip() for x in group.split(",") if re.match(r"[Ee]q ", x.strip())}
    return labels


def implements_lines(files):
    """(file, page, label) of every label of every ``Implements`` line in ``files``."""
    return [(f, page, label.strip()) for f in files
            for page, labels in IMPLEMENTS.findall(f.read_text()) for label in labels.split(",")]


def unresolved(refs, theory):
    """The references of ``implements_lines`` whose page or label does not exist."""
    bad = []
    for f, page, label in refs:
        p = theory / f"{page}.md"
        if not p.exists() or label not in equation_labels(p.read_text()):
            bad.append(f"{f.name}: {page}.md ({label})")
    return bad


def test_every_implements_line_names_an_existing_page_and_equation():
    refs = implements_lines(sorted((ROOT / "supercoil").rglob("*.py")))
    assert len(refs) >= 30  # the kernels carry them (not a vacuous pass)
    assert not unresolved(refs, THEORY)


def test_an_implements_line_with_a_wrong_page_or_label_is_caught(tmp_path):
    (tmp_path / "page.md").write_text("$$ x = 1 \\tag{E1} $$ and [eq da/ds, Eq curvature1].\n")
    good = tmp_path / "good.py"
    good.write_text('"""Implements docs/theory/page.md (E1, eq da/ds, Eq curvature1)."""\n')
    bad = tmp_path / "bad.py"
    bad.write_text('"""Implements docs/theory/page.md (E2).\n\n'
                   'Implements docs/theory/nopage.md (E1)."""\n')
    assert unresolved(implements_lines([good]), tmp_path) == []
    assert unresolved(implements_lines([bad]), tmp_path) == ["bad.py: page.md (E2)",
                                                             "bad.py: nopage.md (E1)"]


def test_every_numbered_equation_of_the_dna_model_pages_has_an_implementing_function():
    done = {(page, label) for _, page, label in
            implements_lines(sorted((ROOT / "supercoil" / "core").rglob("*.py")))}
    missing = [f"{page}.md ({label})" for page in DNA_MODEL_PAGES
               for label in sorted(TAG.findall((THEORY / f"{page}.md").read_text()))
               if (page, label) not in done]
    assert not missing, f"numbered equations without an 'Implements' line: {missing}"
