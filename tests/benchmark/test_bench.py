"""`supercoil bench --quick` runs end to end and its measurements make physical sense.

No timing is asserted (timings live in the benchmark outputs); the checks are on
the errors, which do not depend on the machine.
"""

import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main


@pytest.fixture(scope="module")
def bench_dir(tmp_path_factory):
    out = tmp_path_factory.mktemp("bench")
    assert main(["bench", "--quick", "--out", str(out)]) == 0
    return out


def test_bench_writes_every_chart_and_table(bench_dir):
    for name in ("work_precision.png", "unit_boundary.png", "stability_map.png",
                 "bench_measurements.csv", "hat_curve_cost.csv", "unit_boundary.csv",
                 "stability_map.csv", "headline.csv", "headline.md"):
        assert (bench_dir / name).stat().st_size > 0, name
    head = sc.read_csv(bench_dir / "headline.csv")
    assert len(head) >= 6
    assert "Measured on:" in (bench_dir / "headline.md").read_text()


def test_work_precision_errors_against_independent_references(bench_dir):
    wp = sc.read_csv(bench_dir / "bench_measurements.csv")
    # a failure (a missing point) is allowed only at loose tolerances: there an ODE's
    # s_max can fall short of the reference grid (NoHelixError), which is the honest answer
    assert (wp[wp["failed"]]["tolerance"] >= 1e-4).all()
    k0 = wp[wp["scene"].str.contains("k = 0")]
    closed = k0[k0["method"] == "closed form"]
    assert float(closed["error"].iloc[0]) < 1e-12  # closed form vs the explicit s(alpha)
    for method in ("DOP853", "RK45", "LSODA", "Radau"):
        sub = k0[(k0["method"] == method) & ~k0["failed"]].sort_values("tolerance")
        # tightening the tolerance reduces the error by orders of magnitude
        assert sub["error"].iloc[0] < 1e-3 * sub["error"].iloc[-1], method
    eq = wp[wp["scene"].str.contains("plectoneme")]
    tight = eq[eq["tolerance"] <= 1e-10]
    assert (tight["error"] < 1e-12).all()  # both solvers agree with the MINPACK reference


def test_stability_map_in_bench_has_no_wrong_cell(bench_dir):
    smap = sc.read_csv(bench_dir / "stability_map.csv")
    assert set(smap["category"]) <= {"ok", "flagged", "named error"}
    assert np.isfinite(smap[smap["category"] == "ok"]["force"].dropna()).all()


def test_model_cost_measures_both_models():
    """The free-energy benchmark beside li-zhao: rows per model, ratios to li-zhao."""
    from supercoil.benchmark.dna_models import MODELS, UNITS, model_cost

    rows = model_cost(n_forces=20, sizes=(200,), repeat=1)
    from supercoil.tables import make_table

    assert make_table(rows, UNITS).shape == (6, 7)
    assert rows["model"] == list(MODELS) * 3
    ratio = np.array(rows["ratio_to_li_zhao"])
    assert np.all(ratio[::2] == 1.0) and np.all(np.isfinite(ratio)) and np.all(ratio > 0)
    assert np.all(np.array(rows["rate"]) > 0)
    assert "full coiling" in rows["measurement"][2]
