"""Every script in examples/ runs from a fresh checkout, headless, and writes its outputs.

Each example takes ``--out DIR`` (where to write PNG and CSV files) and
``--quick`` (a smaller run for the test suite; validation scripts use it to
stay within the suite's time budget).
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

EXAMPLES = sorted((Path(__file__).resolve().parent.parent / "examples").glob("*.py"))


def test_there_are_examples():
    assert EXAMPLES, "examples/ holds no scripts"


@pytest.mark.parametrize("script", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_example_runs_and_writes_outputs(script, tmp_path):
    out = tmp_path / "out"
    env = dict(os.environ, MPLBACKEND="Agg")
    env.pop("DISPLAY", None)
    proc = subprocess.run(
        [sys.executable, str(script), "--out", str(out), "--quick"],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=240,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    written = {p.suffix for p in out.rglob("*") if p.is_file()}
    assert ".png" in written, f"{script.name} wrote no figure"
    assert ".csv" in written, f"{script.name} wrote no table"
