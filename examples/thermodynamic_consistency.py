"""Thermodynamic consistency of the two DNA models: li-zhao against free-energy.

Extension and torque at fixed force and turns come from one free energy only
if they satisfy the Maxwell relation dz/dN|_F = -2 pi dM/dF|_N (Mosconi,
Allemand and Croquette, Phys. Rev. Lett. 102, 078301, 2009). This script
measures the ratio (dz/dN) / (-2 pi dM/dF) on the hat curves of both models
(seed parameters, central differences with steps 1e-3 turn and 1e-5 F) in
each phase: mid-stretched (0.5 N_b), just before buckling (0.99 N_b) and in
the plectoneme phase (30 % of the way to full coiling), and compares the
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
from supercoil.cli import example_arguments
from supercoil.core import hat_curve as hc
from supercoil.core import plectoneme as pl
from supercoil.core.dna import free_energy as fe
from supercoil.tables import make_table, provenance

H_N, H_F = 1e-3, 1e-5  # finite-difference steps: turns, relative force
PHASES = {"stretched_mid": 0.5, "before_buckling": 0.99, "plectoneme": None}
REPORT_FORCES = (0.4, 1.2, 3.0, 5.0)


class Models:
    """Float-level hat curves and per-force constants of both models (seed set)."""

    def __init__(self, dna):
        d = dna.si
        self.L, self.B, self.C, self.kT, self.r0 = (
            d.length, d.bending_rigidity, d.torsional_rigidity, d.kT, d.radius)

    def eq(self, T):
        return pl.equilibrium(T, self.B, self.C, self.kT, self.r0)

    def points(self, model, N, F):
        N, F = np.broadcast_arrays(np.asarray(N, float), np.asarray(F, float))
        if model == "li-zhao":
            return hc.hat_curve_points(N, F, self.L, self.B, self.C, self.kT, self.r0)
        return fe.hat_points(N, F, self.L, self.B, self.C, self.kT, self.eq)

    def constants(self, model, F):
        """(torque at buckling, N_b, slope, linking rate D) at the forces F."""
        if model == "li-zhao":
            p = hc.hat_parameters(F, self.L, self.B, self.C, self.kT, self.r0)
        else:
            p = fe.coexistence(F, self.L, self.B, self.C, self.kT, self.eq)
        return p.torque, p.buckling_turns, p.slope, p.linking_rate

    def maxwell_ratio(self, model, N, F):
        dz = (self.points(model, N + H_N, F).extension
              - self.points(model, N - H_N, F).extension) / (2 * H_N)
        dM = (self.points(model, N, F * (1 + H_F)).torque
              - self.points(model, N, F * (1 - H_F)).torque) / (2 * H_F * F)
        return dz / (-2 * np.pi * dM)


def measure(models, forces):
    cols = {"force": forces * 1e12}
    for model in ("li-zhao", "free-energy"):
        key = model.replace("-", "_")
        M, Nb, slope, D = models.constants(model, forces)
        cols[f"torque_{key}"] = M * 1e21
        cols[f"buckling_turns_{key}"] = Nb
        cols[f"slope_{key}"] = slope * 1e9
        for phase, frac in PHASES.items():
            N = Nb * frac if frac is not None else Nb + 0.3 * models.L * D / (2 * np.pi)
            cols[f"maxwell_{phase}_{key}"] = models.maxwell_ratio(model, N, forces)
    for q in ("torque", "buckling_turns", "slope"):
        cols[f"{q}_relative_difference"] = cols[f"{q}_free_energy"] / cols[f"{q}_li_zhao"] - 1
    units = {c: "" for c in cols}
    units.update(force="pN")
    for key in ("li_zhao", "free_energy"):
        units[f"torque_{key}"] = "pN nm"
        units[f"slope_{key}"] = "nm/turn"
        units[f"buckling_turns_{key}"] = "turn"
    return make_table(cols, units, provenance(
        sc.load_parameters("dna"), scene="Maxwell relation dz/dN = -2 pi dM/dF, both models",
        steps=f"dN = {H_N} turn, dF = {H_F} F (central differences)",
        plectoneme_point="N_b + 0.3 (N_full - N_b)"))


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
    models = Models(sc.load_parameters("dna"))
    grid = np.geomspace(0.3, 10.0, 8 if args.quick else 40)
    forces = np.unique(np.concatenate((grid, REPORT_FORCES))) * 1e-12
    df = measure(models, forces)
    sc.write_csv(df, out / "thermodynamic_consistency.csv")
    plot(df, out / "thermodynamic_consistency.png")
    rows = df[np.isin(np.round(df["force"], 9), REPORT_FORCES)]
    print(f"{'F':>4} | {'M* [pN nm]':>15} | {'N_b':>13} | {'dz/dN [nm/turn]':>15} | "
          f"{'li-zhao Maxwell ratio':>28} | free-energy |ratio - 1|")
    print(f"{'pN':>4} | {'LZ':>7} {'FE':>7} | {'LZ':>6} {'FE':>6} | {'LZ':>7} {'FE':>7} | "
          f"{'0.5 Nb':>8} {'0.99 Nb':>8} {'plect.':>8} |")
    for _, r in rows.iterrows():
        fe_dev = max(abs(r[f"maxwell_{p}_free_energy"] - 1) for p in PHASES)
        print(f"{r.force:4.1f} | {r.torque_li_zhao:7.3f} {r.torque_free_energy:7.3f} | "
              f"{r.buckling_turns_li_zhao:6.3f} {r.buckling_turns_free_energy:6.3f} | "
              f"{r.slope_li_zhao:7.3f} {r.slope_free_energy:7.3f} | "
              f"{r.maxwell_stretched_mid_li_zhao:8.4f} {r.maxwell_before_buckling_li_zhao:8.4f} "
              f"{r.maxwell_plectoneme_li_zhao:8.4f} | {fe_dev:.1e}")
    print(f"wrote {out / 'thermodynamic_consistency.csv'}, "
          f"{out / 'thermodynamic_consistency.png'}")


if __name__ == "__main__":
    main()
