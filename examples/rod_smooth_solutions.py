"""Smooth rod (Case I): the uniform double helix versus slack at several turns.

Paper figure 2 parameters: r = 1.0 mm, L = 57.0 cm, E = 4.20 MPa, G = 1.51 MPa.
Writes smooth_solutions.csv (one row per (N, S)) and smooth_solutions.png
(tilt, pitch, tension and writhe fraction versus S).

    python examples/rod_smooth_solutions.py --out OUT [--quick]
"""


import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.example_cli import example_arguments

u = sc.ureg


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/rod_smooth_solutions")

    rod = sc.ElasticRod(1.0 * u.mm, 57.0 * u.cm, 4.20 * u.MPa, 1.51 * u.MPa)  # paper fig. 2
    turns = np.array([10.0, 20.0, 40.0, 60.0, 80.0])
    L_mm = rod.length.m_as(u.mm)
    S = np.linspace(0.0, 0.98 * L_mm, 50 if args.quick else 400) * u.mm
    h = sc.smooth_helix(rod, turns[:, None], S[None, :])  # vectorised over N and S

    table = h.to_table()
    sc.write_csv(table, args.out / "smooth_solutions.csv")

    fig, ax = plt.subplots(2, 2, figsize=(10, 7.5), sharex=True)
    for i, N in enumerate(turns):
        x = h.slack[i].m_as(u.cm)
        ax[0, 0].plot(x, np.degrees(h.alpha[i].m_as(u.rad)), label=f"N = {N:g}")
        ax[0, 1].plot(x, h.pitch[i].m_as(u.mm))
        ax[1, 0].plot(x, h.tension[i].m_as(u.N))
        ax[1, 1].plot(x, (h.writhe[i] / h.linking_number[i]).m_as(u.dimensionless))
    ax[0, 0].set_ylabel("tilt alpha [deg]")
    ax[0, 1].set_ylabel("pitch P [mm]")
    ax[1, 0].set_ylabel("tension T [N]")
    ax[1, 1].set_ylabel("Wr / Lk")
    for a in ax[1]:
        a.set_xlabel("slack S [cm]")
    ax[0, 0].legend()
    fig.suptitle("Smooth rod, uniform helix [smooth surface]: r = 1.0 mm, L = 57.0 cm, "
                 "E = 4.20 MPa, G = 1.51 MPa")
    fig.tight_layout()
    fig.savefig(args.out / "smooth_solutions.png", dpi=120)
    print(f"wrote {args.out / 'smooth_solutions.csv'} and smooth_solutions.png")


if __name__ == "__main__":
    main()
