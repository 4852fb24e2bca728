"""Benchmarks of the rough-rod profile (docs/theory/rough.md): closed form against solve_ivp.

Two scenes, each with a reference that needs no ODE solver:

* k = 0 (twist N = 40, then slack; r = 1 mm, L = 56.7 cm, silicone rubber):
  the reference grid is built *backwards* from the explicit closed form
  ``s(alpha)`` [eq example k=0] on a grid of alpha from alpha_0 down to
  alpha_0/20, so the reference tilts are exact; every method is asked for
  alpha at those s. The closed form itself (alpha(s) by a monotone Newton
  iteration in y, rounding-level accurate, no tolerance to set) is one point.
* non-zero k(S): the designed helix of Example II (P(s) = P0 + P1 sin(k s),
  P0 = 16 mm, P1 = 4 mm, k = 2 pi/(10 P0), L = 57 cm): its twisting rate is
  known analytically from the inversion of [eq da/ds], and the ODE driven by
  it must reproduce the analytic tilt ``alpha(s) = arctan(2 pi r / P(s))``.

Each ODE method (RK45, DOP853, Radau, LSODA) runs at rtol 1e-3 ... 1e-12 with
atol = rtol / 100 (on y = 1 - cos 2 alpha, which is O(0.1-1)).
"""

from __future__ import annotations

import numpy as np

from supercoil.benchmark.work_precision import measure

METHODS = ("RK45", "DOP853", "Radau", "LSODA")
TOLERANCES = tuple(10.0**-k for k in range(3, 13))


def _k0_scene(turns=40.0):
    import supercoil as sc
    from supercoil.core.rod import contact as sco
    from supercoil.core.rod import rough as rh

    rod = sc.load_parameters("silicone_rubber_rod").si
    r, L, B, C = rod.radius, rod.length, rod.bending_rigidity, rod.torsional_rigidity
    a0 = float(sco.initial_tilt(turns, r, L, B, C))
    alpha_ref = np.linspace(a0, a0 / 20.0, 200)
    s_ref = rh.k0_s_of_alpha(alpha_ref, a0, L, B, C)
    s_ref[0] = 0.0

    def closed_form(tol):
        return sco.alpha_of_y(rh.k0_y_of_s(s_ref, a0, L, B, C))

    def ode(method):
        def solve(tol):
            integ = rh.integrate(a0, None, r, L, B, C, ode_method=method, rtol=tol,
                                 atol=tol * 1e-2)
            return sco.alpha_of_y(integ.y(s_ref))
        return solve

    return alpha_ref, closed_form, ode


def _designed_scene():
    import supercoil as sc
    from supercoil.core.rod import contact as sco
    from supercoil.core.rod import design as dh
    from supercoil.core.rod import rough as rh

    base = sc.load_parameters("silicone_rubber_rod").si
    r, B, C = base.radius, base.bending_rigidity, base.torsional_rigidity
    L = 0.57
    P0, P1 = 16e-3, 4e-3
    kw = 2.0 * np.pi / (10.0 * P0)

    def alpha_of(s):
        return dh.tilt_from_pitch(P0 + P1 * np.sin(kw * s), r)

    def kfun(S):
        s = 0.5 * np.asarray(S, float)
        P = P0 + P1 * np.sin(kw * s)
        return dh.twist_rate_for(s, dh.tilt_from_pitch(P, r),
                                 dh.tilt_slope(P, P1 * kw * np.cos(kw * s), r), r, L, B, C)

    s_end = 0.2  # 1.25 wavelengths of the pitch modulation, S = 40 cm
    s_ref = np.linspace(0.0, s_end, 200)
    alpha_ref = alpha_of(s_ref)
    a0 = float(alpha_ref[0])

    def ode(method):
        def solve(tol):
            integ = rh.integrate(a0, kfun, r, L, B, C, s_stop=s_end, ode_method=method,
                                 rtol=tol, atol=tol * 1e-2)
            return sco.alpha_of_y(integ.y(s_ref))
        return solve

    return alpha_ref, ode


def rough_profile_work_precision(tolerances=TOLERANCES, methods=METHODS, repeat=3):
    """Rows of both rough-profile work-precision diagrams (dict of lists)."""
    alpha_ref, closed_form, ode = _k0_scene()
    scene = "rough rod profile, k = 0 (N = 40, r = 1 mm, L = 56.7 cm)"
    rows = measure(scene, {"closed form": closed_form}, [0.0], alpha_ref, repeat=repeat)
    more = measure(scene, {m: ode(m) for m in methods}, tolerances, alpha_ref, repeat=repeat)
    for key in rows:
        rows[key] += more[key]
    alpha_ref2, ode2 = _designed_scene()
    scene2 = "rough rod profile, designed k(S) (P = 16 + 4 sin(ks) mm, L = 57 cm)"
    more = measure(scene2, {m: ode2(m) for m in methods}, tolerances, alpha_ref2, repeat=repeat)
    for key in rows:
        rows[key] += more[key]
    return rows
