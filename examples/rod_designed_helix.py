"""Example II: the twisting schedule for a sinusoidal pitch, and its round trip.

Paper figure sin: P(s) = P0 + P1 sin(k s), P0 = 16 mm, P1 = 4 mm (the caption's
"cm" is a typo), k = 2 pi / (10 P0), rod r = 1.0 mm, L = 57 cm, silicone rubber
E = 4.20 MPa, G = 1.51 MPa, mu = 0.5. Panels: N versus S, T versus N, and the
pitch profile (designed, and recovered by running the schedule forward through
rough_helix's ODE).

    python examples/rod_designed_helix.py --out OUT [--quick]
"""


import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.example_cli import example_arguments
from supercoil.rod.design import sinusoidal_pitch

u = sc.ureg


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/rod_designed_helix")

    rod = sc.ElasticRod(1.0 * u.mm, 57 * u.cm, 4.20 * u.MPa, 1.51 * u.MPa, 0.5)
    P0 = 16 * u.mm
    pitch = sinusoidal_pitch(P0, 4 * u.mm, 2 * np.pi / (10 * P0))
    sched = sc.design_twist_schedule(rod, pitch, slack_max=50 * u.cm,
                                     n_points=501 if args.quick else 2001)
    sc.write_csv(sched, args.out / "designed_schedule.csv")

    grid = sched["s"].to_numpy() * u.mm
    back = sc.rough_helix(rod, sched["turns"].iloc[0], twist_rate=sched, s=grid,
                          rtol=1e-8, atol=1e-10)
    err = np.max(np.abs(back.profile["pitch"] / sched["pitch"] - 1))
    sc.write_csv(back.profile, args.out / "designed_forward_profile.csv")

    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    ax[0].plot(sched["slack"] / 10, sched["turns"])
    ax[0].set_xlabel("slack S [cm]")
    ax[0].set_ylabel("turns N")
    ax[0].set_title("(a) schedule N(S)")
    ax[1].plot(sched["turns"], sched["tension"])
    ax[1].set_xlabel("turns N")
    ax[1].set_ylabel("tension T [N]")
    ax[1].set_title("(b) T versus N")
    ax[2].plot(sched["s"], sched["pitch"], label="designed P(s)")
    ax[2].plot(back.profile["s"], back.profile["pitch"], "--",
               label=f"forward ODE (max rel. diff {err:.1e})")
    ax[2].set_xlabel("s [mm]")
    ax[2].set_ylabel("pitch P [mm]")
    ax[2].set_title("(c) pitch profile")
    ax[2].legend()
    fig.suptitle("Designed helix P = 16 mm + 4 mm sin(2 pi s / 160 mm): r = 1 mm, L = 57 cm")
    fig.tight_layout()
    fig.savefig(args.out / "designed_helix.png", dpi=120)
    print(f"N0 = {sched['turns'].iloc[0]:.4f}, N(S_end) = {sched['turns'].iloc[-1]:.4f}, "
          f"round-trip max relative pitch difference {err:.2e}")


if __name__ == "__main__":
    main()
