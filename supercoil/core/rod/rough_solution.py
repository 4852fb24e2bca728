"""The solution of the rough-helix ODE [eq da/ds]: integration in two phases, piecewise result.

Float-only kernel (SI: m, N m^2, rad). :func:`integrate` solves [eq da/ds] in
the regular variable ``y = 1 - cos 2 alpha`` (see :mod:`supercoil.core.rod.rough`
for the derivation) with ``solve_ivp`` and returns the solution as one object,
:class:`RoughSolution`, in the style of scipy's ``OdeSolution``: sorted segment
boundaries ``ts`` and one interpolant per segment, evaluated by segment lookup.

Every run is bounded: the right side counts its evaluations and a run that needs
more than ``max_nfev`` of them (default :data:`MAX_NFEV`) ends in a
:class:`~supercoil.exceptions.SingularityError` naming the twisting rate, the
slack reached and the solver; a solver failure, a turning point of ``y`` inside
an ``s(y)`` step and more than 50 phase switches are named errors too.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

from supercoil.core.numerics import bisect_increasing
from supercoil.core.rod import contact as sc
from supercoil.exceptions import NoHelixError, SingularityError, SupercoilError, ValidityError

#: Default ODE tolerances of :func:`integrate` (relative, absolute on y).
RTOL = 1e-10
ATOL = 1e-12
#: Default end of the integration when no terminal event fires: the tail keeps
#: this fraction of L (the ODE has a 1/(L - 2s) factor at S = L).
TAIL_FRACTION_MIN = 1e-6
#: Phase switch of :func:`integrate`: below this y (alpha ~ 0.022 rad), while y
#: decreases, the ODE is integrated as s(y) instead of y(s).
Y_SWITCH = 1e-3
#: Default budget of right-side evaluations of one :func:`integrate` run. Typical
#: runs take 50-3000 (k = 0: 50-1300 with DOP853; k = 5 rad/m: ~700 with LSODA);
#: 100 000 is about 30 times the longest typical run (reached with LSODA at
#: ``twist_rate = 1e300 rad/m``).
MAX_NFEV = 100_000


def dy_ds(s, y, k, r, L, B, C):
    """Right side of [eq da/ds] in ``y = 1 - cos 2a`` (1/m); ``k = k(2s)`` in rad/m.

    Implements docs/theory/rough.md (eq da/ds).

    ``dy/ds = -2C / (B (L - 2s)) c^2 / (c^2 + c + 1) [(2 - y) - 2 r k sqrt((2 - y)/y)]``
    with ``c = 1 - y``. The k = 0 part is smooth in y through y = 0 and is
    evaluated there as it is (trial stages of explicit solvers step to y < 0
    past the end s_max: clipping y at 0 put a kink into the right side, which
    spoiled the dense output of the step over s_max by up to 5e-7 relative in
    the position of y = 1e-3); only the ``y^(-1/2)`` k-term is guarded at y > 0,
    and y above 1.5 (beyond the alpha -> pi/4 event) is capped.
    """
    y = np.minimum(np.asarray(y, float), 1.5)
    k = np.asarray(k, float)
    c = 1.0 - y
    yk = np.clip(y, 1e-30, 1.5)
    bracket = (2.0 - y) - np.where(k == 0.0, 0.0, 2.0 * r * k * np.sqrt((2.0 - yk) / yk))
    return -2.0 * C / (B * (L - 2.0 * np.asarray(s, float))) * c * c / (c * c + c + 1.0) * bracket


def _dy_ds_scalar(s, y, k, r, L, B, C):
    """Scalar (math-module) twin of :func:`dy_ds` for the solver's right side."""
    y = min(y, 1.5)
    c = 1.0 - y
    bracket = 2.0 - y
    if k != 0.0:
        yk = min(max(y, 1e-30), 1.5)
        bracket -= 2.0 * r * k * math.sqrt((2.0 - yk) / yk)
    return -2.0 * C / (B * (L - 2.0 * s)) * c * c / (c * c + c + 1.0) * bracket


def nonfinite_rate(k, S):
    """The error for a non-finite twisting rate ``k`` (rad/m) at slack ``S`` (m)."""
    return ValidityError(
        f"twisting rate k = {k!r} rad/m at slack S = {float(S):.9g} m is not finite: "
        "[eq da/ds] is undefined there (twist_rate must be finite)"
    )


