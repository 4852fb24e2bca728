"""The end loop's buckling jump in the marko2007 and free-energy models, at 1-4 pN.

Both models with and without the end loop (docs/theory/end-loop.md): extension and
torque against turns for the seed DNA set (A = 48 nm, C = 86 nm, L = 750 nm, 300 K),
and the extension jump, torque overshoot, loop size and loop free energy at 1, 2, 3
and 4 pN for

* ``marko2007`` (P = 24 nm): the seed set, A = 50 nm, C = 100 nm at the same L and
  temperature (``A50-C100``, the table of docs/theory/end-loop.md#5-size-at-1-4-pn),
  and the bundled set ``dna_150mM_nacl`` (L = 5.03 um);
* ``free-energy``: the seed set with the hard-core interaction and ``dna_150mM_nacl``
  with the screened interaction (docs/theory/end-loop.md#7-free-energy).

    python examples/end_loop_jump.py --out end_loop_out [--quick]

Writes end_loop_jump.csv (one row per model, set and force) and end_loop_jump.png.
"""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.dna.interactions import get_interaction
from supercoil.dna.models.free_energy import FreeEnergy
from supercoil.dna.models.marko2007 import Marko2007
from supercoil.example_cli import example_arguments

FORCES = np.array([1.0, 2.0, 3.0, 4.0])  # pN
UNITS = {"model": "", "set": "", "interaction": "", "force": "pN", "buckling_turns": "turn",
         "jump_turns": "turn", "plectoneme_torque": "pN nm", "torque_overshoot": "pN nm",
         "extension_jump": "nm", "loop_radius": "nm", "loop_length": "nm",
         "loop_excess_free_energy": "pN nm", "loop_excess_free_energy_kT": "",
         "post_buckling_slope": "nm/turn", "jump_over_slope": "turn"}
#: (model, set label, DNA, interaction name or "" for marko2007)
RUNS = (("marko2007", "seed", "seed", ""), ("marko2007", "A50-C100", "A50-C100", ""),
        ("marko2007", "dna_150mM_nacl", "dna_150mM_nacl", ""),
        ("free-energy", "seed", "seed", "hard-core"),
        ("free-energy", "dna_150mM_nacl", "dna_150mM_nacl", "screened"))


def _dna(name):
    if name == "dna_150mM_nacl":
        return sc.load_parameters(name)
    A, C = (48.0, 86.0) if name == "seed" else (50.0, 100.0)
    u = sc.ureg
    return sc.DNA(length=750 * u.nm, bending_persistence=A * u.nm, twist_persistence=C * u.nm,
                  radius=1.75 * u.nm, temperature=300 * u.K)


def _constants(model, dna, interaction):
    """Per-force SI arrays: N_b, N*, M*, dM, dz, l, eps*, slope."""
    si, F = dna.si, FORCES * 1e-12
    if model == "marko2007":
        p = Marko2007(end_loop=True).parameters_at(F, si, True)
        return (p.buckling_turns, p.jump_turns, p.torque, p.torque_overshoot,
                p.extension_jump, p.loop_length, p.loop_excess, p.slope)
    co, lp = FreeEnergy(end_loop=True).loop_constants(F, si, True, get_interaction(interaction))
    return (co.buckling_turns, lp.jump_turns, co.torque, lp.overshoot_torque - co.torque,
            lp.extension_jump, lp.length, lp.excess, co.slope)


def _table():
    rows = {k: [] for k in UNITS}
    for model, label, dname, inter in RUNS:
        dna = _dna(dname)
        Nb, Ns, M, dM, dz, ell, eps, slope = _constants(model, dna, inter)
        n = len(FORCES)
        rows["model"] += [model] * n
        rows["set"] += [label] * n
        rows["interaction"] += [inter or "none (P = 24 nm)"] * n
        rows["force"] += list(FORCES)
        rows["buckling_turns"] += list(Nb)
        rows["jump_turns"] += list(Ns)
        rows["plectoneme_torque"] += list(M * 1e21)
        rows["torque_overshoot"] += list(dM * 1e21)
        rows["extension_jump"] += list(dz * 1e9)
        rows["loop_radius"] += list(ell / (2 * np.pi) * 1e9)
        rows["loop_length"] += list(ell * 1e9)
        rows["loop_excess_free_energy"] += list(eps * 1e21)
        rows["loop_excess_free_energy_kT"] += list(eps / dna.si.kT)
        rows["post_buckling_slope"] += list(slope * 1e9)
        # the jump in units of the extension lost per later turn (Forth et al. 2008: ~2)
        rows["jump_over_slope"] += list(dz / np.abs(slope))
    sets = {"seed": "A = 48 nm, C = 86 nm, L = 750 nm, T = 300 K",
            "A50-C100": "A = 50 nm, C = 100 nm, L = 750 nm, T = 300 K",
            "dna_150mM_nacl": "bundled parameter set dna_150mM_nacl"}
    prov = sc.tables.provenance({"sets": sets},
                                model="marko2007 (end_loop=True, P = 24 nm); "
                                      "free-energy (end_loop=True)")
    return sc.tables.make_table(rows, UNITS, prov)


def _curves(axes, turns):
    dna = _dna("seed")
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    models = ((0, Marko2007(end_loop=True), Marko2007()),
              (1, FreeEnergy(end_loop=True), FreeEnergy()))
    for col, looped, plain in models:
        for model, style in ((looped, "-"), (plain, "--")):
            curves = sc.hat_curve(dna, FORCES * sc.ureg.pN, turns, model=model)
            for k, (f, g) in enumerate(curves.groupby("force", sort=True)):
                label = f"{f:g} pN" + (" end loop" if model.end_loop else " no loop")
                axes[0, col].plot(g["turns"], g["extension"], style, color=colors[k],
                                  label=label)
                axes[1, col].plot(g["turns"], g["torque"], style, color=colors[k])
        axes[0, col].set(xlabel="turns N", ylabel="extension z [nm]",
                         title=f"{looped.name}, seed set (solid: end loop; dashed: none)")
        axes[1, col].set(xlabel="turns N", ylabel="torque [pN nm]")
    axes[0, 0].legend(fontsize=7, ncol=2)


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/end_loop_jump")
    out = args.out
    df = _table()
    sc.write_csv(df, out / "end_loop_jump.csv")
    print(df.drop(columns=["loop_radius", "interaction"]).to_string(index=False,
                                                                   float_format="%.4g"))
    fig, axes = plt.subplots(2, 3, figsize=(16, 8.5), constrained_layout=True)
    _curves(axes, np.linspace(0, 40, 161 if args.quick else 1001))
    markers = {"seed": "o", "A50-C100": "s", "dna_150mM_nacl": "^"}
    for (model, label), g in df.groupby(["model", "set"], sort=False):
        style = ("-" if model == "free-energy" else "--") + markers[label]
        name = f"{model}, {label}" + (f" ({g['interaction'].iloc[0]})"
                                      if model == "free-energy" else "")
        axes[0, 2].plot(g["force"], g["extension_jump"], style, label=name)
        axes[1, 2].plot(g["force"], g["torque_overshoot"], style, label=name)
    axes[0, 2].set(xlabel="force [pN]", ylabel="extension jump at buckling [nm]")
    axes[1, 2].set(xlabel="force [pN]", ylabel="torque overshoot at buckling [pN nm]")
    axes[0, 2].legend(fontsize=7)
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    fig.savefig(out / "end_loop_jump.png", dpi=110)
    plt.close(fig)
    print(f"wrote {out / 'end_loop_jump.png'}, {out / 'end_loop_jump.csv'}")


if __name__ == "__main__":
    main()
