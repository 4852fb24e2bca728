"""The complete benchmark run behind ``supercoil bench --out DIR``.

Writes into DIR:

* ``work_precision.png``: the four work-precision / cost charts (rough profile
  k = 0 and designed k(S); plectoneme equilibrium; hat-curve cost per point);
* ``unit_boundary.png``: public call against the float kernel it wraps;
* ``stability_map.png``: where each solver fails, is flagged, or is valid;
* ``bench_measurements.csv``: every measured point (table convention);
* ``unit_boundary.csv``, ``stability_map.csv``;
* ``headline.csv`` and ``headline.md``: the headline numbers against the
  issue's targets, with the machine they were measured on.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import pandas as pd

from supercoil.benchmark.timing import best_time, machine_description


def _headline(wp, hat, ub, eq1000, machine):
    rows = []

    def add(name, value, unit, target, met, note=""):
        rows.append({"measurement": name, "value": value, "unit": unit, "target": target,
                     "met": bool(met), "note": note})

    add("plectoneme equilibrium, vectorised over 1000 forces, per force", eq1000 * 1e6, "us",
        "<= 20 us", eq1000 * 1e6 <= 20)
    big = hat[(hat["variant"] == "thermal") & (hat["points"] == hat["points"].max())]
    pps = float(big["points_per_second"].iloc[0])
    add(f"hat curve, {int(big['points'].iloc[0]):.0e} turns values, thermal", pps, "points/s",
        ">= 1e7 points/s", pps >= 1e7, "equilibrium solved once inside the call")
    k0 = wp[wp["scene"].str.contains("k = 0") & ~wp["failed"].astype(bool)]
    good = k0[k0["error"] <= 1e-8]
    best = good.loc[good["time"].idxmin()]
    add("rough profile (k = 0, N = 40, 200 points) to 1e-8 rad", best["time"] * 1e3, "ms",
        "<= 20 ms", best["time"] <= 0.02, f"fastest method: {best['method']}")
    ode = good[good["method"] != "closed form"]
    if len(ode):
        b2 = ode.loc[ode["time"].idxmin()]
        add("rough profile (k = 0) to 1e-8 rad by an ODE solver", b2["time"] * 1e3, "ms",
            "<= 20 ms", b2["time"] <= 0.02,
            f"{b2['method']} at rtol {b2['tolerance']:.0e}")
    one = ub[ub["elements"] == 1]
    for name, sub in one.groupby("function", sort=False):
        worst = float(sub["overhead"].max())
        add(f"unit boundary overhead per call: {name}", worst, "us", "<= 50 us", worst <= 50)
    table = pd.DataFrame(rows)
    table.attrs["units"] = {"measurement": "", "value": "", "unit": "", "target": "",
                            "met": "", "note": ""}
    table.attrs["machine"] = machine
    return table


def _markdown(head):
    lines = ["| measurement | value | target | met |", "|---|---|---|---|"]
    for _, r in head.iterrows():
        v = f"{r['value']:.3g} {r['unit']}"
        note = f" ({r['note']})" if r["note"] else ""
        lines.append(f"| {r['measurement']}{note} | {v} | {r['target']} | "
                     f"{'yes' if r['met'] else 'no'} |")
    lines.append("")
    lines.append(f"Measured on: {head.attrs['machine']}.")
    return "\n".join(lines) + "\n"


def run(out, quick=False, log=print):
    """Run every benchmark, write charts and tables into ``out``; returns the headline table."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    import supercoil as sc
    from supercoil.benchmark import dna, rod, stability, unit_boundary, work_precision
    from supercoil.core.dna import plectoneme as pl
    from supercoil.tables import make_table, provenance, write_csv

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()
    machine = machine_description()
    log(f"supercoil bench on {machine}")

    tols = rod.TOLERANCES[::3] if quick else rod.TOLERANCES
    log("1/5 rough-rod profile: closed form vs solve_ivp ...")
    rows = rod.rough_profile_work_precision(tolerances=tols, repeat=2 if quick else 3)
    log("2/5 plectoneme equilibrium: tolerance, vectorised vs scalar loop ...")
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

    log("3/5 hat curve: thermal vs athermal, cost per point ...")
    hat_rows = dna.hat_cost(sizes=(100, 10_000, 1_000_000) if quick else
                            (100, 1_000, 10_000, 100_000, 1_000_000))
    hat = make_table(hat_rows, {"variant": "", "points": "", "time": "s", "time_per_point": "s",
                                "points_per_second": "1/s"}, provenance(None, machine=machine))
    write_csv(hat, out / "hat_curve_cost.csv")

    log("4/5 unit boundary ...")
    ub = unit_boundary.run(sizes=(1, 100, 10_000) if quick else unit_boundary.SIZES)
    write_csv(ub, out / "unit_boundary.csv")

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

    log("5/5 stability map ...")
    smap = stability.run(quick=quick)
    write_csv(smap, out / "stability_map.csv")
    stability.plot(smap, out / "stability_map.png")

    head = _headline(wp, hat, ub, eq1000, machine)
    write_csv(make_table({c: head[c].tolist() for c in head.columns}, head.attrs["units"],
                         provenance(None, machine=machine)), out / "headline.csv")
    (out / "headline.md").write_text(_markdown(head))
    log(_markdown(head))
    log(f"done in {time.perf_counter() - t_start:.1f} s; outputs in {out}")
    return head