def _zero_rate(S):
    return np.zeros_like(np.asarray(S, float))


# --- the solution object (scipy OdeSolution style) --------------------------------


class YOfS:
    """Interpolant of a ``y(s)`` segment: scipy's dense output, called with s."""

    kind = "y(s)"

    def __init__(self, dense):
        self.dense = dense

    def __call__(self, s):
        return np.asarray(self.dense(s), float).reshape(-1, np.size(s))[0]


class InverseSOfY:
    """Interpolant of an ``s(y)`` segment: s(y) is monotone, inverted for y(s).

    The inversion is a safeguarded Newton iteration with the ODE's own slope
    ``ds/dy = 1 / (dy/ds)`` (at most 60 steps, then bisection on the bracket,
    at most 1100 halvings). Kept hand-written by measurement: inverting the
    last s(y) segment of the N_0 = 40 helix (r = 1 mm, L = 56.7 cm) at 2000
    points, scipy.optimize.elementwise.find_root takes 2.8x (k = 0) and 5.5x
    (k = -20 rad/m) the time of this Newton iteration, for the same y
    (1.5e-15 apart): Newton uses the ODE's slope, find_root only values.
    """

    kind = "s(y)"

    def __init__(self, dense, y_start, y_end, rate):
        self.dense, self.y_start, self.y_end, self._rate = dense, y_start, y_end, rate

    def s_of_y(self, y):
        return np.asarray(self.dense(y), float).reshape(-1, np.size(y))[0]

    def __call__(self, x):
        x = np.asarray(x, float)
        lo = np.full(x.shape, self.y_end)
        hi = np.full(x.shape, self.y_start)
        s_hi, s_lo = float(self.s_of_y(self.y_start)[0]), float(self.s_of_y(self.y_end)[0])
        t = np.clip((x - s_hi) / (s_lo - s_hi), 0.0, 1.0) if s_lo != s_hi else np.zeros(x.shape)
        y = self.y_start + t * (self.y_end - self.y_start)
        for _ in range(60):
            f = x - self.s_of_y(y)  # increasing in y
            hi = np.where(f > 0, y, hi)
            lo = np.where(f > 0, lo, y)
            with np.errstate(divide="ignore", invalid="ignore"):
                y_new = y + f * self._rate(x, y)  # Newton: d(x - s(y))/dy = -1/(dy/ds)
            bad = ~np.isfinite(y_new) | (y_new < lo) | (y_new > hi)
            y_new = np.where(bad, 0.5 * (lo + hi), y_new)
            if np.all(np.abs(y_new - y) <= 1e-15 + 1e-13 * np.abs(y)):
                return y_new
            y = y_new
        return bisect_increasing(lambda yy: x - self.s_of_y(yy), lo, hi)


class RoughSolution:
    """Piecewise dense solution ``y(s) = 1 - cos 2 alpha`` (scipy ``OdeSolution`` style).

    Attributes
    ----------
    ts : numpy.ndarray
        Segment boundaries in s (m), increasing, ``len(interpolants) + 1`` values;
        ``ts[0]`` = 0 (the head) and ``ts[-1]`` = s_end.
    interpolants : list
        One callable per segment, ``interp(s) -> y`` for s in its segment
        (:class:`YOfS`, :class:`InverseSOfY` or the k = 0 closed form); each
        has a ``kind`` (``"y(s)"``, ``"s(y)"``, ``"closed form"``).
    t_min, t_max : float
        ``ts[0]`` and ``ts[-1]``.

    Calling the object with s (scalar or array) finds each point's segment
    (:meth:`segment`, like ``OdeSolution``: a point on a boundary belongs to the
    segment on its right, the last boundary to the last segment) and evaluates
    that interpolant; results are clipped at y >= 0.
    """

    def __init__(self, ts, interpolants):
        self.ts = np.asarray(ts, float)
        self.interpolants = list(interpolants)
        if self.ts.ndim != 1 or self.ts.size != len(self.interpolants) + 1 or np.any(
                np.diff(self.ts) < 0):
            raise ValueError("RoughSolution: ts must increase, one more value than interpolants")
        self.t_min, self.t_max = float(self.ts[0]), float(self.ts[-1])

    @property
    def kinds(self):
        """The segments' kinds, in order."""
        return tuple(p.kind for p in self.interpolants)

    def segment(self, s):
        """Index of the segment of every s (array of int); NoHelixError outside [t_min, t_max]."""
        s = np.asarray(s, float)
        if np.any(~((s >= self.t_min) & (s <= self.t_max))):
            bad = float(s[~((s >= self.t_min) & (s <= self.t_max))].reshape(-1)[0])
            raise NoHelixError(f"s = {bad!r} m outside the integrated helix "
                               f"[{self.t_min:.9g}, {self.t_max:.9g} m]")
        idx = np.searchsorted(self.ts, s, side="right") - 1
        return np.clip(idx, 0, len(self.interpolants) - 1)

    def __call__(self, s):
        s = np.asarray(s, float)
        flat = s.reshape(-1)
        seg = self.segment(flat)
        out = np.empty(flat.shape)
        for i in np.unique(seg):
            m = seg == i
            out[m] = self.interpolants[i](flat[m])
        out = np.clip(out, 0.0, None).reshape(s.shape)
        return float(out) if out.ndim == 0 else out


