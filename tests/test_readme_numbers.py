"""README truth: every generated block of README.md is the file its script wrote last.

``supercoil docs figures`` reruns the scripts (examples, ``supercoil validate``,
``supercoil bench``, the main job), writes ``docs/generated/NAME.md`` (and the source
table ``docs/generated/data/NAME.csv``) and copies each into the README block
``<!-- generated: NAME -->`` ... ``<!-- end generated: NAME -->``. These tests run
none of the slow scripts: they compare the README with the files, re-render the kept
tables, and recompute the cheap numbers (the model registry, the main job's buckling)
with the code as it is now, so a change of the model without a rerun fails here.
"""

from __future__ import annotations

import io
from contextlib import redirect_stderr
from pathlib import Path

import numpy as np
import pytest

import supercoil as sc
from supercoil.commands import docs_tables
from supercoil.commands.docs_figures import BLOCK, MAIN_JOB_MODELS, _run, fill_blocks

ROOT = Path(__file__).resolve().parent.parent
README = (ROOT / "README.md").read_text()
GENERATED = ROOT / "docs" / "generated"
BLOCKS = {m["name"]: m["body"] for m in BLOCK.finditer(README)}
#: the blocks the README must carry
REQUIRED = {"headline", "validation", "main-job", "models", "fit-example"}


def test_readme_has_every_required_block_once():
    names = [m["name"] for m in BLOCK.finditer(README)]
    assert sorted(names) == sorted(set(names)), "a block appears twice"
    assert set(names) >= REQUIRED
    # no unmatched marker (a typo in a name would leave one unpaired)
    assert README.count("<!-- generated: ") == len(names)
    assert README.count("<!-- end generated: ") == len(names)


@pytest.mark.parametrize("name", sorted(BLOCKS))
def test_block_equals_its_generated_file(name):
    path = GENERATED / f"{name}.md"
    assert path.is_file(), f"README block {name!r} has no docs/generated/{name}.md"
    assert BLOCKS[name] == path.read_text().removesuffix("\n"), (
        f"README block {name!r} differs from docs/generated/{name}.md: run "
        "`supercoil docs figures`")


def test_every_generated_file_is_used_by_the_readme():
    unused = sorted({p.stem for p in GENERATED.glob("*.md")} - set(BLOCKS))
    assert not unused, f"docs/generated files no README block shows: {unused}"


def test_filling_the_readme_again_changes_nothing():
    text, names = fill_blocks(README, GENERATED)
    assert text == README and set(names) == set(BLOCKS)


@pytest.mark.parametrize("name", sorted(docs_tables.RENDERERS))
def test_block_is_the_rendering_of_its_kept_table(name):
    table = sc.read_csv(GENERATED / "data" / f"{name}.csv")
    assert docs_tables.RENDERERS[name](table) == (GENERATED / f"{name}.md").read_text()


def test_models_block_is_the_registry_now():
    assert (GENERATED / "models.md").read_text() == docs_tables.models_markdown()
    for name in sc.available_models():
        own = type(sc.dna.models.get_model(name)).__module__.startswith("supercoil.")
        assert (f"`{name}`" in BLOCKS["models"]) == own


def test_main_job_numbers_are_what_the_code_computes_now(dna, ureg):
    table = sc.read_csv(GENERATED / "data" / "main-job.csv")
    assert list(dict.fromkeys(table["model"])) == list(MAIN_JOB_MODELS)
    for model, g in table.groupby("model", sort=False):
        assert list(g["force"]) == [0.4, 1.2, 3.0]  # the main job's default forces
        f = g["force"].to_numpy() * ureg.pN
        np.testing.assert_allclose(g["buckling_turns"],
                                   sc.buckling_turns(dna, f, model=model).m_as("turn"),
                                   rtol=1e-9)
        np.testing.assert_allclose(g["post_buckling_slope"],
                                   sc.post_buckling_slope(dna, f, model=model).m_as("nm/turn"),
                                   rtol=1e-9)
    # li-zhao buckles at the plectoneme torque (an independent solve); free-energy lower
    li = table[table.model == "li-zhao"]
    eq = sc.plectoneme_equilibrium(dna, li["force"].to_numpy() * ureg.pN)
    np.testing.assert_allclose(li["buckling_torque"], eq.torque.m_as("pN nm"), rtol=1e-9)
    fe = table[table.model == "free-energy"]
    assert (fe["buckling_torque"].to_numpy() < li["buckling_torque"].to_numpy()).all()


def test_headline_block_is_the_bench_table():
    text = (GENERATED / "headline.md").read_text()
    assert text.startswith("| measurement | value | target | met |\n|---|---|---|---|\n")
    assert "\nMeasured on: " in text


def test_fill_blocks_replaces_stale_content_and_names_a_missing_file(tmp_path):
    (tmp_path / "a.md").write_text("| x |\n|---|\n| 1 |\n")
    text = "intro\n<!-- generated: a -->\nstale 0\n<!-- end generated: a -->\nend\n"
    new, names = fill_blocks(text, tmp_path)
    assert new == ("intro\n<!-- generated: a -->\n| x |\n|---|\n| 1 |\n"
                   "<!-- end generated: a -->\nend\n")
    assert names == ["a"]
    assert fill_blocks(new, tmp_path)[0] == new
    with pytest.raises(FileNotFoundError, match="'b'"):
        fill_blocks("<!-- generated: b -->\n<!-- end generated: b -->", tmp_path)


def test_a_failing_script_stops_the_run_naming_it(tmp_path):
    with pytest.raises(RuntimeError, match=r"the script failed \(exit status 3\)"):
        _run(["-c", "import sys; sys.exit(3)"], tmp_path, print, "the script")


def test_docs_figures_is_a_docs_action():
    from supercoil.cli import build_parser, main

    args = build_parser().parse_args(["docs", "figures", "--quick", "--skip-bench"])
    assert args.action == "figures" and args.quick and args.skip_bench
    with redirect_stderr(io.StringIO()) as err:
        assert main(["docs", "figures", "--root", str(ROOT / "docs")]) == 2
    assert "not a source checkout" in err.getvalue()


def test_copy_figures_takes_the_shown_ones_and_the_main_job_figure(tmp_path):
    from supercoil.commands.docs_figures import copy_figures

    root, work = tmp_path / "repo", tmp_path / "work"
    (root / "docs" / "figures").mkdir(parents=True)
    (root / "README.md").write_text("![a](docs/figures/a.png) ![h](docs/figures/hat_curves.png)")
    (root / "docs" / "figures" / "b.png").write_bytes(b"old b")  # shown by the gallery
    for folder, name, data in (("examples/x", "a.png", b"a"), ("examples/x", "b.png", b"b"),
                               ("examples/x", "c.png", b"c"),
                               ("examples/x", "hat_curves.png", b"the example's"),
                               ("main-job/li-zhao", "hat_curve.png", b"main job")):
        (work / folder).mkdir(parents=True, exist_ok=True)
        (work / folder / name).write_bytes(data)
    folders = {"examples/x": work / "examples/x", "main-job/li-zhao": work / "main-job/li-zhao"}
    assert copy_figures(root, folders, print) == ["a.png", "b.png", "hat_curves.png"]
    figures = root / "docs" / "figures"
    assert (figures / "hat_curves.png").read_bytes() == b"main job"
    assert (figures / "b.png").read_bytes() == b"b" and not (figures / "c.png").exists()
