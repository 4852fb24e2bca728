"""Case II, rough surface: the frozen non-uniform hard-contact helix. Float-only kernel.

MODEL.md section 4, paper [eq da/ds, eq ini, eq tension, eq example k=0] and
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

import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from supercoil.core.geometry import curvature, torsion
from supercoil.core.rod import contact as sc
from supercoil.exceptions import NoHelixError, SingularityError, ValidityError

TWO_PI = 2.0 * np.pi

#: Default ODE tolerances of :func:`integrate` (relative, absolute on y).
RTOL = 1e-10
ATOL = 1e-12
#: Default end of the integration when no terminal event fires: the tail keeps
#: this fraction of L (the ODE has a 1/(L - 2s) factor at S = L).
TAIL_FRACTION_MIN = 1e-6


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
    """Closed form [eq example k=0]: arclength s (m) at which the tilt equals alpha."""
    x = phi_diff(sc.y_of_alpha(alpha), sc.y_of_alpha(alpha0))
    return -0.5 * L * np.expm1(-(B / C) * x)


def k0_s_max(alpha0, L, B, C):
    """[s_max] End of the k = 0 helix, where alpha -> 0 (m)."""
    return k0_s_of_alpha(0.0, alpha0, L, B, C)


def k0_y_of_s(s, alpha0, L, B, C):
    """``y = 1 - cos 2 alpha`` at arclength s for k = 0 (vectorised Newton in y).

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


# --- general twist rate: the ODE ---------------------------------------------


def dy_ds(s, y, k, r, L, B, C):
    """Right side of [eq da/ds] in ``y = 1 - cos 2a`` (1/m); ``k = k(2s)`` in rad/m."""
    # trial stages of explicit solvers may step outside [0, 1]: keep the right
    # side finite there (the error control rejects such steps)
    y = np.clip(np.asarray(y, float), 0.0, 1.5)
    k = np.asarray(k, float)
    c = 1.0 - y
    yy = np.maximum(y, 1e-30)
    bracket = (2.0 - y) - np.where(k == 0.0, 0.0, 2.0 * r * k * np.sqrt((2.0 - y) / yy))
    return -2.0 * C / (B * (L - 2.0 * np.asarray(s, float))) * c * c / (c * c + c + 1.0) * bracket


#: Phase switch of :func:`integrate`: below this y (alpha ~ 0.022 rad), while y
#: decreases, the ODE is integrated as s(y) instead of y(s).
Y_SWITCH = 1e-3


def _dy_ds_scalar(s, y, k, r, L, B, C):
    """Scalar (math-module) twin of :func:`dy_ds` for the solver's right side."""
    y = min(max(y, 0.0), 1.5)
    c = 1.0 - y
    bracket = 2.0 - y
    if k != 0.0:
        bracket -= 2.0 * r * k * math.sqrt((2.0 - y) / max(y, 1e-30))
    return -2.0 * C / (B * (L - 2.0 * s)) * c * c / (c * c + c + 1.0) * bracket


