"""Benchmarks of the DNA scene: plectoneme equilibrium and hat curves.

* :func:`equilibrium_work_precision`: solver tolerance against error and time,
  vectorised over the forces against a scalar loop. The reference solves the
  *unreduced* equations (GE1 eliminated, GE2 and the tension equation in
  (alpha, R), SI units) with MINPACK's hybrid Powell method (scipy ``fsolve``,
  xtol 1e-15) started 1 % away from the solution: a different method and
  different equations from the solver under test.
* :func:`hat_cost`: cost per point of the hat curve as the number of turns grows
  (1e2 to 1e6), thermal against athermal. The equilibrium is solved once per
  call (a fixed cost), so at large sizes this is the cost "once the
  equilibrium is known".
"""

from __future__ import annotations

import numpy as np
from scipy import optimize

from supercoil.benchmark.timing import best_time
from supercoil.benchmark.work_precision import measure


def _reference_equilibrium(forces, B, C, kT, r0, start_alpha, start_R):
    from supercoil.core import geometry as g
    from supercoil.core.dna import marko_siggia as ms

    out = []
    for F, a0, R0 in zip(forces, start_alpha, start_R, strict=True):

        def eqs(v, F=F):
            a, R = v[0], v[1] * r0
            k, t = g.curvature(a, R), g.torsion(a, R)
            k_a, k_r = g.curvature_partials(a, R)
            t_a, t_r = g.torsion_partials(a, R)
            w = ms.interaction(a, R, B, kT, r0)
            w_a, w_r = ms.interaction_partials(a, R, B, kT, r0)
            X, Y = B * k * k_a + w_a, B * k * k_r + w_r
            ge2 = (t_r * X - t_a * Y) * R**3 / kT
            tension = (-0.5 * B * k * k + X / t_a * t - w - F) * r0 / kT
            return [ge2, tension]

        sol, _, ier, msg = optimize.fsolve(eqs, [a0 * 1.01, R0 / r0 * 1.01], xtol=1e-15,
                                              full_output=True)
        if ier != 1 and np.max(np.abs(eqs(sol))) > 1e-13:
            raise RuntimeError(f"reference solve failed at {F:g} N: {msg}")
        out.append((sol[0], sol[1] * r0))
    return np.array(out).T


def equilibrium_work_precision(dna=None, n_forces=200, tolerances=None, repeat=3):
    """Work-precision rows for the plectoneme equilibrium (dict of lists)."""
    import supercoil as sc
    from supercoil.core.dna import plectoneme as pl

    d = (dna or sc.load_parameters("dna")).si
    B, C, kT, r0 = d.bending_rigidity, d.torsional_rigidity, d.kT, d.radius
    forces = np.geomspace(0.1e-12, 10e-12, n_forces)
    tight = pl.equilibrium(forces, B, C, kT, r0, rtol=1e-14)
    a_ref, R_ref = _reference_equilibrium(forces, B, C, kT, r0, tight.alpha, tight.radius)
    # relative errors in alpha and in R, one dimensionless maximum
    scale = np.concatenate((a_ref, R_ref))
    reference = np.ones_like(scale)
    tolerances = tolerances or [10.0**-k for k in range(2, 15, 2)]

    def vectorised(tol):
        s = pl.equilibrium(forces, B, C, kT, r0, rtol=tol)
        return np.concatenate((s.alpha, s.radius)) / scale

    def scalar_loop(tol):
        states = [pl.equilibrium(f, B, C, kT, r0, rtol=tol) for f in forces]
        return np.concatenate(([float(s.alpha) for s in states],
                               [float(s.radius) for s in states])) / scale

    rows = measure(f"plectoneme equilibrium, {n_forces} forces 0.1-10 pN",
                   {"vectorised over forces": vectorised, "scalar loop": scalar_loop},
                   tolerances, reference, repeat=repeat)
    rows["time_per_force"] = [t / n_forces for t in rows["time"]]
    return rows


def hat_cost(dna=None, sizes=(100, 1_000, 10_000, 100_000, 1_000_000), force=1.2e-12):
    """Time per hat-curve point against the number of turns values, thermal and athermal."""
    import supercoil as sc
    from supercoil.core.dna.li_zhao import hat_curve_points

    d = (dna or sc.load_parameters("dna")).si
    args = (d.length, d.bending_rigidity, d.torsional_rigidity, d.kT, d.radius)
    rows = {k: [] for k in ("variant", "points", "time", "time_per_point", "points_per_second")}
    for thermal in (True, False):
        for n in sizes:
            turns = np.linspace(-25.0, 25.0, n)
            forces = np.full(n, force)
            t = best_time(lambda turns=turns, forces=forces, thermal=thermal:
                          hat_curve_points(turns, forces, *args, thermal=thermal), repeat=3)
            rows["variant"].append("thermal" if thermal else "athermal")
            rows["points"].append(n)
            rows["time"].append(t)
            rows["time_per_point"].append(t / n)
            rows["points_per_second"].append(n / t)
    return rows
