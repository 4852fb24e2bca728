"""Fit hat curves to (synthetic) magnetic-tweezers rotation curves and recover the parameters.

Noisy data are generated from known parameters that are *not* the seed set
(twist persistence C_t = 95 nm instead of 86 nm, hard-core radius r_0 = 2.0 nm
instead of 1.75 nm), with a turns offset of 0.4 turn (the true zero of
rotation) and an extension offset of 30 nm (the bead-height reference), and
5 nm Gaussian noise, at 0.3, 0.5 and 0.7 pN (below the 0.8 pN where negative
supercoiling denatures real DNA), 110 points per force, fixed seed. The data
are written as CSV, read back with ``supercoil.read_tweezers_csv``, and fitted
with ``supercoil.fit_hat_curves`` starting from the seed set; the script
prints the fit report, the truth against the estimates (in units of the
reported standard errors) and the fit time, then fits four molecules
separately with ``supercoil.fit_many`` on a process pool, fits extension and
torque jointly (a ``torque [pN nm]`` column, 2 pN nm noise) against the
extensions alone, and compares the registered models.

    python examples/fit_tweezers_data.py --out fit_out [--quick]

Writes tweezers_data.csv, tweezers_many.csv, tweezers_torque.csv,
fit_report.txt, fit_parameters.csv, fit_points.csv, fit_molecules.csv,
fit_torque_report.txt, fit_torque_points.csv, fit_comparison.csv, fit.png,
fit_profile.png (the profile likelihood of the radius), fit_torque.png and
fit_comparison.png.
"""

from __future__ import annotations

import time
from concurrent.futures import ProcessPoolExecutor

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.dna.fitting.result import fmt_pm
from supercoil.example_cli import example_arguments

FORCES = (0.3, 0.5, 0.7)  # pN