class Integration:
    """Result of :func:`integrate`: piecewise dense solution, end point, why it ended.

    ``segments`` is a list of ``(kind, lo, hi, sol)``: kind ``"y(s)"`` covers
    s in [lo, hi] with ``sol(s) -> y``; kind ``"s(y)"`` covers s in [lo, hi]
    with ``sol(y) -> s`` for y decreasing from ``sol.y_start`` to ``sol.y_end``.
    """

    def __init__(self, segments, s_end, reason, nfev, ode_method, rtol, atol, kfun, r, L, B, C):
        self.segments = segments
        self.s_end = s_end
        self.reason = reason  # "alpha->0", "s_stop"
        self.nfev = nfev
        self.ode_method = ode_method
        self.rtol = rtol
        self.atol = atol
        self._k = kfun
        self._p = (r, L, B, C)

    def y(self, s):
        """y(s) from the dense outputs (s(y) segments inverted by bisection), >= 0."""
        s = np.asarray(s, float)
        out = np.full(s.shape, np.nan)
        flat_s, flat_o = s.reshape(-1), out.reshape(-1)
        for kind, lo, hi, sol in self.segments:
            m = (flat_s >= lo) & (flat_s <= hi) & np.isnan(flat_o)
            if not np.any(m):
                continue
            x = flat_s[m]
            if kind == "y(s)":
                flat_o[m] = sol(x)[0]
            else:  # invert the monotone map y -> s on [y_end, y_start]
                flat_o[m] = self._invert(sol, x)
        if np.any(np.isnan(out)):
            raise NoHelixError(f"s outside the integrated helix [0, {self.s_end:.9g} m]")
        out = np.clip(out, 0.0, None)
        return float(out) if out.ndim == 0 else out

    def dy(self, s, y):
        s = np.asarray(s, float)
        k = np.asarray(self._k(2.0 * s), float)
        if not np.all(np.isfinite(k)):
            bad = np.flatnonzero(~np.isfinite(np.broadcast_to(k, s.shape)).reshape(-1))[0]
            raise _nonfinite_rate(float(np.broadcast_to(k, s.shape).reshape(-1)[bad]),
                                  2.0 * float(np.reshape(s, -1)[bad]))
        return dy_ds(s, y, k, *self._p)

    def _invert(self, sol, x):
        """y with ``sol(y) = x`` on an s(y) segment: Newton (ds/dy = 1/(dy/ds)), safeguarded."""
        lo = np.full(x.shape, sol.y_end)
        hi = np.full(x.shape, sol.y_start)
        # start from linear interpolation between the two ends of the segment
        s_hi, s_lo = float(sol(sol.y_start)[0]), float(sol(sol.y_end)[0])
        t = np.clip((x - s_hi) / (s_lo - s_hi), 0.0, 1.0) if s_lo != s_hi else np.zeros(x.shape)
        y = sol.y_start + t * (sol.y_end - sol.y_start)
        for _ in range(60):
            f = x - sol(y)[0]  # increasing in y
            hi = np.where(f > 0, y, hi)
            lo = np.where(f > 0, lo, y)
            slope = -1.0 / self.dy(x, y)  # d(x - s(y))/dy = -ds/dy > 0
            with np.errstate(divide="ignore", invalid="ignore"):
                y_new = y - f / slope
            bad = ~np.isfinite(y_new) | (y_new < lo) | (y_new > hi)
            y_new = np.where(bad, 0.5 * (lo + hi), y_new)
            if np.all(np.abs(y_new - y) <= 1e-15 + 1e-13 * np.abs(y)):
                return y_new
            y = y_new
        return sc.bisect_increasing(lambda yy: x - sol(yy)[0], lo, hi)


def _zero_rate(S):
    return np.zeros_like(np.asarray(S, float))


def _nonfinite_rate(k, S):
    return ValidityError(
        f"twisting rate k = {k!r} rad/m at slack S = {float(S):.9g} m is not finite: "
        "[eq da/ds] is undefined there (twist_rate must be finite)"
    )


def _singular(s_sing, cos2a_min):
    return SingularityError(
        f"tilt alpha -> pi/4 (cos 2 alpha < {cos2a_min:g}) at s = {s_sing:.6g} m "
        f"(slack S = {2 * s_sing:.6g} m): the tension diverges; the twisting rate "
        "k(S) is too large for a hard-contact helix"
    )


