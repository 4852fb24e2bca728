"""Validation: do the fit's 1-sigma intervals cover the true parameters 68 % of the time?

Many noise replicates of the same synthetic experiment (DNA with C_t = 95 nm
and r_0 = 2.0 nm, not the seed values; turns offset 0.4 turn; extension
offset 30 nm; 5 nm Gaussian noise; 0.3, 0.5 and 0.7 pN, 110 points per force)
are fitted from the seed set with ``supercoil.fit_many`` (each replicate is a
"molecule"; the fits run on a process pool). For every parameter the script
counts how often ``|estimate - truth| <= stderr``. For a correct covariance
the fraction is 68.3 %; with n replicates its binomial standard deviation is
sqrt(0.683 * 0.317 / n) (3.3 % for n = 200). The acceptance band is
61 to 75 % (about +-2.2 sd at n = 200). Also shown: the pulls
``(estimate - truth) / stderr``, which should be standard normal.

    python examples/validate_fit_coverage.py --out coverage_out [--replicates 400] [--quick]

``--quick`` runs 24 replicates (a smoke test for the suite; its band is wide).
Writes coverage_fits.csv (one row per replicate), coverage_summary.csv and
coverage_pulls.png. Exit status 1 if a coverage falls outside the band.
"""

from __future__ import annotations

import os
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.example_cli import example_arguments, example_parser
from supercoil.tables import make_table, provenance

FORCES = (0.3, 0.5, 0.7)  # pN
P68 = 0.6826894921370859  # P(|Z| <= 1)


def main(argv=None):
    parser = example_parser(__doc__, default_out="results/validate_fit_coverage")
    parser.add_argument("--replicates", type=int, default=400,
                        help="noise replicates (default 400; at least 200 for the validation)")
    parser.add_argument("--jobs", type=int, default=min(4, os.cpu_count() or 1),
                        help="worker processes")
    parser.add_argument("--seed", type=int, default=6)
    args = example_arguments(__doc__, argv, parser=parser)
    n_rep = 24 if args.quick else args.replicates  # --quick: 24 replicates (smoke test)
    out = args.out
    u = sc.ureg

    seed_set = sc.load_parameters("dna")
    true = seed_set.replace(twist_persistence=95 * u.nm, radius=2.0 * u.nm)
    truth = {"twist_persistence": 95.0, "radius": 2.0, "turns_offset": 0.4,
             "extension_offset": 30.0}
    data = simulate_rotation_curves(true, np.array(FORCES) * u.pN, points_per_force=110,
                                    noise=5 * u.nm, molecules=n_rep, turns_offset=0.4,
                                    extension_offset=30 * u.nm, seed=args.seed)
    t0 = time.perf_counter()
    done_marks = set()

    def progress(done, total, molecule):
        step = max(1, total // 10)
        if done % step == 0 or done == total:
            mark = done // step
            if mark not in done_marks:
                done_marks.add(mark)
                print(f"  {done}/{total} replicates fitted", file=sys.stderr)

    vary = ["twist_persistence", "radius"]
    if args.jobs > 1:
        with ProcessPoolExecutor(max_workers=args.jobs) as pool:
            table = sc.fit_many(data, seed_set, vary=vary, executor=pool, progress=progress)
    else:
        table = sc.fit_many(data, seed_set, vary=vary, progress=progress)
    seconds = time.perf_counter() - t0
    ok = table[table["success"]]
    n_ok = len(ok)
    print(f"{n_ok}/{n_rep} replicates fitted in {seconds:.1f} s "
          f"({seconds / n_rep * 1e3:.1f} ms per replicate with {args.jobs} process(es))")

    sd = np.sqrt(P68 * (1 - P68) / max(n_ok, 1))
    lo, hi = (0.61, 0.75) if n_ok >= 200 else (max(0.0, P68 - 3.5 * sd), min(1.0, P68 + 3.5 * sd))
    rows = {"parameter": [], "unit": [], "truth": [], "mean_estimate": [], "mean_stderr": [],
            "scatter_of_estimates": [], "coverage": [], "binomial_sd": [], "band_low": [],
            "band_high": [], "pull_mean": [], "pull_sd": [], "in_band": []}
    pulls = {}
    for name, value in truth.items():
        est, err = ok[name].to_numpy(), ok[f"{name}_stderr"].to_numpy()
        pull = (est - value) / err
        pulls[name] = pull
        cov = float(np.mean(np.abs(pull) <= 1))
        for k, v in (("parameter", name), ("unit", table.attrs["units"][name]),
                     ("truth", value), ("mean_estimate", est.mean()),
                     ("mean_stderr", err.mean()), ("scatter_of_estimates", est.std(ddof=1)),
                     ("coverage", cov), ("binomial_sd", sd), ("band_low", lo),
                     ("band_high", hi), ("pull_mean", pull.mean()),
                     ("pull_sd", pull.std(ddof=1)), ("in_band", bool(lo <= cov <= hi))):
            rows[k].append(v)
    pooled = float(np.mean([np.abs(p) <= 1 for p in pulls.values()]))
    # one unit per row (nm, or turn for turns_offset): in the "unit" column, so that the
    # headers keep the package convention "name [unit]"
    units = {k: "" for k in rows}
    summary = make_table(rows, units, provenance(
        true, replicates=n_rep, fitted=n_ok, noise="5 nm", forces_pN=list(FORCES),
        points_per_force=110, seed=args.seed, pooled_coverage=pooled))
    sc.write_csv(summary, out / "coverage_summary.csv")
    sc.write_csv(table, out / "coverage_fits.csv")

    print(f"\n{'parameter':<20}{'coverage':>10}{'band':>16}{'pull mean':>11}{'pull sd':>9}"
          f"{'mean stderr':>13}{'scatter':>10}")
    for i, name in enumerate(rows["parameter"]):
        print(f"{name:<20}{100 * rows['coverage'][i]:>9.1f}%"
              f"{f'{100 * lo:.1f}-{100 * hi:.1f}%':>16}{rows['pull_mean'][i]:>11.3f}"
              f"{rows['pull_sd'][i]:>9.3f}{rows['mean_stderr'][i]:>13.4g}"
              f"{rows['scatter_of_estimates'][i]:>10.4g}")
    print(f"pooled coverage over the 4 parameters: {100 * pooled:.1f}% "
          f"(expected {100 * P68:.1f}%)")

    fig, axes = plt.subplots(1, len(truth), figsize=(4 * len(truth), 3.4),
                             layout="constrained")
    x = np.linspace(-4, 4, 200)
    for ax, (name, pull), cov in zip(axes, pulls.items(), rows["coverage"], strict=True):
        ax.hist(pull, bins=np.linspace(-4, 4, 33), density=True, alpha=0.6)
        ax.plot(x, np.exp(-x * x / 2) / np.sqrt(2 * np.pi), "k-", lw=1)
        ax.axvspan(-1, 1, color="g", alpha=0.08)
        ax.set_title(f"{name}\ncoverage {100 * cov:.1f}%", fontsize="medium")
        ax.set_xlabel("(estimate - truth) / stderr")
    fig.suptitle(f"pulls of {n_ok} replicate fits (N(0,1) line; shaded: 1-sigma interval)")
    fig.savefig(out / "coverage_pulls.png", dpi=120)
    plt.close(fig)
    print(f"wrote {out / 'coverage_summary.csv'}, {out / 'coverage_fits.csv'}, "
          f"{out / 'coverage_pulls.png'}")
    if not all(rows["in_band"]) or n_ok < n_rep:
        print("coverage outside the band (or failed fits)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
