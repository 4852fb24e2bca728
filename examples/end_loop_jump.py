"""The end loop's buckling jump in Marko's two-phase model, at 1-4 pN.

``model="marko2007"`` with and without the end loop (docs/theory/end-loop.md):
extension and torque against turns for the seed DNA set (A = 48 nm,
C = 86 nm, L = 750 nm, 300 K) with P = 24 nm, and the extension jump, torque
overshoot, loop size and loop free energy at 1, 2, 3 and 4 pN for the seed set
and for A = 50 nm, C = 100 nm, P = 24 nm (same L and temperature).

    python examples/end_loop_jump.py --out end_loop_out [--quick]

Writes end_loop_jump.csv (one row per set and force) and end_loop_jump.png.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.cli import example_arguments
from supercoil.dna.models.marko2007 import Marko2007

SETS = {"seed": (48.0, 86.0), "A50-C100": (50.0, 100.0)}  # A, C in nm; P = 24 nm both
FORCES = np.array([1.0, 2.0, 3.0, 4.0])  # pN
UNITS = {"set": "", "force": "pN", "buckling_turns": "turn", "jump_turns": "turn",
         "plectoneme_torque": "pN nm", "torque_overshoot": "pN nm", "extension_jump": "nm",
         "loop_radius": "nm", "loop_length": "nm", "loop_excess_free_energy": "pN nm",
         "loop_excess_free_energy_kT": "", "post_buckling_slope": "nm/turn",
         "jump_over_slope": "turn"}


def _dna(A, C):
    u = sc.ureg
    return sc.DNA(length=750 * u.nm, bending_persistence=A * u.nm, twist_persistence=C * u.nm,
                  radius=1.75 * u.nm, temperature=300 * u.K)


def _table():
    rows = {k: [] for k in UNITS}
    looped = Marko2007(end_loop=True)
    for name, (A, C) in SETS.items():
        si = _dna(A, C).si
        p = looped.parameters_at(FORCES * 1e-12, si, True)
        rows["set"] += [name] * len(FORCES)
        rows["force"] += list(FORCES)
        rows["buckling_turns"] += list(p.buckling_turns)
        rows["jump_turns"] += list(p.jump_turns)
        rows["plectoneme_torque"] += list(p.torque * 1e21)
        rows["torque_overshoot"] += list(p.torque_overshoot * 1e21)
        rows["extension_jump"] += list(p.extension_jump * 1e9)
        rows["loop_radius"] += list(p.loop_length / (2 * np.pi) * 1e9)
        rows["loop_length"] += list(p.loop_length * 1e9)
        rows["loop_excess_free_energy"] += list(p.loop_excess * 1e21)
        rows["loop_excess_free_energy_kT"] += list(p.loop_excess / si.kT)
        rows["post_buckling_slope"] += list(p.slope * 1e9)
        # the jump in units of the extension lost per later turn (Forth et al. 2008: ~2)
        rows["jump_over_slope"] += list(p.extension_jump / np.abs(p.slope))
    prov = sc.tables.provenance({"sets": {k: f"A = {a} nm, C = {c} nm, P = 24 nm, L = 750 nm, "
                                          "T = 300 K" for k, (a, c) in SETS.items()}},
                                model="marko2007 (end_loop=True)")
    return sc.tables.make_table(rows, UNITS, prov)


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/end_loop_jump")
    out = args.out
    df = _table()
    sc.write_csv(df, out / "end_loop_jump.csv")
    print(df.drop(columns=["loop_radius"]).to_string(index=False, float_format="%.4g"))

    dna = _dna(*SETS["seed"])
    turns = np.linspace(0, 40, 161 if args.quick else 2001)
    fig, axes = plt.subplots(2, 2, figsize=(12, 8.5), constrained_layout=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for model, style in ((Marko2007(end_loop=True), "-"), (Marko2007(), "--")):
        curves = sc.hat_curve(dna, FORCES * sc.ureg.pN, turns, model=model)
        for k, (f, g) in enumerate(curves.groupby("force", sort=True)):
            label = f"{f:g} pN" + (" end loop" if model.end_loop else " no loop")
            axes[0, 0].plot(g["turns"], g["extension"], style, color=colors[k], label=label)
            axes[0, 1].plot(g["turns"], g["torque"], style, color=colors[k])
    for name, marker in (("seed", "o"), ("A50-C100", "s")):
        g = df[df["set"] == name]
        axes[1, 0].plot(g["force"], g["extension_jump"], marker + "-", label=name)
        axes[1, 1].plot(g["force"], g["torque_overshoot"], marker + "-", label=name)
    axes[0, 0].set(xlabel="turns N", ylabel="extension z [nm]",
                   title="seed set, P = 24 nm (solid: end loop; dashed: Marko 2007 alone)")
    axes[0, 1].set(xlabel="turns N", ylabel="torque [pN nm]")
    axes[1, 0].set(xlabel="force [pN]", ylabel="extension jump at buckling [nm]")
    axes[1, 1].set(xlabel="force [pN]", ylabel="torque overshoot at buckling [pN nm]")
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=7, ncol=2)
    axes[1, 0].legend()
    fig.savefig(out / "end_loop_jump.png", dpi=120)
    plt.close(fig)
    print(f"wrote {out / 'end_loop_jump.png'}, {out / 'end_loop_jump.csv'}")


if __name__ == "__main__":
    main()