def integrate(alpha0, kfun, r, L, B, C, s_stop=None, ode_method="DOP853",
              rtol=RTOL, atol=ATOL, cos2a_min=sc.COS2A_MIN, y_switch=Y_SWITCH):
    """Integrate [eq da/ds] from s = 0 with ``solve_ivp``, in two phases.

    Phase "y(s)": y = 1 - cos 2 alpha as a function of s (regular for k = 0 and
    wherever y is not small). Phase "s(y)": once y falls below ``y_switch``
    while decreasing, s is integrated as a function of y down to y = 0,
    ``ds/dy = 1 / (dy/ds)``. Near the end dy/ds is finite (k = 0) or diverges
    like ``y^(-1/2)`` (k < 0, untwisting while slacking), so ds/dy is regular
    in both cases and the end s_max = s(y = 0) is reached without an event
    search on a singular right side. If dy/ds rises to half its value at the
    switch in phase "s(y)" (a turning point ahead: k > 0 re-tilting the helix)
    the integration goes back to phase "y(s)" with the switch level halved.

    Parameters
    ----------
    alpha0 : float
        Initial tilt from [eq ini] (rad).
    kfun : callable or None
        ``kfun(S) -> k`` twisting rate in rad/m as a function of slack S (m),
        vectorised, in the frame where N_0 > 0. None: k = 0.
    r, L, B, C : float
        Rod radius, length (m), rigidities (N m^2).
    s_stop : float, optional
        Last s to integrate to if the helix does not end first; default
        ``(L/2)(1 - TAIL_FRACTION_MIN)``.
    ode_method : str
        Any ``solve_ivp`` method ("RK45", "DOP853", "Radau", "LSODA", ...).
    rtol, atol : float
        Tolerances (defaults 1e-10, 1e-12): on y in phase "y(s)"; on s in
        phase "s(y)" with ``atol * L`` as absolute tolerance (metres).
    cos2a_min : float
        alpha -> pi/4 guard: terminal event at ``cos 2a = cos2a_min``.
    y_switch : float
        Phase switch threshold in y (default 1e-3).

    Returns
    -------
    Integration

    Raises
    ------
    SingularityError
        If the tilt reaches pi/4 (cos 2 alpha = cos2a_min) at some s, or a
        solver fails (message from solve_ivp).
    """
    if s_stop is None:
        s_stop = 0.5 * L * (1.0 - TAIL_FRACTION_MIN)

    if kfun is None:
        kfun = _zero_rate

        def kscalar(S):
            return 0.0
    else:

        def kscalar(S):
            k = float(np.asarray(kfun(S)).reshape(-1)[0])
            if not math.isfinite(k):  # never integrate on: a NaN/inf k stalls the solver
                raise _nonfinite_rate(k, S)
            return k

    def ydot(s, y):
        return _dy_ds_scalar(float(s), float(y), kscalar(2.0 * s), r, L, B, C)

    def fun_y(s, yv):
        return np.array([ydot(s, yv[0])])

    def fun_s(y, sv):
        return np.array([1.0 / ydot(sv[0], y)])

    def ev_zero(s, yv):
        return yv[0]

    ev_zero.terminal, ev_zero.direction = True, -1

    def ev_sing(s, yv):
        return (1.0 - yv[0]) - cos2a_min

    ev_sing.terminal, ev_sing.direction = True, -1

    def ev_stop(y, sv):
        return sv[0] - s_stop

    ev_stop.terminal, ev_stop.direction = True, 1

    def done(segments, s_end, reason):
        return Integration(segments, s_end, reason, nfev, ode_method, rtol, atol, kfun,
                           r, L, B, C)

    segments, nfev = [], 0
    s0, y0 = 0.0, float(sc.y_of_alpha(alpha0))
    y_sw = float(y_switch)
    if y0 <= y_sw and ydot(s0, y0) < 0:
        mode, ydot_sw = "s(y)", float(ydot(s0, y0))
    else:
        mode = "y(s)"
        y_sw = y_sw if y0 > y_sw else 0.5 * y0
    for _ in range(50):
        if mode == "s(y)":

            def ev_turn(y, sv, ref=ydot_sw):  # dy/ds rising toward 0 (turning point ahead)
                return ydot(sv[0], y) - 0.5 * ref

            ev_turn.terminal, ev_turn.direction = True, 1
            sol = solve_ivp(fun_s, (y0, 0.0), [s0], method=ode_method, rtol=rtol,
                            atol=atol * L, events=(ev_turn, ev_stop), dense_output=True)
            nfev += sol.nfev
            if sol.status == -1:
                raise SingularityError(f"rough-helix ODE ({ode_method}, s(y)) failed: "
                                       f"{sol.message}")
            dense = sol.sol
            dense.y_start = y0
            if sol.t_events[1].size:  # reached s_stop
                dense.y_end = float(sol.t_events[1][0])
                segments.append(("s(y)", s0, s_stop, dense))
                return done(segments, s_stop, "s_stop")
            if sol.t_events[0].size:  # slope flattening: back to y(s), lower switch level
                dense.y_end = float(sol.t_events[0][0])
                s_end = float(sol.y_events[0][0][0])
                segments.append(("s(y)", s0, s_end, dense))
                s0, y0, mode, y_sw = s_end, dense.y_end, "y(s)", 0.5 * dense.y_end
                continue
            dense.y_end = 0.0
            s_end = float(sol.y[0, -1])
            segments.append(("s(y)", s0, s_end, dense))
            return done(segments, s_end, "alpha->0")

        def ev_switch(s, yv, level=y_sw):
            return yv[0] - level

        ev_switch.terminal, ev_switch.direction = True, -1
        sol = solve_ivp(fun_y, (s0, s_stop), [y0], method=ode_method, rtol=rtol, atol=atol,
                        events=(ev_zero, ev_sing, ev_switch), dense_output=True)
        nfev += sol.nfev
        if sol.status == -1:
            raise SingularityError(f"rough-helix ODE ({ode_method}) failed: {sol.message}")
        if sol.t_events[1].size:
            raise _singular(float(sol.t_events[1][0]), cos2a_min)
        if sol.t_events[0].size:
            s_end = float(sol.t_events[0][0])
            segments.append(("y(s)", s0, s_end, sol.sol))
            return done(segments, s_end, "alpha->0")
        if sol.t_events[2].size:
            s_sw = float(sol.t_events[2][0])
            segments.append(("y(s)", s0, s_sw, sol.sol))
            s0, y0, mode = s_sw, y_sw, "s(y)"
            ydot_sw = float(ydot(s0, y0))
            continue
        segments.append(("y(s)", s0, float(sol.t[-1]), sol.sol))
        return done(segments, float(sol.t[-1]), "s_stop")
    raise SingularityError("rough-helix ODE: more than 50 phase switches (alpha oscillating "
                           "around the switch threshold)")


