"""`supercoil bench --smoke` runs end to end and its measurements make physical sense.

The smoke run is ``--quick`` at the smallest sizes that still write and fill every chart
and table (``supercoil.benchmark.suite.SIZES``). It runs once per session in a fresh
interpreter (:func:`bench_process`) in the suite's background lane (the job ``bench``,
``tests/fresh_scripts.py``); the tests that read its outputs carry ``background("bench")``.

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
from fresh_scripts import background_job

import supercoil as sc
from supercoil.cli import main

#: the tests that read the smoke run's outputs
ON_BENCH = pytest.mark.background("bench")


def bench_process(out):
    """The process of the job ``bench``: ``supercoil bench --smoke --out OUT``.

    Then, for tests/benchmark/test_stability.py, the run's stability map (the whole quick
    map of the default materials, which the run computed and ``stability.run`` keeps per
    process) pickled with its attrs as ``stability_map.pickle``, and what the figure that
    the run drew from it and saved as ``stability_map.png`` shows (read from that figure
    as ``stability.plot`` returned it): ``stability_plot.json``, the title and axis labels
    of every panel and the number of solvers in the table.
    """
    import json
    import pickle
    from pathlib import Path

    from supercoil.benchmark import stability

    drawn = []
    plot = stability.plot

    def recording_plot(table, path=None):
        fig = plot(table, path)
        drawn.append([[ax.get_title(), ax.get_xlabel(), ax.get_ylabel()] for ax in fig.axes])
        return fig

    stability.plot = recording_plot
    try:
        status = main(["bench", "--smoke", "--out", out])
    finally:
        stability.plot = plot
    assert len(drawn) == 1, f"supercoil bench drew the stability map {len(drawn)} times"
    table = stability.run(quick=True)
    with open(Path(out) / "stability_map.pickle", "wb") as f:
        pickle.dump(table, f)
    (Path(out) / "stability_plot.json").write_text(json.dumps(
        {"panels": drawn[0], "solvers": int(table["solver"].nunique())}))
    return status


@background_job("bench")
def _bench_smoke(lane, folder):
    """:func:`bench_process` in a fresh process: (process, output folder)."""
    return lane.call(__file__, "bench_process", folder / "out", timeout=900,
                     cwd=folder), folder / "out"


@pytest.fixture(scope="module")
def bench_dir(background):
    proc, out = background.result("bench")
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return out


@ON_BENCH
def test_bench_writes_every_chart_and_table(bench_dir):
    for name in ("work_precision.png", "unit_boundary.png", "stability_map.png",
                 "family_precision.png", "bench_measurements.csv", "hat_curve_cost.csv",
                 "unit_boundary.csv", "stability_map.csv", "family_precision.csv",
                 "dna_model_cost.csv", "screened_equilibrium_cost.csv", "bench_sections.csv",
                 "headline.csv", "headline.md"):
        assert (bench_dir / name).stat().st_size > 0, name
    assert "Measured on:" in (bench_dir / "headline.md").read_text()
    assert "load average" in (bench_dir / "headline.md").read_text()


def _bound(target):
    """(comparison, number) of a target text such as '<= 10x', '>= 1.8x', 'about 10-15 ms'."""
    m = re.match(r"\s*(<=|>=|<|>)\s*([0-9.e+-]+)", target)
    if m:
        return m.group(1), float(m.group(2))
    m = re.match(r"\s*about\s+[0-9.]+\s*-\s*([0-9.]+)", target)
    return "<=", float(m.group(1))


@ON_BENCH
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
        holds = {"<=": value <= bound, ">=": value >= bound, "<": value < bound,
                 ">": value > bound}[op]
        assert bool(row["met"]) == holds, row
    cli = head[head["measurement"].str.startswith("supercoil hat")]["note"].iloc[0]
    for phase in ("import", "compute", "plot"):
        assert re.search(rf"{phase} [0-9.]+ s", cli), phase
    # the pool's ratios are medians of paired runs, each within the spread of its pairs
    for needle in ("CPU per molecule, pool", "molecules per second per core"):
        row = head[head["measurement"].str.contains(needle, regex=False)].iloc[0]
        lo, hi = (float(x) for x in re.search(r"spread over ([0-9.]+)-([0-9.]+)",
                                              row["note"]).groups())
        value = float(row["value"])  # the note's numbers have 3 digits (within 0.5 %)
        assert lo * (1 - 6e-3) <= value <= hi * (1 + 6e-3), row["note"]


@ON_BENCH
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


@ON_BENCH
def test_stability_map_in_bench_has_no_wrong_cell(bench_dir):
    smap = sc.read_csv(bench_dir / "stability_map.csv")
    assert set(smap["category"]) <= {"ok", "flagged", "named error"}
    assert np.isfinite(smap[smap["category"] == "ok"]["force"].dropna()).all()


def test_model_cost_measures_every_model():
    """The free-energy and marko2007 benchmarks beside li-zhao: rows per model, ratios."""
    from supercoil.benchmark.dna_models import MODELS, UNITS, model_cost
    from supercoil.tables import make_table

    rows = model_cost(n_forces=20, sizes=(200,), repeat=1, coiled=(40.0, 400))
    assert make_table(rows, UNITS).shape == (10, 7)
    assert rows["model"] == list(MODELS) * 5
    assert "past full coiling" in rows["measurement"][6]
    assert rows["measurement"][8].startswith("public sc.hat_curve")  # the same points
    assert rows["points"][8] == rows["points"][6] == 400
    ratio = np.array(rows["ratio_to_li_zhao"])
    assert np.all(ratio[::2] == 1.0) and np.all(np.isfinite(ratio)) and np.all(ratio > 0)
    assert np.all(np.array(rows["rate"]) > 0)
    assert "full coiling" in rows["measurement"][2]
    three = ("li-zhao", "free-energy", "marko2007")
    rows = model_cost(n_forces=10, sizes=(100,), repeat=1, models=three, coiled=None)
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


@ON_BENCH
def test_the_two_memory_regimes_differ_in_page_faults(bench_dir):
    """The children of hat_throughput_regimes run under glibc settings that reuse freed
    memory (no page faults per call) or map every large array anew (faults, the pass's
    output too): what the two rows of each hat-curve target stand for. Read from the
    notes of the two ``public sc.hat_curve`` rows of the smoke run (2e5 turns values:
    arrays above the 1 MB mmap threshold of the fresh regime)."""
    import sys

    if not sys.platform.startswith("linux"):
        pytest.skip("glibc malloc settings (Linux)")
    from supercoil.benchmark.headline import REGIMES

    head = sc.read_csv(bench_dir / "headline.csv")
    faults = {}
    for regime, label in REGIMES.items():
        (note,) = head[head["measurement"].str.startswith("public sc.hat_curve, ")
                       & head["measurement"].str.contains(f"[{label}]", regex=False)]["note"]
        m = re.search(r"minor page faults per call: public (\d+), the 9 columns (\d+), "
                      r"the sqrt pass (\d+)", note)
        assert m, note
        faults[regime] = dict(zip(("public", "columns", "sqrt_pass"), map(int, m.groups()),
                                  strict=True))
    assert faults["reused"]["public"] < 0.1 * faults["fresh"]["public"]
    assert faults["fresh"]["sqrt_pass"] > 0 and faults["reused"]["sqrt_pass"] == 0
