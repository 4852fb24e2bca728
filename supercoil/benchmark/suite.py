"""The complete benchmark run behind ``supercoil bench --out DIR``.

Writes into DIR:

* ``work_precision.png``: the four work-precision / cost charts (rough profile
  k = 0 and designed k(S); plectoneme equilibrium; hat-curve cost per point);
* ``unit_boundary.png``: public call against the float kernel it wraps;
* ``stability_map.png``: where each solver fails, is flagged, or is valid;
* ``bench_measurements.csv``: every measured point (table convention);
* ``unit_boundary.csv``, ``stability_map.csv``;
* ``family_precision.csv`` and ``family_precision.png``: every registered model and
  interaction, cost per hat curve and per fit against the difference from the reference
  model (:mod:`supercoil.benchmark.family`);
* ``dna_model_cost.csv``: the DNA models side by side (time per force, points
  per second, ratio to li-zhao);
* ``screened_equilibrium_cost.csv``: the screened equilibrium by Newton against the
  direct nested solve it replaced;
* ``bench_sections.csv``: wall and CPU seconds of each section of the run;
* ``headline.csv`` and ``headline.md``: one row per speed or memory target
  (:mod:`supercoil.benchmark.headline`: what is timed, value, unit, target,
  met, note), with the machine and its load average.
"""

from __future__ import annotations

import contextlib
import time
from pathlib import Path

import numpy as np
import pandas as pd

from supercoil.benchmark.timing import best_time, machine_description


def _legacy_rows(wp, hat, ub, eq1000):
    """Rows of the earlier issues' targets (best wall time of a kernel or a solver)."""
    from supercoil.benchmark.headline import target_row as _row

    rows = [_row("kernel supercoil.core.dna.plectoneme.equilibrium, 1000 forces: best wall "
                 "time per force", eq1000 * 1e6, "us", "<= 20 us", eq1000 * 1e6 <= 20)]
    big = hat[(hat["variant"] == "thermal") & (hat["points"] == hat["points"].max())]
    pps = float(big["points_per_second"].iloc[0])
    rows.append(_row(f"kernel supercoil.core.dna.li_zhao.hat_curve_points, "
                     f"{int(big['points'].iloc[0]):.0e} turns values, thermal: points per "
                     "second (best wall time)", pps, "points/s", ">= 1e7 points/s", pps >= 1e7,
                     "equilibrium solved once inside the call"))
    k0 = wp[wp["scene"].str.contains("k = 0") & ~wp["failed"].astype(bool)]
    good = k0[k0["error"] <= 1e-8]
    best = good.loc[good["time"].idxmin()]
    rows.append(_row("rough-rod profile (k = 0, N = 40, 200 points) to 1e-8 rad: best wall "
                     "time of the fastest method", best["time"] * 1e3, "ms", "<= 20 ms",
                     best["time"] <= 0.02, f"fastest method: {best['method']}"))
    ode = good[good["method"] != "closed form"]
    if len(ode):
        b2 = ode.loc[ode["time"].idxmin()]
        rows.append(_row("rough-rod profile (k = 0) to 1e-8 rad by "
                         "supercoil.core.rod.rough.integrate (solve_ivp): best wall time",
                         b2["time"] * 1e3, "ms", "<= 20 ms", b2["time"] <= 0.02,
                         f"{b2['method']} at rtol {b2['tolerance']:.0e}"))
    one = ub[ub["elements"] == 1]
    for name, sub in one.groupby("function", sort=False):
        worst = float(sub["overhead"].max())
        rows.append(_row(f"unit boundary: public {name} minus its kernel, 1 element, best "
                         "wall time", worst, "us", "<= 50 us", worst <= 50))
    return rows


def _headline_table(rows, machine):
    from supercoil.tables import make_table, provenance

    cols = {k: [r[k] for r in rows] for k in ("measurement", "value", "unit", "target", "met",
                                              "note")}
    units = dict.fromkeys(cols, "")
    return make_table(cols, units, provenance(None, machine=machine))


