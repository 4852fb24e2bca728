"""Case II, rough surface: the frozen non-uniform hard-contact helix. Float-only kernel.

docs/theory/rough.md, paper [eq da/ds, eq ini, eq tension, eq example k=0] and
Appendix C. SI floats (m, N, N m^2, rad); nothing here imports pint.

The ODE in a regular variable
-----------------------------
[eq da/ds] reads, with ``c = cos 2a`` and R = r,

    d alpha/ds = C / (B (L - 2s)) * [sin 2a - 2 r k(2s)] c^2 / (c^3 - 1).

At alpha -> 0 (the helix end s_max for k = 0) ``c^3 - 1 ~ -6 a^2`` and
d alpha/ds ~ -C / (3 B (L - 2s) alpha) diverges (alpha ~ sqrt(s_max - s)), which
an explicit solver cannot step onto. With ``y = 1 - cos 2a = 2 sin^2 a``,
``dy/ds = 2 sin 2a d alpha/ds`` and ``c^3 - 1 = -y (c^2 + c + 1)`` give

    dy/ds = -2C / (B (L - 2s)) * c^2 / (c^2 + c + 1) * [(2 - y) - 2 r k sqrt((2 - y)/y)]

which for k = 0 is smooth and non-zero at y = 0, so y crosses 0 linearly at
s_max and the terminal event ``y = 0`` is located to solver accuracy. (For
k != 0 the k-term is an integrable ``y^(-1/2)``.) The second terminal event is
``cos 2a = cos2a_min`` (alpha -> pi/4, where the tension diverges).

Closed form, k = 0 [eq example k=0]
-----------------------------------
With ``Phi(c) = ln(1 + c) - 1/c`` (increasing in c) the solution is
``ln(1 - 2s/L) = -(B/C) [Phi(c) - Phi(c0)]``, so s is explicit in alpha,

    s(alpha) = -(L/2) expm1(-(B/C) [Phi(cos 2a) - Phi(cos 2a0)]),

and alpha(s) is the root of ``Phi(c) = Phi(c0) - (C/B) ln(1 - 2s/L)`` (solved by
a vectorised, monotonically converging Newton iteration in y, accurate to the
rounding level of Phi, ~1e-16 in y). The end
(alpha = 0, c = 1) is [s_max]:
``s_max = (L/2) [1 - (2 exp(sec 2a0 - 1) / (cos 2a0 + 1))^(-B/C)]``.

Conditioning near s_max
-----------------------
alpha(s) has a square-root singularity at s_max, so an absolute error ds in the
position of the end (>= one float spacing of s, ~1e-17 m) gives an error
~ sqrt(|dy/ds| ds / 2) in alpha at the last points. Agreement between methods
is therefore measured in y (uniformly, ~1e-11 with DOP853 at rtol 1e-10) and
in alpha on the default grid, which stops at s_max (1 - 1e-7): there the
difference is <= 1e-8 rad (at s_max (1 - 1e-8) it grows to ~2e-8 rad).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from supercoil.core.geometry import curvature, torsion
from supercoil.core.numerics import cumulative_integrals, first_crossing
from supercoil.core.rod import contact as sc
from supercoil.core.rod.rough_solution import (
    ATOL,
    MAX_NFEV,
    RTOL,
    TAIL_FRACTION_MIN,
    Y_SWITCH,
    Integration,
    RoughSolution,
    dy_ds,
    integrate,
)
from supercoil.exceptions import NoHelixError

__all__ = ["ATOL", "MAX_NFEV", "RTOL", "TAIL_FRACTION_MIN", "Y_SWITCH", "ClosedForm",
           "Integration", "RoughProfile", "RoughSolution", "cumulative_integrals", "dy_ds",
           "first_crossing", "integrate", "rough_profile"]

TWO_PI = 2.0 * np.pi
#: Uniform points of the internal grid on which :func:`rough_profile` locates the
#: slip and curvature-error onsets and breaks the Tw, Wr, N quadratures (plus 60
#: points clustered toward s_max and the nodes of a twist-rate table).
INTERNAL_POINTS = 801
#: Profile points evaluated at once (bounds the working memory of a long profile).
CHUNK = 1 << 12


# --- closed form, k = 0 ------------------------------------------------------


def phi(y):
    """``Phi = ln(1 + c) - 1/c`` with ``c = 1 - y``; decreasing in y on [0, 1)."""
    y = np.asarray(y, float)
    return np.log(2.0 - y) - 1.0 / (1.0 - y)


def phi_diff(ya, yb):
    """``Phi(ya) - Phi(yb)`` without cancellation (accurate also for tiny y, ya ~ yb).

    ``ln((2 - ya)/(2 - yb)) - [1/(1 - ya) - 1/(1 - yb)]
    = log1p((yb - ya)/(2 - yb)) - (ya - yb) / ((1 - ya)(1 - yb))``; the plain
    difference of two O(1) values of Phi loses everything below 1e-16 (the
    k = 0 helix of N_0 = 1e-300 turns would get s_max = 0).
    """
    ya = np.asarray(ya, float)
    yb = np.asarray(yb, float)
    d = ya - yb
    return np.log1p(-d / (2.0 - yb)) - d / ((1.0 - ya) * (1.0 - yb))


def k0_s_of_alpha(alpha, alpha0, L, B, C):
    """Closed form [eq example k=0]: arclength s (m) at which the tilt equals alpha.

    Implements docs/theory/rough.md (eq example k=0).
    """
    x = phi_diff(sc.y_of_alpha(alpha), sc.y_of_alpha(alpha0))
    return -0.5 * L * np.expm1(-(B / C) * x)


def k0_s_max(alpha0, L, B, C):
    """[s_max] End of the k = 0 helix, where alpha -> 0 (m)."""
    return k0_s_of_alpha(0.0, alpha0, L, B, C)


def k0_y_of_s(s, alpha0, L, B, C):
    """``y = 1 - cos 2 alpha`` at arclength s for k = 0 (vectorised Newton in y).

    Implements docs/theory/rough.md (eq example k=0).

    Solves ``q(y) = Phi_target(s) - Phi(y) = 0`` on [0, y0]. q is increasing
    and convex in y (``Phi' < 0``, ``Phi'' < 0``), so Newton's method started at
    ``y = y0`` (where q >= 0) decreases monotonically onto the root without
    overshooting; it stops when the steps reach rounding level (about 1e-16
    y0 in y, the conditioning of the closed form itself; ``Phi`` differences
    are taken by :func:`phi_diff`, so a tiny y0 keeps its relative accuracy).

    Raises
    ------
    NoHelixError
        If some s lies outside ``[0, s_max]``.
    """
    s = np.asarray(s, float)
    smax = k0_s_max(alpha0, L, B, C)
    if np.any(s < 0) or np.any(s > smax):
        raise NoHelixError(
            f"s outside the k = 0 helix [0, s_max = {smax:.9g} m]: beyond s_max alpha "
            "would be negative (the pitch has diverged)"
        )
    y0 = float(sc.y_of_alpha(alpha0))
    with np.errstate(divide="ignore"):  # s = L/2 only if s_max rounds to L/2
        drop = -(C / B) * np.log1p(-2.0 * s / L)  # Phi(y(s)) - Phi(y0) >= 0
    drop = np.where(np.isfinite(drop), drop, phi_diff(0.0, y0))
    y = np.full_like(drop, y0)
    for _ in range(100):
        q = drop - phi_diff(y, y0)  # = Phi_target(s) - Phi(y), without cancellation
        dq = 1.0 / (2.0 - y) + 1.0 / (1.0 - y) ** 2  # -Phi'(y) > 0
        step = q / dq
        y_new = np.clip(y - step, 0.0, y0)
        done = np.all(np.abs(y_new - y) <= 2.5e-15 * y0)  # relative: tiny y0 too
        y = y_new
        if done:
            break
    return np.where(s == 0, y0, np.where(s == smax, 0.0, y))


def k0_dy_ds(s, y, L, B, C):
    """dy/ds for k = 0 (1/m): ``-2C/(B (L-2s)) c^2 (1 + c) / (c^2 + c + 1)``."""
    c = 1.0 - np.asarray(y, float)
    return -2.0 * C / (B * (L - 2.0 * np.asarray(s, float))) * c * c * (1.0 + c) / (c * c + c + 1.0)


class ClosedForm:
    """Interpolant of the k = 0 helix: y(s) of [eq example k=0] (:func:`k0_y_of_s`)."""

    kind = "closed form"

    def __init__(self, alpha0, L, B, C):
        self.p = (alpha0, L, B, C)

    def __call__(self, s):
        return k0_y_of_s(s, *self.p)


# --- the algorithm: solution, grids, integrals, onsets, columns ----------------


class RoughProfile(NamedTuple):
    """Float-level result of :func:`rough_profile` (SI units).

    ``columns`` holds every profile column (SI, signed with N_0, the flag as
    bool); ``s_max`` is None when the helix end is unknown (see
    :class:`supercoil.rod.rough.RoughHelix`); ``alpha_max`` is the largest tilt
    on [0, s_end] (internal grid and the head), for the hard-contact check.
    """

    alpha0: float
    s_end: float
    s_max: float | None
    end: str
    method: str
    solver: dict
    columns: dict
    slip_onset: float | None
    curvature_error_onset: float | None
    alpha_max: float
    solution: RoughSolution


def _solve(alpha0, kfun, k_zero, method, r, L, B, C, s_user, s_table, ode):
    """The helix y(s): ``(solution, dy(s, y), end, solver dict, s_max)`` (s in m)."""
    s_rod = 0.5 * L * (1.0 - TAIL_FRACTION_MIN)  # the helix takes the whole rod
    with np.errstate(over="ignore", under="ignore"):
        s_max_k0 = float(k0_s_max(alpha0, L, B, C)) if k_zero else None
    if method == "closed_form":
        s_end, end = s_max_k0, "alpha->0"
        if s_end > s_rod:
            s_end, end = s_rod, "s_stop"
        if s_user is not None and s_user < s_end:
            s_end, end = s_user, "s_stop"
        sol = RoughSolution([0.0, s_end], [ClosedForm(alpha0, L, B, C)])
        dy, solver = (lambda x, y: k0_dy_ds(x, y, L, B, C)), {}
    else:
        rtol, atol, ode_method, max_nfev, cos2a_min = ode
        rtol = sc.check_scalar(rtol, "rtol", 0.0, 0.1, hi_open=False,
                               what=" (looser ODE steps leave y = 1 - cos 2 alpha in [0, 1])")
        atol = sc.check_scalar(atol, "atol", 0.0, np.inf, what=" (absolute ODE tolerance on y)")
        if ode_method == "auto":
            ode_method = "DOP853" if k_zero else "LSODA"
        # a tiny initial tilt (tiny N_0) must still be resolved relatively: cap atol
        # at rtol y_0 (no effect unless y_0 = 1 - cos 2 alpha_0 < atol / rtol)
        atol = min(atol, rtol * float(sc.y_of_alpha(alpha0)))
        s_stop = min(x for x in (s_rod, s_user, s_table) if x is not None)
        with np.errstate(all="ignore"):  # e.g. scipy's error norm at y ~ 1e-200; the
            # outcome is checked: solver status, events, finite profile columns
            integ = integrate(alpha0, None if k_zero else kfun, r, L, B, C, s_stop=s_stop,
                              ode_method=ode_method, rtol=rtol, atol=atol,
                              cos2a_min=cos2a_min, max_nfev=max_nfev)
        sol, dy, end = integ.solution, integ.dy, integ.reason
        solver = {"ode_method": ode_method, "rtol": rtol, "atol": atol, "nfev": int(integ.nfev)}
    s_end = sol.t_max
    if end == "alpha->0" or s_end >= s_rod:  # the true end, never where the run stopped
        s_max = s_end
    else:
        s_max = min(s_max_k0, s_rod) if k_zero else None
    return sol, dy, end, solver, s_max


def _profile_points(grid, s_end, end, n_points):
    """The profile grid (m): the default one, or ``grid`` checked to lie on the helix."""
    n_end, include = (60, False) if end == "alpha->0" else (0, True)
    if grid is None:
        return profile_grid(s_end, n_points, n_end, include_end=include)
    if grid[0] < 0 or grid[-1] > s_end or (end == "alpha->0" and grid[-1] >= s_end):
        raise NoHelixError(
            f"profile grid s outside the helix [0, s_max = {s_end * 1e3:.9g} mm)"
            + (": alpha = 0 and the pitch is infinite at s_max" if end == "alpha->0" else
               f" (integrated up to s_end = {s_end * 1e3:.9g} mm)"))
    return grid


def _integrals_at(x, inner, ints_in, y_at, kfun, r, B, C):
    """``(int omega, int tau, int k(2s))`` from the head at the sorted points x.

    Points on an internal node take the internal integrals ``ints_in``; the
    others add the integral from their node below, taken as a difference of
    running integrals over those nodes and points (one quadrature per chunk).
    """
    idx = np.searchsorted(inner, x, side="right") - 1
    out = ints_in[:, idx]
    off = inner[idx] != x
    if np.any(off):
        breaks = np.unique(np.concatenate([inner[idx[off]], x[off]]))
        # absolute budget: 1e-12 of the integrals over the whole helix (a relative one
        # on a short chunk sits below the integrand's rounding noise)
        run = strand_integrals(breaks, y_at, kfun, r, B, C,
                               atol=1e-12 * np.max(np.abs(ints_in), axis=1))
        out[:, off] += (run[:, np.searchsorted(breaks, x[off])]
                        - run[:, np.searchsorted(breaks, inner[idx[off]])])
    return out


def _onsets(inner, y_in, dy_in, y_at, dy_at, r, B, mu, tol):
    """``(slip_onset, curvature_error_onset)`` (m or None) searched on the internal grid."""
    slip = None
    if mu is not None:
        g_slip = (sc.friction_torque_required_y(y_in, dy_in, r, B)
                  - sc.friction_torque_available(sc.alpha_of_y(y_in), r, B, mu))
        slip = first_crossing(inner, g_slip, slip_function(y_at, dy_at, r, B, mu))
    err_in = np.abs(curvature_error_y(y_in, dy_in, r) - 1.0)
    ce = first_crossing(inner, err_in - tol, curvature_error_function(y_at, dy_at, r, tol))
    return slip, ce


ORDER = ("s", "slack", "alpha", "pitch", "omega", "curvature", "torsion", "tension", "torque",
         "normal_force", "friction_torque_required", "friction_torque_available",
         "curvature_error", "curvature_error_flag", "turns", "twist", "writhe")


def _fill_columns(out, sl, x, sol, dy, inner, ints_in, kfun, n0, r, L, B, C, mu, tol):
    """Profile columns at the points ``x`` (one chunk) written into ``out[c][sl]``."""
    y = np.asarray(sol(x), float)
    ints = _integrals_at(x, inner, ints_in, sol, kfun, r, B, C)
    cols = profile_columns(x, y, dy(x, y), abs(n0) + ints[2] / np.pi, ints[0], ints[1],
                           r, L, B, C, mu)
    cols["torque"] = C * cols["omega"]
    sign = 1.0 if n0 >= 0 else -1.0
    for key in ("omega", "torque", "twist", "writhe", "turns"):
        cols[key] = sign * cols[key]
    cols["curvature_error_flag"] = np.abs(cols["curvature_error"] - 1.0) > tol
    if mu is None:
        cols["friction_torque_available"] = np.nan
    for c in ORDER:
        if c != "s":
            out[c][sl] = cols[c]


def rough_profile(n0, r, L, B, C, mu=None, *, kfun=None, k_zero=True, method="closed_form",
                  grid=None, n_points=801, slack_max=None, slack_table=None, k_nodes=(),
                  curvature_tolerance=0.01, ode_method="auto", rtol=RTOL, atol=ATOL,
                  cos2a_min=sc.COS2A_MIN, max_nfev=MAX_NFEV):
    """The frozen rough helix of N_0 turns: solution, profile columns and onsets (SI).

    The algorithm behind :func:`supercoil.rod.rough.rough_helix` (see there
    for the physics and every argument, here in SI floats: ``slack_max`` and
    ``slack_table`` (the last slack of a twist-rate table) in m or None,
    ``kfun(S)`` in rad/m in the frame N_0 > 0, ``grid`` a checked increasing
    array in m or None, ``k_nodes`` the table's slack nodes in m). Steps:
    alpha_0 from [eq ini]; y(s) in closed form or by :func:`integrate` (one
    :class:`RoughSolution`); the profile grid; ``int omega``, ``int tau`` and
    ``int k`` from the head on the internal grid (:data:`INTERNAL_POINTS` plus
    the table nodes) by :func:`strand_integrals`, and from the nearest internal
    node to every profile point; the slip and curvature-error onsets on the
    internal grid; the columns, :data:`CHUNK` points at a time, so the memory
    beyond the output columns stays bounded for any number of points.

    Returns
    -------
    RoughProfile

    Raises
    ------
    NoHelixError, SingularityError, ValidityError
        See :func:`supercoil.rod.rough.rough_helix`.
    """
    with np.errstate(over="ignore", under="ignore"):
        alpha0 = float(sc.initial_tilt(abs(n0), r, L, B, C))
    sc.check_tilt(alpha0, f"initial tilt [eq ini], N_0 = {n0:g}, N_0 r / L = "
                  f"{abs(n0) * r / L:.3g}", cos2a_min)
    kfun = kfun if kfun is not None else (lambda S: np.zeros_like(np.asarray(S, float)))
    sol, dy, end, solver, s_max = _solve(
        alpha0, kfun, k_zero, method, r, L, B, C,
        None if slack_max is None else 0.5 * slack_max,
        None if slack_table is None else 0.5 * slack_table,
        (rtol, atol, ode_method, max_nfev, cos2a_min))
    s_end = sol.t_max
    pts = _profile_points(grid, s_end, end, n_points)
    inner = profile_grid(s_end, INTERNAL_POINTS, 60 if end == "alpha->0" else 0,
                         include_end=(end != "alpha->0"))
    nodes = 0.5 * np.asarray(k_nodes, float)
    inner = np.unique(np.concatenate([inner, nodes[(nodes > 0) & (nodes < inner[-1])]]))
    with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
        y_in = np.asarray(sol(inner), float)
        dy_in = np.asarray(dy(inner, y_in), float)
        ints_in = strand_integrals(inner, sol, kfun, r, B, C)
        slip, ce = _onsets(inner, y_in, dy_in, sol, dy, r, B, mu, curvature_tolerance)
        out = {c: np.empty(pts.shape, bool if c == "curvature_error_flag" else float)
               for c in ORDER if c != "s"}
        out["s"] = pts
        for i in range(0, pts.size, CHUNK):
            sl = slice(i, i + CHUNK)
            _fill_columns(out, sl, pts[sl], sol, dy, inner, ints_in, kfun, n0, r, L, B, C,
                          mu, curvature_tolerance)
    alpha_max = float(np.max(sc.alpha_of_y(np.concatenate([[sc.y_of_alpha(alpha0)], y_in]))))
    return RoughProfile(alpha0, s_end, s_max, end, method, solver, {c: out[c] for c in ORDER},
                        slip, ce, alpha_max, sol)


# --- grids and profile columns -------------------------------------------------


def profile_grid(s_end, n_points=801, n_end=60, include_end=False):
    """Arclength grid on [0, s_end): uniform, plus points clustered toward s_end.

    The clustered points ``s_end (1 - q)``, q geometric from 1e-2 to 1e-7,
    resolve the square-root ending of alpha at s_max (alpha ~ sqrt(s_max - s)).
    The grid stops at ``s_max (1 - 1e-7)``: closer to the end alpha(s) is so
    ill-conditioned (d alpha/ds ~ 1/alpha) that no solver resolves it, and the
    slowly-varying-pitch model has long failed there (|e - 1| ~ 1e8). ``include_end`` adds
    s_end itself (use it when the end is not alpha = 0). Points closer than
    ``1e-12 s_end`` to their left neighbour are dropped (they would repeat in mm).
    """
    base = np.linspace(0.0, s_end, int(n_points))[:-1]
    tail = s_end * (1.0 - np.geomspace(1e-2, 1e-7, int(n_end))) if n_end else np.empty(0)
    grid = np.unique(np.concatenate([base, tail, [s_end] if include_end else []]))
    grid = grid[grid <= s_end]
    # drop near-duplicates (a uniform point a few float spacings from a clustered
    # one): they would collapse into one value in the table's mm column
    return grid[np.concatenate([[True], np.diff(grid) > 1e-12 * s_end])]


def strand_integrals(breaks, y_at, kfun, r, B, C, atol=0.0):
    """``(int omega ds, int tau ds, int k(2s) ds)`` from s = breaks[0] at every breakpoint.

    ``y_at(s)`` gives ``y = 1 - cos 2 alpha`` along the helix and ``kfun(S)``
    the twisting rate (rad/m) at slack S. With these integrals (one strand,
    s from the head) [Eq Lk=Tw+Wr] at slack S = 2 s reads

        Tw = (1/pi) int_0^s omega + omega(s) (L - 2 s) / 2 pi,
        Wr = (1/pi) int_0^s tau,      N = N_0 + (1/pi) int_0^s k(2s') ds',

    and ``Tw + Wr = N`` holds for the exact solution of [eq da/ds] (its
    derivative is the ODE). See :func:`cumulative_integrals` for the quadrature
    (relative tolerance 1e-12; ``atol`` its absolute budget per row).
    """

    def f(x):
        alpha = sc.alpha_of_y(y_at(x))
        k = np.broadcast_to(np.asarray(kfun(2.0 * x), float), x.shape)
        return np.vstack([sc.twist_density(alpha, r, B, C), torsion(alpha, r), k])

    return cumulative_integrals(f, breaks, atol=atol)


def profile_columns(s, y, dyds, turns_abs, omega_int, tau_int, r, L, B, C, mu=None):
    """All profile columns (SI floats) from y(s) and dy/ds on a grid s (one strand).

    ``turns_abs`` is N(S) at S = 2 s; ``omega_int`` and ``tau_int`` are
    ``int_0^s omega ds'`` and ``int_0^s tau ds'`` from the head (see
    :func:`strand_integrals`), so the grid s may start anywhere and be coarse.

    Returns a dict with ``s, alpha, pitch, omega, curvature, torsion, tension,
    normal_force, friction_torque_required, friction_torque_available,
    curvature_error, slack, turns, twist, writhe`` (unsigned; the caller
    attaches sign(N) to omega, twist, writhe, turns and torque).
    ``friction_torque_available`` is only present when ``mu`` is given.
    """
    s = np.asarray(s, float)
    y = np.asarray(y, float)
    alpha = sc.alpha_of_y(y)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        pitch = np.where(y > 0, TWO_PI * r / np.tan(alpha), np.inf)
        omega = sc.twist_density(alpha, r, B, C)
        tau = torsion(alpha, r)
        out = {
            "s": s,
            "slack": 2.0 * s,
            "alpha": alpha,
            "pitch": pitch,
            "omega": omega,
            "curvature": curvature(alpha, r),
            "torsion": tau,
            "tension": sc.tension(alpha, r, B),
            "normal_force": sc.normal_force(alpha, r, B),
            "friction_torque_required": sc.friction_torque_required_y(y, dyds, r, B),
            "curvature_error": curvature_error_y(y, dyds, r),
            "turns": np.asarray(turns_abs, float) * np.ones_like(s),
            "twist": np.asarray(omega_int, float) / np.pi + omega * (L - 2.0 * s) / TWO_PI,
            "writhe": np.asarray(tau_int, float) / np.pi,
        }
        if mu is not None:
            out["friction_torque_available"] = sc.friction_torque_available(alpha, r, B, mu)
    return out


def curvature_error_y(y, dyds, r):
    """Appendix A factor ``e = sqrt(1 + (dP/ds)^2 / 4 pi^2)`` from y and dy/ds.

    ``dP/ds = -2 pi r (dy/ds) / (y sqrt(y (2 - y)))``, so
    ``(dP/ds) / 2 pi = -r (dy/ds) / (y sqrt(y (2 - y)))``; ``hypot`` keeps e
    finite where dP/ds is huge (tiny tilts); ``inf`` at y = 0 (pitch infinite).
    """
    y = np.asarray(y, float)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        s2 = np.sqrt(np.clip(y * (2.0 - y), 0.0, None))
        x = np.where(y > 0, r * np.asarray(dyds, float) / s2 / y, np.inf)
        return np.hypot(1.0, x)


def slip_function(y_at, dy_at, r, B, mu):
    """``s -> C |d omega/ds| - dM_fmax/ds`` (N), positive where the strands slip."""

    def g(s):
        y = y_at(s)
        return float(sc.friction_torque_required_y(y, dy_at(s, y), r, B)
                     - sc.friction_torque_available(sc.alpha_of_y(y), r, B, mu))

    return g


def curvature_error_function(y_at, dy_at, r, tol):
    """``s -> |e - 1| - tol`` along the profile (Appendix A)."""

    def g(s):
        y = y_at(s)
        if y <= 0:
            return np.inf
        return float(curvature_error_y(y, dy_at(s, y), r) - 1.0 - tol)

    return g
