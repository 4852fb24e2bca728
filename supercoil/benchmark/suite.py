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
* ``headline.csv`` and ``headline.md``: one row per speed or memory target
  (:mod:`supercoil.benchmark.headline`: what is timed, value, unit, target,
  met, note), with the machine and its load average.
"""

from __future__ import annotations

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


def _headline_step(out, quick, log, machine, legacy):
    """Measure the headline targets; write dna_model_cost.csv, headline.csv and headline.md."""
    from supercoil.benchmark import dna_models, headline
    from supercoil.tables import make_table, provenance, write_csv

    res = headline.measure(quick=quick, log=log)
    write_csv(make_table(res["models"], dna_models.UNITS, provenance(None, machine=machine)),
              out / "dna_model_cost.csv")
    head = _headline_table(headline.target_rows(res) + legacy, machine)
    write_csv(head, out / "headline.csv")
    md = headline.markdown(head, machine, (res["load_start"], res["load_end"]))
    (out / "headline.md").write_text(md)
    log(md)
    return head


def run(out, quick=False, log=print):
    """Run every benchmark, write charts and tables into ``out``; returns the headline table."""
    import supercoil as sc
    from supercoil.benchmark import dna, family, rod, stability, unit_boundary, work_precision
    from supercoil.core.dna import plectoneme as pl
    from supercoil.tables import make_table, provenance, write_csv

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    machine = machine_description()
    log(f"supercoil bench on {machine}")

    tols = rod.TOLERANCES[::3] if quick else rod.TOLERANCES
    log("1/7 rough-rod profile: closed form vs solve_ivp ...")
    rows = rod.rough_profile_work_precision(tolerances=tols, repeat=2 if quick else 3)
    log("2/7 plectoneme equilibrium: tolerance, vectorised vs scalar loop ...")
    eq_rows = dna.equilibrium_work_precision(n_forces=50 if quick else 200,
                                             tolerances=[1e-2, 1e-6, 1e-10, 1e-14] if quick
                                             else None, repeat=2 if quick else 3)
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

    log("3/7 hat curve: thermal vs athermal, cost per point ...")
    hat_rows = dna.hat_cost(sizes=(100, 10_000, 1_000_000) if quick else
                            (100, 1_000, 10_000, 100_000, 1_000_000))
    hat = make_table(hat_rows, {"variant": "", "points": "", "time": "s", "time_per_point": "s",
                                "points_per_second": "1/s"}, provenance(None, machine=machine))
    write_csv(hat, out / "hat_curve_cost.csv")

    log("4/7 unit boundary ...")
    ub = unit_boundary.run(sizes=(1, 10_000) if quick else unit_boundary.SIZES)
    write_csv(ub, out / "unit_boundary.csv")

    _charts(wp, hat, ub, out)

    log("5/7 stability map ...")
    smap = stability.run(quick=quick)
    write_csv(smap, out / "stability_map.csv")
    stability.plot(smap, out / "stability_map.png")

    log("6/7 the model family: cost against difference from the reference ...")
    fam = make_table(family.family_precision(turns_points=101 if quick else 401,
                                             repeat=1 if quick else 3, log=log),
                     family.UNITS, provenance(None, machine=machine, reference=family.REFERENCE,
                                              forces_pN=list(family.FORCES)))
    write_csv(fam, out / "family_precision.csv")
    family.plot(fam, out / "family_precision.png")

    log("7/7 headline targets ...")
    head = _headline_step(out, quick, log, machine, _legacy_rows(wp, hat, ub, eq1000))
    log(f"done in {time.perf_counter() - t_start:.1f} s; outputs in {out}")
    return head