def _charts(wp, hat, ub, out):
    """work_precision.png (three work-precision scenes, hat-curve cost) and unit_boundary.png."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from supercoil.benchmark import unit_boundary, work_precision

    fig, axes = plt.subplots(2, 2, figsize=(12, 9))
    labels = ("max |alpha error| (rad)", "max |alpha error| (rad)",
              "max relative error of alpha and R")
    for ax, (scene, sub), xlabel in zip(axes.flat[:3], wp.groupby("scene", sort=False), labels,
                                        strict=False):
        work_precision.plot(sub, ax, title=scene, error_label=xlabel)
        ax.title.set_fontsize(8)
    ax = axes.flat[3]
    for variant, sub in hat.groupby("variant", sort=False):
        ax.loglog(sub["points"], sub["time_per_point"] * 1e9, "o-", label=variant)
    ax.set(xlabel="turns values per call", ylabel="time per point (ns)",
           title="hat curve (1.2 pN): cost per point")
    ax.title.set_fontsize(8)
    ax.legend()
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "work_precision.png", dpi=110)
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    unit_boundary.plot(ub, ax)
    fig.tight_layout()
    fig.savefig(out / "unit_boundary.png", dpi=110)
    plt.close(fig)


def _headline_step(out, size, log, machine, legacy):
    """Measure the headline targets; write dna_model_cost.csv, headline.csv and headline.md."""
    from supercoil.benchmark import dna_models, headline
    from supercoil.tables import make_table, provenance, write_csv

    res = headline.measure(size=size, log=log)
    write_csv(make_table(res["models"], dna_models.REGIME_UNITS,
                         provenance(None, machine=machine)), out / "dna_model_cost.csv")
    head = _headline_table(headline.target_rows(res) + legacy, machine)
    write_csv(head, out / "headline.csv")
    md = headline.markdown(head, machine, (res["load_start"], res["load_end"]))
    (out / "headline.md").write_text(md)
    log(md)
    return head


class _Sections:
    """Wall and CPU seconds of each section of the run (``bench_sections.csv``)."""

    def __init__(self, log):
        self.log, self.rows = log, []

    @contextlib.contextmanager
    def __call__(self, name):
        self.log(f"{len(self.rows) + 1}/{len(SECTIONS)} {name} ...")
        c0, w0 = time.process_time(), time.perf_counter()
        yield
        wall, cpu = time.perf_counter() - w0, time.process_time() - c0
        self.rows.append((name, wall, cpu))
        self.log(f"    {name}: {wall:.1f} s wall, {cpu:.1f} s CPU")

    def table(self, machine):
        from supercoil.tables import make_table, provenance

        cols = {"section": [r[0] for r in self.rows], "wall": [r[1] for r in self.rows],
                "cpu": [r[2] for r in self.rows]}
        return make_table(cols, {"section": "", "wall": "s", "cpu": "s"},
                          provenance(None, machine=machine))


#: the sections of :func:`run`, in order
SECTIONS = ("rough-rod profile: closed form vs solve_ivp",
            "plectoneme equilibrium: tolerance, vectorised vs scalar loop",
            "hat curve: thermal vs athermal, cost per point", "unit boundary",
            "stability map", "the model family: cost against difference from the reference",
            "screened equilibrium: Newton against the direct solve", "headline targets")


#: the sizes of each run: ``supercoil bench`` ("full"), ``--quick`` and ``--smoke``
#: (the smallest run that still writes and fills every chart and table: the test suite's;
#: its numbers say nothing about speed)
SIZES = {
    "full": {"rod_tolerances": None, "repeat": 3, "eq_forces": 200, "eq_tolerances": None,
             "hat_sizes": (100, 1_000, 10_000, 100_000, 1_000_000), "ub_sizes": None,
             "stability_quick": False, "family_points": 401, "family_repeat": 3,
             "family_fit_budget": None, "screened_forces": 300},
    "quick": {"rod_tolerances": "every third", "repeat": 2, "eq_forces": 50,
              "eq_tolerances": (1e-2, 1e-6, 1e-10, 1e-14), "hat_sizes": (100, 10_000, 1_000_000),
              "ub_sizes": (1, 10_000), "stability_quick": True, "family_points": 101,
              "family_repeat": 1, "family_fit_budget": 0.05, "screened_forces": 100},
    # smoke: three tolerances still span the orders of magnitude of the charts (LSODA fails
    # at 1e-3); the stability map is the whole quick one (the test suite checks it from
    # this run, tests/benchmark/test_stability.py, rather than computing it again); at 21
    # turns values
    # the ensemble's hat curve is cheap enough to pass the quick fit budget, and its fit
    # would be most of the run: the smoke budget is lower (the other constructions, several
    # times cheaper, are still fitted)
    "smoke": {"rod_tolerances": (1e-3, 1e-6, 1e-11), "repeat": 1, "eq_forces": 10,
              "eq_tolerances": (1e-2, 1e-6, 1e-10, 1e-14), "hat_sizes": (100, 10_000),
              "ub_sizes": (1, 100), "stability_quick": True, "family_points": 21,
              "family_repeat": 1, "family_fit_budget": 0.015, "screened_forces": 20},
}


def _sizes(quick, smoke):
    """``(name, sizes)`` of the run: smoke, quick or full (:data:`SIZES`)."""
    size = "smoke" if smoke else "quick" if quick else "full"
    return size, SIZES[size]


def _rod_tolerances(z):
    from supercoil.benchmark import rod

    return {None: rod.TOLERANCES, "every third": rod.TOLERANCES[::3]}.get(
        z["rod_tolerances"], z["rod_tolerances"])


def run(out, quick=False, log=print, smoke=False):
    """Run every benchmark, write charts and tables into ``out``; returns the headline table.

    Each section's wall and CPU seconds are logged and written to ``bench_sections.csv``.
    ``quick`` and ``smoke`` pick the sizes of :data:`SIZES` (``smoke`` wins).
    """
    import supercoil as sc
    from supercoil.benchmark import dna, dna_models, rod, stability, unit_boundary, work_precision
    from supercoil.core.dna import plectoneme as pl
    from supercoil.tables import make_table, provenance, write_csv

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    machine = machine_description()
    size, z = _sizes(quick, smoke)
    log(f"supercoil bench on {machine}" + ("" if size == "full" else f" ({size} sizes)"))
    section = _Sections(log)
    names = iter(SECTIONS)

    with section(next(names)):
        rows = rod.rough_profile_work_precision(tolerances=_rod_tolerances(z),
                                                repeat=z["repeat"])
    with section(next(names)):
        eq_rows = dna.equilibrium_work_precision(n_forces=z["eq_forces"],
                                                 tolerances=z["eq_tolerances"],
                                                 repeat=z["repeat"])
        d = sc.load_parameters("dna").si
        forces = np.linspace(0.2e-12, 10e-12, 1000)
        eq1000 = best_time(lambda: pl.equilibrium(forces, d.bending_rigidity,
                                                  d.torsional_rigidity, d.kT, d.radius),
                           repeat=3) / 1000
    for key in rows:
        rows[key] += eq_rows[key]
    wp = pd.DataFrame(rows)
    wp_table = make_table(rows, {**work_precision.UNITS}, provenance(None, machine=machine))
    write_csv(wp_table, out / "bench_measurements.csv")

    with section(next(names)):
        hat_rows = dna.hat_cost(sizes=z["hat_sizes"])
    hat = make_table(hat_rows, {"variant": "", "points": "", "time": "s", "time_per_point": "s",
                                "points_per_second": "1/s"}, provenance(None, machine=machine))
    write_csv(hat, out / "hat_curve_cost.csv")

    with section(next(names)):
        ub = unit_boundary.run(sizes=z["ub_sizes"] or unit_boundary.SIZES)
    write_csv(ub, out / "unit_boundary.csv")

    _charts(wp, hat, ub, out)

    with section(next(names)):
        smap = stability.run(quick=z["stability_quick"])
    write_csv(smap, out / "stability_map.csv")
    stability.plot(smap, out / "stability_map.png")

    with section(next(names)):
        _family_step(out, z, log, machine)

    with section(next(names)):
        # a ratio of ~20: one sample of 300 forces resolves it (the direct solve is the cost)
        screened = dna_models.screened_equilibrium_cost(n_forces=z["screened_forces"],
                                                        repeat=1)
    write_csv(make_table(screened, dna_models.UNITS, provenance(None, machine=machine)),
              out / "screened_equilibrium_cost.csv")

    with section(next(names)):
        head = _headline_step(out, size, log, machine,
                              _legacy_rows(wp, hat, ub, eq1000) + _screened_rows(screened))
    write_csv(section.table(machine), out / "bench_sections.csv")
    log(f"done in {time.perf_counter() - t_start:.1f} s; outputs in {out}")
    return head


def _family_step(out, z, log, machine):
    """family_precision.csv and .png (quick and smoke skip the fits of the costly hat curves)."""
    from supercoil.benchmark import family
    from supercoil.tables import make_table, provenance, write_csv

    fam = make_table(family.family_precision(turns_points=z["family_points"],
                                             repeat=z["family_repeat"], log=log,
                                             fit_budget=z["family_fit_budget"]),
                     family.UNITS, provenance(None, machine=machine,
                                              reference=family.REFERENCE,
                                              forces_pN=list(family.FORCES)))
    write_csv(fam, out / "family_precision.csv")
    family.plot(fam, out / "family_precision.png")


def _screened_rows(rows):
    """The screened equilibrium's Newton solve against the direct nested solve."""
    from supercoil.benchmark.headline import target_row

    i = rows["model"].index("newton")
    ratio = rows["ratio_to_li_zhao"][i]
    return [target_row(f"kernel supercoil.core.dna.equilibrium.solve_equilibrium (screened), "
                       f"{rows['measurement'][i].split(', ')[1]}: CPU per force, Newton / the "
                       "direct nested solve", ratio, "x", "< 1x", ratio < 1,
                       f"Newton {rows['per_item'][i] * 1e3:.3g} ms per force")]
