"""Twist-spinning: beta and pitch versus head tension T' (paper figure fbp).

Rod r = 1.0 mm, L = 56.7 cm, N = 40, silicone rubber E = 4.20 MPa,
G = 1.51 MPa. T' = 0 is the twist-slacking helix (beta = pi/2, [eq ini]).
Stationarity equations derived in supercoil.core.rod.spinning.

    python examples/rod_twist_spinning.py --out OUT [--quick]
"""


import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.example_cli import example_arguments

u = sc.ureg


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/rod_twist_spinning")

    rod = sc.load_parameters("silicone_rubber_rod")
    turns = np.array([20.0, 40.0, 60.0])
    T = np.linspace(0, 2.0, 41 if args.quick else 401) * u.N
    sp = sc.twist_spinning(rod, turns[:, None], T[None, :])
    sc.write_csv(sp.to_table(), args.out / "twist_spinning.csv")

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    for i, N in enumerate(turns):
        ax[0].plot(T.m_as(u.N), np.degrees(sp.beta[i].m_as(u.rad)), label=f"N = {N:g}")
        ax[1].plot(T.m_as(u.N), sp.pitch[i].m_as(u.mm), label=f"N = {N:g}")
    ax[0].set_ylabel("beta [deg]")
    ax[1].set_ylabel("pitch P [mm]")
    for a in ax:
        a.set_xlabel("head tension T' [N]")
        a.legend()
    fig.suptitle("Twist-spinning, r = 1 mm, L = 56.7 cm: T' = 0 is the twist-slacking helix")
    fig.tight_layout()
    fig.savefig(args.out / "twist_spinning.png", dpi=120)
    print("pitch increase at T' = 2 N:", np.round(sp.pitch_increase[:, -1].magnitude, 4))


if __name__ == "__main__":
    main()
