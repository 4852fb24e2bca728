"""Tension and twist moment at the fixed end while a twisted rod is slacked.

Paper figure tt: r = 1 mm, L = 1.01 m, N = 80 (no moduli given there: we use
the silicone rubber values E = 4.20 MPa, G = 1.51 MPa, mu = 0.5). Rough rod,
k = 0: tension [eq tension] and torque ``C omega(S/2)`` versus slack S; the
smooth-rod (Case I) prediction at the same (N, S) is drawn for comparison.
The model has no loop at the head, so the measured drop of T at S ~ 1 cm
(buckling) is not in it (docs/theory/limits.md#not-modelled).

    python examples/rod_tension_torque_slacking.py --out OUT [--quick]
"""


import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import supercoil as sc
from supercoil.example_cli import example_arguments
from supercoil.tables import make_table

u = sc.ureg


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/rod_tension_torque_slacking")

    rod = sc.ElasticRod(1.0 * u.mm, 1.01 * u.m, 4.20 * u.MPa, 1.51 * u.MPa, 0.5)
    N = 80
    rough = sc.rough_helix(rod, N, n_points=201 if args.quick else 1001)
    p = rough.profile
    S = p["slack"].to_numpy() * u.mm
    smooth = sc.smooth_helix(rod, N, S)

    table = make_table(
        {"slack": p["slack"], "tension_rough": p["tension"], "torque_rough": p["torque"],
         "tension_smooth": smooth.tension.m_as(u.N),
         "torque_smooth": smooth.torque.m_as(u.N * u.mm),
         "alpha_rough_end": p["alpha"], "alpha_smooth": smooth.alpha.m_as(u.rad)},
        {"slack": "mm", "tension_rough": "N", "torque_rough": "N*mm", "tension_smooth": "N",
         "torque_smooth": "N*mm", "alpha_rough_end": "rad", "alpha_smooth": "rad"},
        p.attrs["provenance"],
    )
    sc.write_csv(table, args.out / "tension_torque_slacking.csv")

    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    x = S.m_as(u.cm)
    ax[0].plot(x, p["tension"], label="rough (k = 0) [eq tension]")
    ax[0].plot(x, smooth.tension.m_as(u.N), "--", label="smooth (Case I)")
    ax[0].set_ylabel("tension T [N]")
    ax[1].plot(x, p["torque"], label="rough: C omega(S/2)")
    ax[1].plot(x, smooth.torque.m_as(u.N * u.mm), "--", label="smooth: C omega")
    ax[1].set_ylabel("twist moment M_3 [N mm]")
    for a in ax:
        a.set_xlabel("slack S [cm]")
        a.axvline(2 * rough.s_max.m_as(u.cm), color="gray", lw=0.8, ls=":")
        a.legend()
    fig.suptitle(f"Slacking a rod twisted by N = {N}: r = 1 mm, L = 1.01 m "
                 f"(helix ends at S = 2 s_max = {2 * rough.s_max.m_as(u.cm):.1f} cm)")
    fig.tight_layout()
    fig.savefig(args.out / "tension_torque_slacking.png", dpi=120)
    print(f"s_max = {rough.s_max:.2f~P}; T(0) = {p['tension'].iloc[0]:.4f} N, "
          f"M(0) = {p['torque'].iloc[0]:.4f} N mm")


if __name__ == "__main__":
    main()