# --- the integration ---------------------------------------------------------------


class _Rhs:
    """The right side of one run, counting its evaluations against the budget."""

    def __init__(self, kfun, r, L, B, C, max_nfev, ode_method):
        self.kfun, self.p, self.max_nfev, self.ode_method = kfun, (r, L, B, C), max_nfev, ode_method
        self.nfev, self.s_last = 0, 0.0

    def k(self, S):
        if self.kfun is None:
            return 0.0
        k = float(np.asarray(self.kfun(S)).reshape(-1)[0])
        if not math.isfinite(k):  # never integrate on: a NaN/inf k stalls the solver
            raise nonfinite_rate(k, S)
        return k

    def ydot(self, s, y):
        self.nfev += 1
        self.s_last = s = float(s)
        if self.nfev > self.max_nfev:
            raise self._budget_error(s)
        return _dy_ds_scalar(s, float(y), self.k(2.0 * s), *self.p)

    def _budget_error(self, s):
        k = self.k(2.0 * s)
        return SingularityError(
            f"rough-helix ODE ({self.ode_method}) stopped after {self.max_nfev} right-side "
            f"evaluations (its budget) at s = {s:.6g} m (slack S = {2 * s:.6g} m), where the "
            f"twisting rate is k = {k:.6g} rad/m (2 r k = {2 * self.p[0] * k:.3g}; a hard-"
            "contact helix needs sin 2 alpha = 2 r k <= 1 to follow it): the equation is too "
            "stiff there; use a smaller twist_rate, another ode_method ('LSODA', 'Radau') or "
            "a larger max_nfev")

    def fun_y(self, s, yv):
        return np.array([self.ydot(s, yv[0])])

    def fun_s(self, y, sv):
        d = self.ydot(sv[0], y)
        if d == 0.0:
            raise SingularityError(
                f"rough-helix ODE ({self.ode_method}, s(y)): dy/ds = 0 at s = {sv[0]:.6g} m, "
                f"y = {y:.3g} inside an s(y) step (a turning point of the tilt)")
        return np.array([1.0 / d])

    def dy(self, s, y):
        """Vectorised dy/ds along the solution (rate of the s(y) inversion)."""
        s = np.asarray(s, float)
        k = np.broadcast_to(np.asarray((self.kfun or _zero_rate)(2.0 * s), float), s.shape)
        if not np.all(np.isfinite(k)):
            bad = int(np.flatnonzero(~np.isfinite(k).reshape(-1))[0])
            raise nonfinite_rate(float(k.reshape(-1)[bad]), 2.0 * float(s.reshape(-1)[bad]))
        return dy_ds(s, y, k, *self.p)


class Integration:
    """Result of :func:`integrate`.

    Attributes
    ----------
    solution : RoughSolution
        y(s) on [0, s_end].
    s_end : float
        Last s (m): the helix end (``reason == "alpha->0"``) or ``s_stop``.
    reason : str
        ``"alpha->0"`` or ``"s_stop"``.
    nfev : int
        Right-side evaluations used.
    ode_method, rtol, atol
        The solver settings.
    """

    def __init__(self, solution, reason, rhs, rtol, atol):
        self.solution, self.reason = solution, reason
        self.s_end = solution.t_max
        self.nfev, self.ode_method, self.rtol, self.atol = rhs.nfev, rhs.ode_method, rtol, atol
        self._rhs = rhs

    def y(self, s):
        """y(s) (see :class:`RoughSolution`)."""
        return self.solution(s)

    def dy(self, s, y):
        """dy/ds (1/m) at s and y (the twisting rate is checked finite)."""
        return self._rhs.dy(s, y)


