"""No-slip check: friction torque required versus available (paper figure fricth).

(a) k = 0, N = 40, r = 1.0 mm, L = 56.7 cm; (b) the designed sinusoidal helix
(P0 = 16 mm, P1 = 4 mm, k = 2 pi/(10 P0), r = 1.0 mm, L = 57 cm). Silicone
rubber E = 4.20 MPa, G = 1.51 MPa, mu = 0.5. Required: ``C |d omega/ds|``;
available: ``mu r cos(alpha) F`` with ``F = B (1 - cos 2a)^2 / (4 r^3 cos 2a)``
([eq friction] and [eq normal reaction] corrected: dimension and a factor 2,
see supercoil.core.rod.contact). The dashed curve is the paper's printed
[eq friction] evaluated in SI units, for comparison.

    python examples/rod_friction_check.py --out OUT [--quick]
"""


import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import supercoil as sc
from supercoil.example_cli import example_arguments
from supercoil.rod.design import sinusoidal_pitch

u = sc.ureg
E, G, MU = 4.20 * u.MPa, 1.51 * u.MPa, 0.5


def main(argv=None):
    args = example_arguments(__doc__, argv, default_out="results/rod_friction_check")
    n = 301 if args.quick else 1501

    rod_a = sc.ElasticRod(1.0 * u.mm, 56.7 * u.cm, E, G, MU)
    res = sc.rough_helix(rod_a, 40, n_points=n)
    sc.write_csv(res.profile, args.out / "friction_k0_N40.csv")

    rod_b = sc.ElasticRod(1.0 * u.mm, 57 * u.cm, E, G, MU)
    P0 = 16 * u.mm
    sched = sc.design_twist_schedule(rod_b, sinusoidal_pitch(P0, 4 * u.mm, 2 * np.pi / (10 * P0)),
                                     slack_max=50 * u.cm, n_points=n)
    sc.write_csv(sched, args.out / "friction_designed.csv")

    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    p = res.profile
    ax[0].semilogy(p["s"], p["friction_torque_required"], label="required C|d omega/ds|")
    ax[0].semilogy(p["s"], p["friction_torque_available"], label="available dM_fmax/ds")
    r_m = rod_a.si.radius
    ax[0].semilogy(p["s"], p["friction_torque_available"] / (2 * r_m), "--", lw=0.8,
                   label="paper's printed [eq friction] in SI (x 1/(2r))")
    ax[0].axvline(res.slip_onset.m_as(u.mm), color="k", ls=":", lw=0.8,
                  label=f"slip onset s = {res.slip_onset.m_as(u.mm):.1f} mm")
    ax[0].axvline(res.s_max.m_as(u.mm), color="gray", ls="--", lw=0.8,
                  label=f"s_max = {res.s_max.m_as(u.mm):.1f} mm")
    ax[0].set_ylim(1e-6, 1)
    ax[0].set_title("(a) k = 0, N = 40, r = 1.0 mm, L = 56.7 cm")
    ax[1].plot(sched["s"], sched["friction_torque_required"], label="required C|d omega/ds|")
    ax[1].plot(sched["s"], sched["friction_torque_available"], label="available dM_fmax/ds")
    ax[1].set_title("(b) designed sinusoidal helix, L = 57 cm")
    for a in ax:
        a.set_xlabel("s [mm]")
        a.set_ylabel("torque per length [N]")
        a.legend()
    fig.suptitle("No-slip condition [eq friction con], mu = 0.5")
    fig.tight_layout()
    fig.savefig(args.out / "friction_check.png", dpi=120)
    ratio = (sched["friction_torque_required"] / sched["friction_torque_available"]).max()
    frac = (res.slip_onset / res.s_max).m_as(u.dimensionless)
    print(f"k = 0, N = 40: slip onset s = {res.slip_onset:.2f~P} ({frac:.3f} s_max); "
          f"designed helix: max required/available = {ratio:.3f}")


if __name__ == "__main__":
    main()
