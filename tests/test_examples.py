"""Every script in examples/ runs from a fresh checkout, headless, and writes its outputs.

Each example takes ``--out DIR`` (where to write PNG and CSV files) and
``--quick`` (a smaller run for the test suite; validation scripts use it to
stay within the suite's time budget).

Each script runs once per session as ``python SCRIPT --out DIR --quick`` in a fresh
process, in the suite's background lane, forked from a helper that has imported numpy,
scipy, pandas, matplotlib and supercoil once (the ``example_run`` fixture of
``conftest.py`` and :mod:`fresh_scripts`:
the same argv, ``sys.path``, ``__main__`` and Agg backend as a fresh interpreter; no state
passes from one script to the next); tests that check an example's outputs further
(``tests/fitting/test_csv_outputs.py``) read the same run.
"""

from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).resolve().parent.parent / "examples").glob("*.py"))


def test_there_are_examples():
    assert EXAMPLES, "examples/ holds no scripts"


@pytest.mark.parametrize("script", [
    pytest.param(p, marks=pytest.mark.background(f"example:{p.stem}"), id=p.stem)
    for p in EXAMPLES])
def test_example_runs_and_writes_outputs(script, example_run):
    status, stderr, out = example_run(script.stem)
    assert status == 0, stderr[-3000:]
    written = {p.suffix for p in out.rglob("*") if p.is_file()}
    assert ".png" in written, f"{script.name} wrote no figure"
    assert ".csv" in written, f"{script.name} wrote no table"