def _solve_ivp(rhs, fun, span, y0, **kw):
    """``solve_ivp`` whose raw failures (NaN/inf in an implicit solver's linear
    algebra, a zero division) become a named SingularityError."""
    try:
        sol = solve_ivp(fun, span, [y0], method=rhs.ode_method, dense_output=True, **kw)
    except SupercoilError:
        raise
    except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        raise SingularityError(
            f"rough-helix ODE ({rhs.ode_method}) failed near s = {rhs.s_last:.6g} m, where the "
            f"twisting rate is k = {rhs.k(2.0 * rhs.s_last):.6g} rad/m: {exc}") from exc
    if sol.status == -1:
        raise SingularityError(
            f"rough-helix ODE ({rhs.ode_method}) failed near s = {rhs.s_last:.6g} m, where the "
            f"twisting rate is k = {rhs.k(2.0 * rhs.s_last):.6g} rad/m: {sol.message}")
    return sol


def _event(fun, terminal, direction):
    fun.terminal, fun.direction = terminal, direction
    return fun


def _phase_s_of_y(rhs, s0, y0, ydot_sw, s_stop, rtol, atol, L):
    """s(y) from y0 down to 0: ``(interp, s_end, reason, y_end)``; reason None = back to y(s)."""
    ev_turn = _event(lambda y, sv: rhs.ydot(sv[0], y) - 0.5 * ydot_sw, True, 1)
    ev_stop = _event(lambda y, sv: sv[0] - s_stop, True, 1)
    sol = _solve_ivp(rhs, rhs.fun_s, (y0, 0.0), s0, rtol=rtol, atol=atol * L,
                     events=(ev_turn, ev_stop))
    if sol.t_events[1].size:  # reached s_stop
        y_end = float(sol.t_events[1][0])
        return InverseSOfY(sol.sol, y0, y_end, rhs.dy), s_stop, "s_stop", y_end
    if sol.t_events[0].size:  # slope flattening: a turning point ahead, back to y(s)
        y_end = float(sol.t_events[0][0])
        return InverseSOfY(sol.sol, y0, y_end, rhs.dy), float(sol.y_events[0][0][0]), None, y_end
    return InverseSOfY(sol.sol, y0, 0.0, rhs.dy), float(sol.y[0, -1]), "alpha->0", 0.0


def _phase_y_of_s(rhs, s0, y0, y_sw, s_stop, rtol, atol, cos2a_min):
    """y(s) from s0: ``(pieces, s_end, reason)``; reason None = switch to s(y) at y_sw.

    ``pieces`` is a list of ``(interpolant, s_right)``. When a terminal event
    (y = y_sw or y = 0) fires, the step that contains it is integrated again
    from its left node with at most 1/8 of its length per step: the dense
    output of one long step is not error-controlled between its nodes (a
    DOP853 step over [0.025, 0.16] m put y = 1e-3 1e-8 m off and alpha 1.6e-8
    rad off at 1e-7 s_max from the end, N_0 = 12.7, r = 0.42 mm, L = 2.64 m).
    """
    ev_zero = _event(lambda s, yv: yv[0], True, -1)
    ev_sing = _event(lambda s, yv: (1.0 - yv[0]) - cos2a_min, True, -1)
    ev_switch = _event(lambda s, yv: yv[0] - y_sw, True, -1)
    pieces, s_end, reason = [], s_stop, None
    for refine in (False, True):
        step = {"max_step": (s_end - s0) / 8.0} if refine else {}
        sol = _solve_ivp(rhs, rhs.fun_y, (s0, s_stop), y0, rtol=rtol, atol=atol,
                         events=(ev_zero, ev_sing, ev_switch), **step)
        if sol.t_events[1].size:
            s_sing = float(sol.t_events[1][0])
            raise SingularityError(
                f"tilt alpha -> pi/4 (cos 2 alpha < {cos2a_min:g}) at s = {s_sing:.6g} m "
                f"(slack S = {2 * s_sing:.6g} m): the tension diverges; the twisting rate "
                "k(S) is too large for a hard-contact helix")
        fired = [i for i in (0, 2) if sol.t_events[i].size]
        if not fired:
            pieces.append((YOfS(sol.sol), float(sol.t[-1])))
            return pieces, float(sol.t[-1]), "s_stop"
        s_end = float(sol.t_events[fired[0]][0])
        reason = "alpha->0" if fired[0] == 0 else None
        if refine or not s_end > s0:
            break
        if sol.t.size > 2:  # keep the accepted steps before the one with the event
            pieces.append((YOfS(sol.sol), float(sol.t[-2])))
            s0, y0 = float(sol.t[-2]), float(sol.y[0, -2])
    pieces.append((YOfS(sol.sol), s_end))
    return pieces, s_end, reason


