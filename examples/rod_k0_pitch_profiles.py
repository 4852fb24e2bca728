"""Rough rod, Example I (k = 0): pitch profiles, s_max, curvature-error and slip onsets.

Paper figure kzero: (a) r = 1.0 mm, L = 56.7 cm; (b) r = 1.7 mm, L = 142.0 cm.
The paper gives no turns for the curves except N = 40 in (a) and no moduli
for (b): we plot N = 30, 40, 50, 60 for (a) and N = 40, 60, 80 for (b) and use
the silicone rubber values E = 4.20 MPa, G = 1.51 MPa, mu = 0.5 for both.

Writes k0_profiles.csv (all profiles, closed form [eq example k=0]),
k0_summary.csv (per curve: alpha_0, s_max, first s where |e - 1| > 0.15 % and
> 1 %, slip onset, closed form vs ODE difference and timings) and
k0_pitch_profiles.png.

    python examples/rod_k0_pitch_profiles.py --out OUT [--quick]
"""

import time

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import supercoil as sc
from supercoil.example_cli import example_arguments
from supercoil.tables import make_table, provenance

u = sc.ureg
E, G, MU = 4.20 * u.MPa, 1.51 * u.MPa, 0.5  # silicone rubber (paper, Appendix E)
CASES = {
    "a": (sc.ElasticRod(1.0 * u.mm, 56.7 * u.cm, E, G, MU), [30, 40, 50, 60]),
    "b": (sc.ElasticRod(1.7 * u.mm, 142.0 * u.cm, E, G, MU), [40, 60, 80]),
}


def best_time(fn, repeat):
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/rod_k0_pitch_profiles")
    n_points = 201 if args.quick else 801
    repeat = 1 if args.quick else 5

    frames, rows = [], []
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.8))
    for (label, (rod, turns)), ax in zip(CASES.items(), axes, strict=True):
        for N in turns:
            t_cf, cf = best_time(lambda rod=rod, N=N: sc.rough_helix(rod, N, n_points=n_points),
                                 repeat)
            grid = cf.profile["s"].to_numpy() * u.mm
            t_ode, ode = best_time(lambda rod=rod, N=N, grid=grid: sc.rough_helix(
                rod, N, method="ode", s=grid, rtol=1e-10, atol=1e-12), repeat)
            tight = sc.rough_helix(rod, N, n_points=n_points, curvature_tolerance=0.0015)
            smax = cf.s_max.m_as(u.mm)
            e015 = tight.curvature_error_onset.m_as(u.mm)
            e1 = cf.curvature_error_onset.m_as(u.mm)
            slip = cf.slip_onset.m_as(u.mm) if cf.slip_onset is not None else np.nan
            dalpha = float(np.max(np.abs(ode.profile["alpha"] - cf.profile["alpha"])))
            rows.append({
                "case": label, "radius": rod.radius.m_as(u.mm), "length": rod.length.m_as(u.cm),
                "turns": N, "alpha0": cf.alpha0.m_as(u.rad), "s_max": smax,
                "s_max_ode": ode.s_max.m_as(u.mm),
                "s_err_0p15pct": e015, "frac_err_0p15pct": e015 / smax,
                "s_err_1pct": e1, "frac_err_1pct": e1 / smax,
                "slip_onset": slip, "frac_slip_onset": slip / smax,
                "max_dalpha_ode_vs_closed": dalpha,
                "time_closed_form": t_cf, "time_ode": t_ode,
            })
            p = cf.profile.copy()
            p.insert(0, "turns_0", float(N))
            p.insert(0, "case", label)
            frames.append(p)
            line, = ax.plot(p["s"], p["pitch"], label=f"N = {N}")
            ax.axvline(e1, color=line.get_color(), ls=":", lw=0.8)
        r_mm, L_cm = rod.radius.m_as(u.mm), rod.length.m_as(u.cm)
        ax.set_title(f"({label}) r = {r_mm:g} mm, L = {L_cm:g} cm  (dotted: |e-1| > 1 %)")
        ax.set_xlabel("s [mm]")
        ax.set_ylabel("pitch P [mm]")
        ax.set_ylim(0, 60 if label == "a" else 90)
        ax.legend()
    fig.suptitle("Rough rod, k = 0: twist N turns, then slack [eq example k=0]")
    fig.tight_layout()
    fig.savefig(args.out / "k0_pitch_profiles.png", dpi=120)

    profiles = pd.concat(frames, ignore_index=True)
    units = {"case": "", "turns_0": "", **frames[0].attrs["units"]}
    sc.write_csv(make_table({c: profiles[c] for c in profiles.columns}, units,
                            provenance(None, scene="k=0 pitch profiles", E="4.20 MPa",
                                       G="1.51 MPa", mu=MU)),
                 args.out / "k0_profiles.csv")
    summary = pd.DataFrame(rows)
    sunits = {c: "" for c in summary.columns}
    sunits.update({"radius": "mm", "length": "cm", "alpha0": "rad", "s_max": "mm",
                   "s_max_ode": "mm", "s_err_0p15pct": "mm", "s_err_1pct": "mm",
                   "slip_onset": "mm", "max_dalpha_ode_vs_closed": "rad",
                   "time_closed_form": "s", "time_ode": "s"})
    sc.write_csv(make_table({c: summary[c] for c in summary.columns}, sunits,
                            provenance(None, scene="k=0 summary", ode="DOP853 rtol 1e-10 "
                                       "atol 1e-12", n_points=n_points)),
                 args.out / "k0_summary.csv")
    with pd.option_context("display.width", 200, "display.max_columns", 30):
        print(summary.to_string(index=False, float_format=lambda v: f"{v:.6g}"))


if __name__ == "__main__":
    main()
