"""Every script in examples/ runs from a fresh checkout, headless, and writes its outputs.

Each example takes ``--out DIR`` (where to write PNG and CSV files) and
``--quick`` (a smaller run for the test suite; validation scripts use it to
stay within the suite's time budget).

Each script runs as ``python SCRIPT --out DIR --quick`` in a fresh process, forked from a
helper that has imported numpy, scipy, pandas, matplotlib and supercoil once
(:mod:`fresh_scripts`: the same argv, ``sys.path``, ``__main__`` and Agg backend as a
fresh interpreter; no state passes from one script to the next).
"""

import os
from pathlib import Path

import pytest
from fresh_scripts import FreshScripts

EXAMPLES = sorted((Path(__file__).resolve().parent.parent / "examples").glob("*.py"))


def test_there_are_examples():
    assert EXAMPLES, "examples/ holds no scripts"


@pytest.fixture(scope="module")
def scripts():
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("DISPLAY", None)
    helper = FreshScripts(env)
    yield helper
    helper.close()


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs_and_writes_outputs(script, tmp_path, scripts):
    out = tmp_path / "out"
    status, _, stderr = scripts.run(script, ["--out", out, "--quick"], cwd=tmp_path,
                                    timeout=240)
    assert status == 0, stderr[-3000:]
    written = {p.suffix for p in out.rglob("*") if p.is_file()}
    assert ".png" in written, f"{script.name} wrote no figure"
    assert ".csv" in written, f"{script.name} wrote no table"