def integrate(alpha0, kfun, r, L, B, C, s_stop=None, ode_method="DOP853",
              rtol=RTOL, atol=ATOL, cos2a_min=sc.COS2A_MIN, y_switch=Y_SWITCH,
              max_nfev=MAX_NFEV):
    """Integrate [eq da/ds] from s = 0 with ``solve_ivp``, in two phases.

    Phase "y(s)": y = 1 - cos 2 alpha versus s. Phase "s(y)": once y falls
    below ``y_switch`` while decreasing, ``ds/dy = 1 / (dy/ds)`` down to y = 0;
    near the end dy/ds is finite (k = 0) or diverges like ``y^(-1/2)`` (k < 0),
    so ds/dy is regular and s_max = s(y = 0) needs no event search on a
    singular right side. If dy/ds rises to half its value at the switch (a
    turning point ahead: k > 0 re-tilting the helix) it goes back to "y(s)"
    with the switch level halved.

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
        Last s if the helix does not end first; ``(L/2)(1 - TAIL_FRACTION_MIN)``.
    ode_method : str
        Any ``solve_ivp`` method ("RK45", "DOP853", "Radau", "LSODA", ...).
    rtol, atol : float
        Tolerances (defaults 1e-10, 1e-12): on y in phase "y(s)"; on s in
        phase "s(y)" with ``atol * L`` as absolute tolerance (metres).
    cos2a_min : float
        alpha -> pi/4 guard: terminal event at ``cos 2a = cos2a_min``.
    y_switch : float
        Phase switch threshold in y (default 1e-3).
    max_nfev : int
        Budget of right-side evaluations for the whole run (:data:`MAX_NFEV`).

    Returns
    -------
    Integration

    Raises
    ------
    SingularityError
        If the tilt reaches pi/4 (cos 2 alpha = cos2a_min) at some s, a solver
        fails (message from solve_ivp), the budget ``max_nfev`` is spent (the
        message names the twisting rate and the slack reached) or alpha
        oscillates across the switch level more than 50 times.
    ValidityError
        If the twisting rate is not finite at some slack (named).
    """
    if s_stop is None:
        s_stop = 0.5 * L * (1.0 - TAIL_FRACTION_MIN)
    rhs = _Rhs(kfun, r, L, B, C, int(max_nfev), ode_method)
    s0, y0, y_sw = 0.0, float(sc.y_of_alpha(alpha0)), float(y_switch)
    if y0 <= y_sw and rhs.ydot(s0, y0) < 0:
        mode, ydot_sw = "s(y)", float(rhs.ydot(s0, y0))
    else:
        mode, ydot_sw = "y(s)", None
        y_sw = y_sw if y0 > y_sw else 0.5 * y0
    ts, interps = [s0], []
    for _ in range(50):
        if mode == "s(y)":
            interp, s_end, reason, y0 = _phase_s_of_y(rhs, s0, y0, ydot_sw, s_stop, rtol,
                                                      atol, L)
            pieces = [(interp, s_end)]
            mode, y_sw = "y(s)", 0.5 * y0
        else:
            pieces, s_end, reason = _phase_y_of_s(rhs, s0, y0, y_sw, s_stop, rtol, atol,
                                                  cos2a_min)
            mode, y0 = "s(y)", y_sw
        for interp, s_right in pieces:
            interps.append(interp)
            ts.append(s_right)
        if reason is not None:
            return Integration(RoughSolution(ts, interps), reason, rhs, rtol, atol)
        s0 = s_end
        if mode == "s(y)":
            ydot_sw = float(rhs.ydot(s0, y0))
    raise SingularityError("rough-helix ODE: more than 50 phase switches (alpha oscillating "
                           "around the switch threshold)")