def joint_torque_fit(true, seed_set, out, vary):
    """Extension and torque (magnetic torque tweezers) fitted jointly, against extension only."""
    u = sc.ureg
    data = simulate_rotation_curves(true, np.array(FORCES) * u.pN, points_per_force=110,
                                    noise=5 * u.nm, turns_offset=0.4, extension_offset=30 * u.nm,
                                    torque_noise=2 * u.pN * u.nm, seed=20261122)
    data = sc.read_tweezers_csv(sc.write_csv(data, out / "tweezers_torque.csv"))
    joint = sc.fit_hat_curves(data, seed_set, vary=vary)
    ext = sc.fit_hat_curves(data.drop(columns=["torque"]), seed_set, vary=vary)
    ch = joint.channels
    print("\njoint extension + torque fit (5 nm and 2 pN nm noise, estimated per channel: "
          f"{ch['extension']['noise'].m_as('nm'):.3g} nm, "
          f"{ch['torque']['noise'].m_as('pN*nm'):.3g} pN nm)")
    for name in vary:
        print(f"  {name:<20} joint {fmt_pm(joint.parameters[name].m, joint.stderr[name].m)}  "
              f"extension only {fmt_pm(ext.parameters[name].m, ext.stderr[name].m)} "
              f"{joint.units[name]}")
    (out / "fit_torque_report.txt").write_text(joint.report() + "\n")
    sc.write_csv(joint.points_frame(), out / "fit_torque_points.csv")
    fig = joint.plot()
    fig.savefig(out / "fit_torque.png", dpi=100)
    plt.close(fig)


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/fit_tweezers_data")
    out = args.out
    u = sc.ureg

    seed_set = sc.load_parameters("dna")
    true = seed_set.replace(twist_persistence=95 * u.nm, radius=2.0 * u.nm)
    truth = {"twist_persistence": 95 * u.nm, "radius": 2.0 * u.nm,
             "turns_offset": 0.4 * u.turn, "extension_offset": 30 * u.nm}

    # ---- synthetic data -> CSV -> back ----------------------------------------------------
    data = simulate_rotation_curves(true, np.array(FORCES) * u.pN, points_per_force=110,
                                    noise=5 * u.nm, turns_offset=0.4, extension_offset=30 * u.nm,
                                    seed=20261121)
    csv = sc.write_csv(data, out / "tweezers_data.csv")
    data = sc.read_tweezers_csv(csv)
    print(f"wrote and read back {csv}: {len(data)} points at {', '.join(map(str, FORCES))} pN")

    # ---- global fit ---------------------------------------------------------------------------
    vary = ["twist_persistence", "radius"]
    result = sc.fit_hat_curves(data, seed_set, vary=vary)
    repeats = 3 if args.quick else 20
    t0 = time.perf_counter()
    for _ in range(repeats):
        sc.fit_hat_curves(data, seed_set, vary=vary)
    seconds = (time.perf_counter() - t0) / repeats
    report = result.report()
    print(report)
    print(f"\nfit time: {seconds * 1e3:.1f} ms per fit ({len(data)} points, {len(FORCES)} forces, "
          f"{len(vary)} physical parameters + 2 offsets; mean of {repeats})")
    print(f"noise estimate (residual RMS): {result.residual_rms.m_as('nm'):.3g} nm "
          "(true noise 5 nm)")
    print(f"\n{'parameter':<20}{'true':>10}{'fit':>12}{'stderr':>10}{'(fit-true)/stderr':>20}")
    for name, q in truth.items():
        est, err = result.parameters[name], result.stderr[name]
        t = q.m_as(est.units)
        print(f"{name:<20}{t:>10.4g}{est.m:>12.5g}{err.m:>10.2g}{(est.m - t) / err.m:>20.2f}")
    (out / "fit_report.txt").write_text(report + f"\n\nfit time: {seconds * 1e3:.1f} ms\n")
    sc.write_csv(result.to_frame(), out / "fit_parameters.csv")
    sc.write_csv(result.points_frame(), out / "fit_points.csv")
    plt.close(result.plot(path=out / "fit.png", dpi=120))
    profile = result.profile("radius")  # the other parameters refitted at each radius
    plt.close(profile.plot(path=out / "fit_profile.png", dpi=120))
    print(f"radius: 68 % profile-likelihood interval {profile.lower_bound:.4g} to "
          f"{profile.upper_bound:.4g} nm (Jacobian: {result.parameters['radius'].m:.4g} "
          f"± {result.stderr['radius'].m:.2g} nm)")

    # ---- four molecules, fitted separately on a process pool -----------------------------------
    many = simulate_rotation_curves(true, np.array(FORCES) * u.pN, points_per_force=110,
                                    noise=5 * u.nm, molecules=4,
                                    turns_offset=[0.4, -0.2, 0.6, 0.0],
                                    extension_offset=[30, 10, -15, 0] * u.nm, seed=7)
    sc.write_csv(many, out / "tweezers_many.csv")
    with ProcessPoolExecutor(max_workers=2) as pool:
        table = sc.fit_many(many, seed_set, vary=vary, executor=pool,
                            progress=lambda done, total, mol: print(
                                f"  molecule {mol} done ({done}/{total})"))
    sc.write_csv(table, out / "fit_molecules.csv")
    # unit weights: the noise estimate is the residual RMS (nm; the reduced chi-square is 1
    # by construction). `determined` is False where the data leave a parameter free.
    shown = table[["molecule", "success", "determined", "twist_persistence",
                   "twist_persistence_stderr", "radius", "radius_stderr", "turns_offset"]].copy()
    shown["noise_estimate_nm"] = table["residual_rms"]
    print(shown.to_string(index=False))
    joint_torque_fit(true, seed_set, out, vary)
    # ---- model comparison: every registered model fitted to the same data -----------------
    import warnings

    from supercoil.dna.fitting.plot import plot_comparison
    from supercoil.dna.models import get_model

    with warnings.catch_warnings():  # wrong models warn (runs test, limits): the table says it
        warnings.simplefilter("ignore")
        # --quick: the closed-form and one-solve models (an "ensemble" fit costs ~100x one).
        # Each model fits C_t, r_0 and its own parameters, except the ensemble: its
        # parameters describe measured real DNA (melting, domains, twist-bend softening),
        # which these synthetic li-zhao curves do not contain, so they stay at its defaults
        # (and it has no superhelix radius: C_t only)
        models = (["li-zhao", "free-energy", "marko2007"] if args.quick
                  else sc.available_models())
        per_model = {m: ["twist_persistence"] if m == "ensemble"
                     else [*vary, *get_model(m).parameters] for m in models}
        result = sc.compare_models(data, seed_set, models, vary=per_model)
    comparison, fits = result.table, result.results
    print("\nmodel comparison (lmfit's AIC and BIC; the data were made by li-zhao):")
    print(comparison[["model", "nparams", "chi_square", "aic", "delta_aic", "delta_bic",
                      "goodness_p", "cpu_seconds", "curve_cpu_seconds"]].to_string(index=False))
    sc.write_csv(comparison, out / "fit_comparison.csv")
    fig = plot_comparison(fits)
    fig.savefig(out / "fit_comparison.png", dpi=120)
    plt.close(fig)
    print(f"wrote {out / 'fit.png'}, {out / 'fit_report.txt'}, {out / 'fit_parameters.csv'}, "
          f"{out / 'fit_molecules.csv'}, {out / 'fit_comparison.csv'}, "
          f"{out / 'fit_comparison.png'}")


if __name__ == "__main__":
    main()