# --- grids and profile columns -------------------------------------------------


def profile_grid(s_end, n_points=801, n_end=60, include_end=False):
    """Arclength grid on [0, s_end): uniform, plus points clustered toward s_end.

    The clustered points ``s_end (1 - q)``, q geometric from 1e-2 to 1e-7,
    resolve the square-root ending of alpha at s_max (alpha ~ sqrt(s_max - s)).
    The grid stops at ``s_max (1 - 1e-7)``: closer to the end alpha(s) is so
    ill-conditioned (d alpha/ds ~ 1/alpha) that no solver resolves it, and the
    slowly-varying-pitch model has long failed there (|e - 1| ~ 1e8). ``include_end`` adds
    s_end itself (use it when the end is not alpha = 0).
    """
    base = np.linspace(0.0, s_end, int(n_points))[:-1]
    tail = s_end * (1.0 - np.geomspace(1e-2, 1e-7, int(n_end))) if n_end else np.empty(0)
    grid = np.unique(np.concatenate([base, tail, [s_end] if include_end else []]))
    return grid[grid <= s_end]


#: Gauss-Legendre rules of :func:`cumulative_integrals` (8 points, and 4 for the error estimate).
_GL8 = np.polynomial.legendre.leggauss(8)
_GL4 = np.polynomial.legendre.leggauss(4)


