"""The paper's DNA figure: hat curves of a 750 nm DNA at 0.4, 1.2 and 3.0 pN.

Example III of Li, Zhao et al. (docs/theory/li-zhao.md): extension versus the
supercoiling degree eta = 2 pi N xi_T / L and versus turns N, and torque
versus N, for the seed parameter set. Solid lines: with the Moroz-Nelson
thermal corrections; dashed: the athermal variant (C_eff = C, zeta = 1; the
paper's figure ignores thermal fluctuations). Dotted parts: tails shorter than
3 bending persistence lengths, where zeta is not valid (flagged, not smoothed).

    python examples/hat_curves_fixed_forces.py --out hat_out [--quick]

Writes hat_curves_thermal.csv, hat_curves_athermal.csv and hat_curves.png.
"""

from __future__ import annotations

import warnings

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.dna.hat import buckling_turns, post_buckling_slope
from supercoil.example_cli import example_arguments


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/hat_curves_fixed_forces")
    out = args.out

    u = sc.ureg
    dna = sc.load_parameters("dna")
    forces = np.array([0.4, 1.2, 3.0]) * u.pN
    turns = np.linspace(-40, 40, 161 if args.quick else 1601)

    tables = {}
    with warnings.catch_warnings():
        # the model ignores denaturation of negatively supercoiled DNA above 0.8 pN
        warnings.filterwarnings("ignore", message="negative turns", category=sc.ValidityWarning)
        for thermal in (True, False):
            tables[thermal] = sc.hat_curve(dna, forces, turns, thermal=thermal)
    sc.write_csv(tables[True], out / "hat_curves_thermal.csv")
    sc.write_csv(tables[False], out / "hat_curves_athermal.csv")

    eq = sc.plectoneme_equilibrium(dna, forces)
    nb = buckling_turns(dna, forces)
    slope = post_buckling_slope(dna, forces)
    print(f"{'F [pN]':>7} {'R [nm]':>7} {'alpha [deg]':>11} {'P [nm]':>7} "
          f"{'M [pN nm]':>9} {'N_b':>6} {'dz/dN [nm]':>10}")
    for i, f in enumerate(forces.magnitude):
        print(f"{f:7.2f} {eq.radius.magnitude[i]:7.3f} {np.degrees(eq.alpha.magnitude[i]):11.3f} "
              f"{eq.pitch.magnitude[i]:7.2f} {eq.torque.magnitude[i]:9.3f} "
              f"{nb.magnitude[i]:6.3f} {slope.magnitude[i]:10.3f}")

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6), constrained_layout=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    panels = (("eta", "extension"), ("turns", "extension"), ("turns", "torque"))
    for thermal, style in ((True, "-"), (False, "--")):
        df = tables[thermal]
        for k, (force, g) in enumerate(df.groupby("force", sort=True)):
            long_tail = ~g["short_tail"].to_numpy()
            for ax, (x, y) in zip(axes, panels, strict=True):
                xs, ys = g[x].to_numpy(), g[y].to_numpy()
                label = f"{force:g} pN" + ("" if thermal else " (athermal)")
                ax.plot(xs, np.where(long_tail | (not thermal), ys, np.nan), style,
                        color=colors[k], label=label)
                if thermal:
                    ax.plot(xs, np.where(long_tail, np.nan, ys), ":", color=colors[k])
    axes[0].set(xlabel=r"$\eta = 2\pi N \xi_T / L$", ylabel="extension z [nm]")
    axes[1].set(xlabel="turns N", ylabel="extension z [nm]")
    axes[2].set(xlabel="turns N", ylabel="torque [pN nm]")
    for ax in axes:
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8)
    fig.suptitle("DNA hat curves, L = 750 nm (solid: Moroz-Nelson tail; dashed: athermal; "
                 "dotted: tail < 3 persistence lengths)")
    fig.savefig(out / "hat_curves.png", dpi=120)
    plt.close(fig)
    print(f"wrote {out / 'hat_curves.png'}, {out / 'hat_curves_thermal.csv'}, "
          f"{out / 'hat_curves_athermal.csv'}")


if __name__ == "__main__":
    main()
