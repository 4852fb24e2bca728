"""Every CSV that the fit examples and ``supercoil fit`` write reads back with its units.

Issue 15: one column-header convention everywhere: the name, then the unit in
brackets, nothing else in brackets (coverage_summary.csv had prose there).
"""

import re

import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.units import ureg

#: the examples' runs that ``written`` reads (the ones test_examples checks)
EXAMPLES = ("fit_tweezers_data", "validate_fit_coverage")
pytestmark = pytest.mark.background(*(f"example:{name}" for name in EXAMPLES))

#: a header cell: a name (may hold a molecule label "[m1]" glued to it), then " [unit]"
HEADER = re.compile(r"^(?P<name>[A-Za-z_][\w.]*(\[[^\[\]]+\])?\w*)( \[(?P<unit>[^\[\]()]+)\])?$")
DIMENSIONS = {"force": "[force]", "extension": "[length]", "torque": "[force] * [length]",
              "radius": "[length]", "twist_persistence": "[length]", "turns_offset": "turn"}


@pytest.fixture(scope="module")
def written(tmp_path_factory, true_dna, example_run):
    root = tmp_path_factory.mktemp("csv")
    examples = []
    for name in EXAMPLES:
        status, stderr, out = example_run(name)
        assert status == 0, stderr[-3000:]
        examples += list(out.rglob("*.csv"))
    u = sc.ureg
    one = simulate_rotation_curves(true_dna, [0.3, 0.5, 0.7] * u.pN, points_per_force=40,
                                   seed=9, torque_noise=2 * u.pN * u.nm, sigma_column=True)
    many = simulate_rotation_curves(true_dna, [0.3, 0.5, 0.7] * u.pN, points_per_force=30,
                                    molecules=2, seed=9)
    sc.write_csv(one, root / "one.csv")
    sc.write_csv(many, root / "many.csv")
    assert main(["fit", str(root / "one.csv"), "--out", str(root / "cli1"), "--no-plot"]) == 0
    assert main(["fit", str(root / "many.csv"), "--out", str(root / "cli2"), "--no-plot",
                 "--no-progress"]) == 0
    assert main(["fit", str(root / "many.csv"), "--global", "--out", str(root / "cli3"),
                 "--no-plot"]) == 0
    assert main(["fit", str(root / "one.csv"), "--model", "li-zhao", "--model", "marko2007",
                 "--out", str(root / "cli4"), "--no-plot"]) in (0, 1)
    files = sorted(p for p in root.rglob("*.csv") if p.parent != root)
    return sorted(examples) + files


def test_every_fit_csv_reads_back_with_units(written):
    names = {p.name for p in written}
    assert {"coverage_summary.csv", "coverage_fits.csv", "fit_points.csv", "fit_parameters.csv",
            "fit_molecules.csv"} <= names
    for path in written:
        header = next(line for line in path.read_text().splitlines()
                      if line and not line.startswith("#"))
        df = sc.read_csv(path)
        cells = [c.strip().strip('"') for c in header.split(",")]
        assert len(cells) == len(df.columns), path
        for cell, col in zip(cells, df.columns, strict=True):
            m = HEADER.match(cell)
            assert m, f"{path.name}: header {cell!r} is not 'name' or 'name [unit]'"
            unit = df.attrs["units"][col]
            assert unit == (m.group("unit") or ""), (path.name, cell)
            if unit:
                ureg.Unit(unit)  # a unit pint reads
            base = col.removesuffix("_stderr").split("[")[0]
            if base in DIMENSIONS and col != "turns":
                assert ureg.Quantity(1, unit or "turn").check(DIMENSIONS[base]), (path.name, col)
            if col.endswith("_stderr") and col.removesuffix("_stderr") in df.columns:
                assert unit == df.attrs["units"][col.removesuffix("_stderr")], (path.name, col)


def test_coverage_summary_has_a_unit_column(written):
    path = next(p for p in written if p.name == "coverage_summary.csv")
    df = sc.read_csv(path)
    assert dict(zip(df["parameter"], df["unit"], strict=True)) == {
        "twist_persistence": "nm", "radius": "nm", "turns_offset": "turn",
        "extension_offset": "nm"}
    assert np.all((df["coverage"] >= 0) & (df["coverage"] <= 1))
