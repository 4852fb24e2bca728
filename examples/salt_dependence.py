"""Salt dependence of the DNA plectoneme with the screened interaction.

Plectoneme radius, tilt, torque, buckling turns and post-buckling slope against force at
10, 50, 150, 500 and 1000 mM monovalent salt for ``interaction="screened"`` (Debye-Hueckel
repulsion of the two strands with Stigter's effective charge and the paper's confinement
term; docs/theory/screened-interaction.md), with the paper's hard-core interaction
(r0 = 1.75 nm) for comparison; and hat curves at 150 mM at 0.5, 1, 2 and 4 pN. Parameter
set ``dna_150mM_nacl`` (A = 50 nm, C = 100 nm, L = 5.03 um), with the salt changed; the
paper's construction (``model="li-zhao"``).

    python examples/salt_dependence.py --out salt_out [--quick]

Writes salt_dependence.csv, salt_dependence.png, salt_constructions_150mM.csv (buckling
turns and slope of every construction that takes an interaction: li-zhao, and free-energy
where it is registered; dotted in the figure), salt_hat_curves_150mM.csv and
salt_hat_curves_150mM.png.
"""

from __future__ import annotations

import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.example_cli import example_arguments
from supercoil.tables import make_table, provenance

SALTS_MM = (10, 50, 150, 500, 1000)
HAT_FORCES_PN = (0.5, 1.0, 2.0, 4.0)
#: the paper's Marko-Siggia hard-core radius (seed set), for the comparison curves
PAPER_R0_NM = 1.75


def _observables(dna, force, interaction):
    """R (nm), tilt (deg), torque (pN nm), N_b (turns), slope (nm/turn) at each force."""
    eq = sc.plectoneme_equilibrium(dna, force, interaction=interaction)
    nb = sc.buckling_turns(dna, force, interaction=interaction)
    slope = sc.post_buckling_slope(dna, force, interaction=interaction)
    return {"radius": eq.radius.m_as("nm"), "tilt": np.degrees(eq.alpha.m_as("rad")),
            "torque": eq.torque.m_as("pN nm"), "buckling_turns": nb.m_as("turn"),
            "slope": slope.m_as("nm/turn")}


def sweep(base, forces_pN):
    """Rows (label, salt, force, observables) for the screened salts and the hard core."""
    u = sc.ureg
    force = forces_pN * u.pN
    runs = [(f"screened {c} mM", c, base.replace(salt=c * u.mM), "screened")
            for c in SALTS_MM]
    runs.append((f"hard core r0 = {PAPER_R0_NM} nm", np.nan,
                 base.replace(radius=PAPER_R0_NM * u.nm), "hard-core"))
    cols = {k: [] for k in ("interaction", "salt", "force", "radius", "tilt", "torque",
                            "buckling_turns", "slope")}
    for label, c, dna, inter in runs:
        obs = _observables(dna, force, inter)
        cols["interaction"] += [label] * forces_pN.size
        cols["salt"] += [c] * forces_pN.size
        cols["force"] += list(forces_pN)
        for k, v in obs.items():
            cols[k] += list(v)
    units = {"interaction": "", "salt": "mM", "force": "pN", "radius": "nm", "tilt": "deg",
             "torque": "pN nm", "buckling_turns": "turn", "slope": "nm/turn"}
    return make_table(cols, units, provenance(base, model="li-zhao",
                                              interactions="screened; hard-core"))


def constructions(base, forces_pN):
    """N_b and slope at 150 mM for every registered model that takes an interaction."""
    force = forces_pN * sc.ureg.pN
    models = [m for m in sc.available_models() if m in ("li-zhao", "free-energy")]
    cols = {"model": [], "force": [], "buckling_turns": [], "slope": []}
    for m in models:
        nb = sc.buckling_turns(base, force, model=m, interaction="screened")
        sl = sc.post_buckling_slope(base, force, model=m, interaction="screened")
        cols["model"] += [m] * forces_pN.size
        cols["force"] += list(forces_pN)
        cols["buckling_turns"] += list(nb.m_as("turn"))
        cols["slope"] += list(sl.m_as("nm/turn"))
    units = {"model": "", "force": "pN", "buckling_turns": "turn", "slope": "nm/turn"}
    return make_table(cols, units, provenance(base, interaction="screened"))


