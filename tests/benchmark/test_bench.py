"""`supercoil bench --quick` runs end to end and its measurements make physical sense.

No timing is asserted (timings live in the benchmark outputs); the checks are on
the errors, which do not depend on the machine, on the bookkeeping of the
headline table (every target has a value and a met column that agrees with it),
and on the measuring instruments themselves (memory tracing, kernel-call
counting, the replaying executor).
"""

import re

import numpy as np
import pandas as pd
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
                 "stability_map.csv", "dna_model_cost.csv", "headline.csv", "headline.md"):
        assert (bench_dir / name).stat().st_size > 0, name
    assert "Measured on:" in (bench_dir / "headline.md").read_text()
    assert "load average" in (bench_dir / "headline.md").read_text()


def _bound(target):
    """(comparison, number) of a target text such as '<= 10x', '>= 1.8x', 'about 10-15 ms'."""
    m = re.match(r"\s*(<=|>=)\s*([0-9.e+-]+)", target)
    if m:
        return m.group(1), float(m.group(2))
    m = re.match(r"\s*about\s+[0-9.]+\s*-\s*([0-9.]+)", target)
    return "<=", float(m.group(1))


def test_every_target_has_a_value_and_a_consistent_met_column(bench_dir):
    head = sc.read_csv(bench_dir / "headline.csv")
    text = " ".join(head["measurement"])
    # every speed and memory target has its row
    for needle in ("public sc.hat_curve", "kernel supercoil.core.dna.li_zhao.hat_curve_points",
                   "peak traced memory / memory of its result", "sc.fit_hat_curves",
                   "kernel calls x CPU", "sc.fit_many", "ProcessPoolExecutor(2)",
                   "molecules read by sc.read_tweezers_csv",
                   "sc.plectoneme_equilibrium", "beyond its output, per force",
                   "import supercoil", "supercoil hat --params dna", "sc.read_tweezers_csv",
                   "model free-energy / li-zhao",
                   # the hat-curve rows in both allocator regimes (benchmark.process)
                   "[memory reused from the previous call]", "[fresh memory"):
        assert needle in text, needle
    assert len(head) >= 20
    assert np.isfinite(head["value"].astype(float)).all()
    for _, row in head.iterrows():
        op, bound = _bound(row["target"])
        value = float(row["value"])
        assert bool(row["met"]) == (value <= bound if op == "<=" else value >= bound), row
    cli = head[head["measurement"].str.startswith("supercoil hat")]["note"].iloc[0]
    for phase in ("import", "compute", "plot"):
        assert re.search(rf"{phase} [0-9.]+ s", cli), phase


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


def test_model_cost_measures_every_model():
    """The free-energy and marko2007 benchmarks beside li-zhao: rows per model, ratios."""
    from supercoil.benchmark.dna_models import MODELS, UNITS, model_cost
    from supercoil.tables import make_table

    rows = model_cost(n_forces=20, sizes=(200,), repeat=1)
    assert make_table(rows, UNITS).shape == (6, 7)
    assert rows["model"] == list(MODELS) * 3
    ratio = np.array(rows["ratio_to_li_zhao"])
    assert np.all(ratio[::2] == 1.0) and np.all(np.isfinite(ratio)) and np.all(ratio > 0)
    assert np.all(np.array(rows["rate"]) > 0)
    assert "full coiling" in rows["measurement"][2]
    three = ("li-zhao", "free-energy", "marko2007")
    rows = model_cost(n_forces=10, sizes=(100,), repeat=1, models=three)
    time, ratio = np.array(rows["time"]), np.array(rows["ratio_to_li_zhao"])
    # each ratio is the model's time over li-zhao's time of the same measurement
    np.testing.assert_allclose(ratio, time / np.repeat(time[::3], 3), rtol=1e-12)


def test_peak_memory_sees_numpy_buffers():
    from supercoil.benchmark.cpu import peak_memory

    n = 10**6

    def make():
        temporary = np.ones(n)  # 8 MB freed on return
        return temporary * 2.0  # 8 MB kept (no temporary elision: a named array)

    m = peak_memory(make)
    assert 8 * n <= m["retained"] < 8 * n + 10_000
    assert m["peak"] >= 16 * n
    assert m["result"].shape == (n,)


def test_hat_memory_result_is_the_dataframe_it_returns():
    """The retained bytes equal pandas' own count of the table (an independent count)."""
    from supercoil.benchmark.targets_dna import HAT_FORCE, HAT_TURNS, hat_memory

    n = 20_000
    mem = hat_memory(n)
    df = sc.hat_curve(sc.load_parameters("dna"), HAT_FORCE * sc.ureg.N, np.linspace(*HAT_TURNS, n))
    pandas_bytes = df.memory_usage(deep=True).sum()
    assert abs(mem["result"] - pandas_bytes) < 0.05 * pandas_bytes
    assert mem["peak"] >= mem["result"]


def test_kernel_counter_counts_calls_and_restores_the_kernel():
    from supercoil.benchmark.targets_fit import _KernelCounter
    from supercoil.core.dna import li_zhao

    original = li_zhao.hat_curve_points
    d = sc.load_parameters("dna").si
    args = (np.array([0.0, 5.0]), np.full(2, 1e-12), d.length, d.bending_rigidity,
            d.torsional_rigidity, d.kT, d.radius)
    with _KernelCounter() as counter:
        a = li_zhao.hat_curve_points(*args)
        li_zhao.hat_curve_points(*args, thermal=False)
    assert li_zhao.hat_curve_points is original
    assert len(counter.calls) == 2 and counter.calls[1][1] == {"thermal": False}
    np.testing.assert_array_equal(a.extension, original(*args).extension)


def test_replay_executor_runs_the_function_once():
    from supercoil.benchmark.targets_fit import ReplayExecutor

    calls = []

    def work(x):
        calls.append(x)
        return {"value": x}

    ex = ReplayExecutor()
    first, second = ex.submit(work, 1), ex.submit(work, 2)
    assert calls == [1]
    assert first.result() == second.result() == {"value": 1}
    assert first.result() is not second.result()


def test_markdown_escapes_pipes_and_keeps_the_four_columns():
    from supercoil.benchmark.headline import markdown

    table = pd.DataFrame({"measurement": ["hat points, |N| <= 25"], "value": [2.5],
                          "unit": ["x"], "target": ["<= 3x"], "met": [True], "note": ["a note"]})
    text = markdown(table, "a machine", (1.0, 2.0))
    lines = text.splitlines()
    assert lines[:2] == ["| measurement | value | target | met |", "|---|---|---|---|"]
    assert lines[2] == "| hat points, \\|N\\| <= 25 (a note) | 2.5 x | <= 3x | yes |"
    # four cells: the escaped pipes do not split the row
    assert len(re.split(r"(?<!\\)\|", lines[2])) == 6
    assert lines[-1] == "Measured on: a machine; load average 1.0 at the start, 2.0 at the end."


def test_the_two_memory_regimes_differ_in_page_faults():
    """The children of hat_throughput_regimes run under glibc settings that reuse freed
    memory (no page faults per call) or map every large array anew (faults, the pass's
    output too): what the two rows of each hat-curve target stand for."""
    import sys

    if not sys.platform.startswith("linux"):
        pytest.skip("glibc malloc settings (Linux)")
    from supercoil.benchmark.process import hat_throughput_regimes

    r = hat_throughput_regimes(2 * 10**5, samples=1, compiled=False)
    assert r["reused"]["public_faults"] < 0.1 * r["fresh"]["public_faults"]
    assert r["fresh"]["sqrt_pass_faults"] > 0 and r["reused"]["sqrt_pass_faults"] == 0
