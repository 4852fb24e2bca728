"""Thermodynamic consistency of the two DNA models: li-zhao against free-energy.

Extension and torque at fixed force and turns come from one free energy only
if they satisfy the Maxwell relation dz/dN|_F = -2 pi dM/dF|_N (Mosconi,
Allemand, Bensimon and Croquette, Phys. Rev. Lett. 102, 078301, 2009). This script
measures the ratio (dz/dN) / (-2 pi dM/dF) on the public hat curves of both
models (``sc.hat_curve(..., model=...)``, seed parameters, central differences
with steps 1e-4 turn and 1e-5 F) in each phase: mid-stretched (0.5 N_b), just
before buckling (0.99 N_b) and in the plectoneme phase (N_b + 3 turns), and
compares the
buckling torque, buckling turns and post-buckling slope of the two models
(docs/theory/free-energy.md).

    python examples/thermodynamic_consistency.py --out consistency_out [--quick]

Writes thermodynamic_consistency.csv (one row per force) and
thermodynamic_consistency.png.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.example_cli import example_arguments
from supercoil.tables import make_table, provenance

H_N, H_F = 1e-4, 1e-5  # finite-difference steps: turns, relative force
MODELS = ("li-zhao", "free-energy")
#: test points in turns: fractions of N_b (stretched) and N_b + 3 turns (plectoneme:
#: S <= 165 nm for the seed set over 0.3-10 pN, so the tail stays > 3 persistence lengths)
PHASES = {"stretched_mid": 0.5, "before_buckling": 0.99, "plectoneme": 3.0}
REPORT_FORCES = (0.4, 1.2, 3.0, 5.0)


def _point(dna, model, F, N):
    """(extension [nm], torque [pN nm]) of ``sc.hat_curve`` at one force and turns values."""
    df = sc.hat_curve(dna, F * sc.ureg.pN, N, model=model)
    return df["extension"].to_numpy(), df["torque"].to_numpy()


def maxwell_ratio(dna, model, F, N):
    """``(dz/dN) / (-2 pi dM/dF)`` by central differences of the public hat curve."""
    dz = (_point(dna, model, F, N + H_N)[0] - _point(dna, model, F, N - H_N)[0]) / (2 * H_N)
    dM = (_point(dna, model, F * (1 + H_F), N)[1]
          - _point(dna, model, F * (1 - H_F), N)[1]) / (2 * H_F * F)  # nm
    return dz / (-2 * np.pi * dM)


def measure(dna, forces):
    """One row per force (pN): buckling torque, N_b, slope and Maxwell ratios, both models."""
    cols = {"force": forces}
    for model in MODELS:
        key = model.replace("-", "_")
        nb = sc.buckling_turns(dna, forces * sc.ureg.pN, model=model).magnitude
        cols[f"buckling_turns_{key}"] = nb
        cols[f"slope_{key}"] = sc.post_buckling_slope(dna, forces * sc.ureg.pN,
                                                      model=model).magnitude
        ratios = {p: np.empty(forces.size) for p in PHASES}
        torque = np.empty(forces.size)
        for i, F in enumerate(forces):
            N = np.array([nb[i] * PHASES["stretched_mid"], nb[i] * PHASES["before_buckling"],
                          nb[i] + PHASES["plectoneme"]])
            r = maxwell_ratio(dna, model, F, N)
            for j, p in enumerate(PHASES):
                ratios[p][i] = r[j]
            torque[i] = _point(dna, model, F, N[2:])[1][0]  # the plateau torque
        cols[f"torque_{key}"] = torque
        for p in PHASES:
            cols[f"maxwell_{p}_{key}"] = ratios[p]
    for q in ("torque", "buckling_turns", "slope"):
        cols[f"{q}_relative_difference"] = cols[f"{q}_free_energy"] / cols[f"{q}_li_zhao"] - 1
    units = {c: "" for c in cols}
    units.update(force="pN")
    for key in ("li_zhao", "free_energy"):
        units[f"torque_{key}"] = "pN nm"
        units[f"slope_{key}"] = "nm/turn"
        units[f"buckling_turns_{key}"] = "turn"
    return make_table(cols, units, provenance(
        dna, scene="Maxwell relation dz/dN = -2 pi dM/dF, both models (thermal)",
        steps=f"dN = {H_N} turn, dF = {H_F} F (central differences of sc.hat_curve)",
        points="0.5 N_b, 0.99 N_b, N_b + 3 turns; torque at N_b + 3 turns (plateau)"))


def plot(df, path):
    f = df["force"]
    fig, axes = plt.subplots(2, 2, figsize=(11, 8), constrained_layout=True)
    ax = axes[0, 0]
    styles = {"stretched_mid": ":", "before_buckling": "--", "plectoneme": "-"}
    for key, color in (("li_zhao", "C0"), ("free_energy", "C3")):
        for phase, ls in styles.items():
            ax.plot(f, df[f"maxwell_{phase}_{key}"], ls, color=color,
                    label=f"{key.replace('_', '-')}, {phase.replace('_', ' ')}")
    ax.axhline(1.0, color="k", lw=0.6)
    ax.set(xscale="log", xlabel="force [pN]", ylabel=r"$(dz/dN) / (-2\pi\, dM/dF)$",
           title="Maxwell ratio (1 = one free energy)")
    ax.legend(fontsize=7)
    for ax, q, label in ((axes[0, 1], "torque", "torque at buckling [pN nm]"),
                         (axes[1, 0], "buckling_turns", "buckling turns N_b"),
                         (axes[1, 1], "slope", "post-buckling slope dz/dN [nm/turn]")):
        ax.plot(f, df[f"{q}_li_zhao"], color="C0", label="li-zhao")
        ax.plot(f, df[f"{q}_free_energy"], color="C3", label="free-energy")
        ax.set(xscale="log", xlabel="force [pN]", ylabel=label)
        ax.legend(fontsize=8)
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    fig.suptitle("DNA, L = 750 nm, seed parameters: paper construction (li-zhao) against "
                 "one free energy (free-energy)")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/thermodynamic_consistency")
    out = args.out
    dna = sc.load_parameters("dna")
    grid = np.geomspace(0.3, 10.0, 8 if args.quick else 40)
    forces = np.unique(np.concatenate((grid, REPORT_FORCES)))
    df = measure(dna, forces)
    sc.write_csv(df, out / "thermodynamic_consistency.csv")
    plot(df, out / "thermodynamic_consistency.png")
    rows = df[np.isin(np.round(df["force"], 9), REPORT_FORCES)]
    print(f"{'F':>4} | {'M* [pN nm]':>15} | {'N_b':>13} | {'dz/dN [nm/turn]':>15} | "
          f"{'li-zhao Maxwell ratio':>26} | free-energy")
    print(f"{'pN':>4} | {'LZ':>7} {'FE':>7} | {'LZ':>6} {'FE':>6} | {'LZ':>7} {'FE':>7} | "
          f"{'0.5 Nb':>8} {'0.99 Nb':>8} {'Nb+3':>8} | max |ratio - 1|")
    for _, r in rows.iterrows():
        fe_dev = max(abs(r[f"maxwell_{p}_free_energy"] - 1) for p in PHASES)
        print(f"{r.force:4.1f} | {r.torque_li_zhao:7.3f} {r.torque_free_energy:7.3f} | "
              f"{r.buckling_turns_li_zhao:6.3f} {r.buckling_turns_free_energy:6.3f} | "
              f"{r.slope_li_zhao:7.3f} {r.slope_free_energy:7.3f} | "
              f"{r.maxwell_stretched_mid_li_zhao:8.4f} {r.maxwell_before_buckling_li_zhao:8.4f} "
              f"{r.maxwell_plectoneme_li_zhao:8.4f} | {fe_dev:.1e}")
    for top in (5.0, df.force.max()):
        lz = df.loc[df.force <= top, [f"maxwell_{p}_li_zhao" for p in PHASES]]
        print(f"li-zhao Maxwell ratio over {df.force.min():g}-{top:g} pN: before buckling "
              f"{lz.iloc[:, 1].min():.3f}-{lz.iloc[:, 1].max():.3f}, plectoneme "
              f"{lz.iloc[:, 2].min():.3f}-{lz.iloc[:, 2].max():.3f}")
    print(f"wrote {out / 'thermodynamic_consistency.csv'}, "
          f"{out / 'thermodynamic_consistency.png'}")


if __name__ == "__main__":
    main()