def plot_sweep(df, path, models=None):
    panels = (("radius", "plectoneme radius R [nm]"), ("tilt", "tilt alpha [deg]"),
              ("torque", "torque [pN nm]"), ("buckling_turns", "buckling turns N_b"),
              ("slope", "post-buckling slope dz/dN [nm/turn]"))
    fig, axes = plt.subplots(1, 5, figsize=(22, 4.4), constrained_layout=True)
    for label, g in df.groupby("interaction", sort=False):
        style = "k--" if label.startswith("hard") else "-"
        for ax, (col, ylabel) in zip(axes, panels, strict=True):
            ax.plot(g["force"], g[col], style, label=label)
            ax.set(xlabel="force [pN]", ylabel=ylabel)
            ax.grid(alpha=0.3)
    if models is not None:
        for label, g in models.groupby("model", sort=False):
            if label == "li-zhao":
                continue
            for ax, col in ((axes[3], "buckling_turns"), (axes[4], "slope")):
                ax.plot(g["force"], g[col], ":", color="tab:green", lw=2,
                        label=f"screened 150 mM, {label}")
        axes[4].legend(fontsize=8)
    axes[0].legend(fontsize=8)
    fig.suptitle("Screened interaction against salt (solid) and the paper's hard core "
                 "(dashed); A = 50 nm, C = 100 nm, L = 5.03 um, li-zhao construction "
                 "(dotted: free-energy construction at 150 mM, where registered)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def hat_curves(base, turns):
    u = sc.ureg
    force = np.array(HAT_FORCES_PN) * u.pN
    with warnings.catch_warnings():
        # the model ignores denaturation of negatively supercoiled DNA above 0.8 pN
        warnings.filterwarnings("ignore", message="negative turns", category=sc.ValidityWarning)
        screened = sc.hat_curve(base, force, turns, interaction="screened")
        hard = sc.hat_curve(base.replace(radius=PAPER_R0_NM * u.nm), force, turns)
    return screened, hard


def plot_hats(screened, hard, path):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6), constrained_layout=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for df, style in ((screened, "-"), (hard, "--")):
        for k, (force, g) in enumerate(df.groupby("force", sort=True)):
            label = f"{force:g} pN" + ("" if style == "-" else " (hard core)")
            axes[0].plot(g["turns"], g["extension"], style, color=colors[k], label=label)
            axes[1].plot(g["turns"], g["torque"], style, color=colors[k], label=label)
    axes[0].set(xlabel="turns N", ylabel="extension z [nm]")
    axes[1].set(xlabel="turns N", ylabel="torque [pN nm]")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("Hat curves at 150 mM: screened interaction (solid) and the paper's hard "
                 f"core r0 = {PAPER_R0_NM} nm (dashed), L = 5.03 um")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/salt_dependence")
    out = args.out
    base = sc.load_parameters("dna_150mM_nacl")
    forces = np.linspace(0.5, 5.0, 4 if args.quick else 46)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always", sc.ValidityWarning)
        df = sweep(base, forces)
        models = constructions(base, forces)
    for msg in dict.fromkeys(str(w.message) for w in caught):  # e.g. Q < 1 at 10 mM, 0.5 pN
        print(f"ValidityWarning: {msg}")
    sc.write_csv(df, out / "salt_dependence.csv")
    sc.write_csv(models, out / "salt_constructions_150mM.csv")
    plot_sweep(df, out / "salt_dependence.png", models)

    turns = np.linspace(-250, 250, 51 if args.quick else 1001)
    screened, hard = hat_curves(base, turns)
    sc.write_csv(screened, out / "salt_hat_curves_150mM.csv")
    plot_hats(screened, hard, out / "salt_hat_curves_150mM.png")

    table = _observables(base, np.array(HAT_FORCES_PN) * sc.ureg.pN, "screened")
    print("150 mM, screened, li-zhao construction")
    print(f"{'F [pN]':>7} {'R [nm]':>7} {'tilt [deg]':>10} {'M [pN nm]':>9} {'N_b':>6} "
          f"{'dz/dN [nm/turn]':>15}")
    for i, f in enumerate(HAT_FORCES_PN):
        print(f"{f:7.2f} {table['radius'][i]:7.3f} {table['tilt'][i]:10.2f} "
              f"{table['torque'][i]:9.2f} {table['buckling_turns'][i]:6.1f} "
              f"{table['slope'][i]:15.1f}")
    print(f"wrote {out / 'salt_dependence.png'}, {out / 'salt_dependence.csv'}, "
          f"{out / 'salt_constructions_150mM.csv'}, "
          f"{out / 'salt_hat_curves_150mM.png'}, {out / 'salt_hat_curves_150mM.csv'}")


if __name__ == "__main__":
    main()