def cumulative_integrals(fun, breaks, rtol=1e-12, max_depth=60, max_panels=20000):
    """Running integrals ``int_{b_0}^{b_j} f ds`` of a vector integrand at sorted breakpoints.

    Adaptive composite Gauss-Legendre quadrature: every panel between two
    breakpoints is integrated with 8 points; the 4-point rule gives a
    (pessimistic) error estimate. A panel is accepted when its estimate is below
    its share of ``rtol`` times the integral of ``|f|`` (in proportion to its
    width); the rest are halved, level by level, until the estimates of all
    panels together are below that budget (so rounding noise of the integrand
    does not force endless halving), at most ``max_depth`` times and while
    fewer than ``max_panels`` panels are pending. The 8-point rule is exact for
    polynomials of degree 15, so smooth integrands converge at once, and a jump
    of a twisting-rate callable is localised by the halving.

    Parameters
    ----------
    fun : callable
        ``fun(x) -> array (m, x.size)``, vectorised over a 1-D array x.
    breaks : array_like
        Strictly increasing breakpoints (1-D, at least one).

    Returns
    -------
    numpy.ndarray, shape (m, breaks.size)
        The integrals from ``breaks[0]``, 0 in the first column.
    """
    b = np.asarray(breaks, float)
    if b.size < 2:
        m = np.asarray(fun(b[:1])).shape[0]
        return np.zeros((m, b.size))
    x8, w8 = _GL8
    x4, w4 = _GL4
    lo, hi = b[:-1], b[1:]
    owner = np.arange(lo.size)
    span = b[-1] - b[0]
    totals = budget = spent = None
    for depth in range(max_depth + 1):
        half, mid = 0.5 * (hi - lo), 0.5 * (hi + lo)
        nodes = np.concatenate([(mid[:, None] + half[:, None] * x8).ravel(),
                                (mid[:, None] + half[:, None] * x4).ravel()])
        f = np.asarray(fun(nodes), float)
        m, n8 = f.shape[0], lo.size * 8
        f8 = f[:, :n8].reshape(m, lo.size, 8)
        i8 = (f8 @ w8) * half
        err = np.abs(i8 - (f[:, n8:].reshape(m, lo.size, 4) @ w4) * half)
        if totals is None:
            totals = np.zeros((m, b.size - 1))
            budget = rtol * np.sum((np.abs(f8) @ w8) * half, axis=1)
            spent = np.zeros(m)
        ok = np.all(err <= (budget / span)[:, None] * (hi - lo), axis=0)
        ok |= ~np.all(np.isfinite(i8), axis=0)  # NaN/inf: no refinement helps; caller checks
        if (depth == max_depth or np.count_nonzero(~ok) > max_panels
                or np.all(spent + err.sum(axis=1) <= budget)):
            ok[:] = True
        np.add.at(totals, (slice(None), owner[ok]), i8[:, ok])
        spent = spent + np.where(np.isfinite(err), err, 0.0)[:, ok].sum(axis=1)
        if np.all(ok):
            break
        lo, hi, owner = lo[~ok], hi[~ok], owner[~ok]
        mid = 0.5 * (lo + hi)
        lo, hi, owner = (np.concatenate([lo, mid]), np.concatenate([mid, hi]),
                         np.concatenate([owner, owner]))
    return np.concatenate([np.zeros((totals.shape[0], 1)), np.cumsum(totals, axis=1)], axis=1)


def strand_integrals(breaks, y_at, kfun, r, B, C):
    """``(int omega ds, int tau ds, int k(2s) ds)`` from s = breaks[0] at every breakpoint.

    ``y_at(s)`` gives ``y = 1 - cos 2 alpha`` along the helix and ``kfun(S)``
    the twisting rate (rad/m) at slack S. With these integrals (one strand,
    s from the head) [Eq Lk=Tw+Wr] at slack S = 2 s reads

        Tw = (1/pi) int_0^s omega + omega(s) (L - 2 s) / 2 pi,
        Wr = (1/pi) int_0^s tau,      N = N_0 + (1/pi) int_0^s k(2s') ds',

    and ``Tw + Wr = N`` holds for the exact solution of [eq da/ds] (its
    derivative is the ODE). See :func:`cumulative_integrals` for the quadrature.
    """

    def f(x):
        alpha = sc.alpha_of_y(y_at(x))
        k = np.broadcast_to(np.asarray(kfun(2.0 * x), float), x.shape)
        return np.vstack([sc.twist_density(alpha, r, B, C), torsion(alpha, r), k])

    return cumulative_integrals(f, breaks)


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


def first_crossing(s, g, g_at):
    """First s where ``g`` (tabulated on grid ``s``) turns positive, refined by brentq.

    ``g_at(s_scalar)`` evaluates the same function anywhere. Returns None if
    ``g <= 0`` on the whole grid, ``s[0]`` if already positive there: pass a
    grid that starts at the head, s = 0 (the caller's internal grid), or the
    onset of a helix that fails from its head would be reported at ``s[0] > 0``.
    """
    g = np.asarray(g, float)
    idx = np.flatnonzero(g > 0)
    if idx.size == 0:
        return None
    i = int(idx[0])
    if i == 0:
        return float(s[0])
    a, b = float(s[i - 1]), float(s[i])
    try:
        return float(brentq(g_at, a, b, xtol=1e-15, rtol=1e-13))
    except ValueError:  # sign change not reproduced by g_at (grid rounding)
        return b


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
