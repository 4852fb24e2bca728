"""Uniform plectoneme at fixed tension for any interaction ``w(alpha, R)``.
Float-only SI kernel (docs/theory/plectoneme.md; docs/theory/screened-interaction.md#5).

Equations: :mod:`supercoil.core.dna.equilibrium_equations`.

Method
------
For each R, (GE2) is solved for alpha in (0, pi/4) by bracketed root finding
(``h < 0`` as alpha -> 0 for a repulsive interaction, ``w_R < 0``; ``h = X/2 > 0`` at
pi/4). The tension ``T(R)`` is tabulated on a log grid from the smallest allowed
radius ``r_min`` (the hard core) outwards; the physical branch runs from ``r_min`` to
the first grid point where T stops decreasing or falls to zero.

Each target tension is bracketed in that table (nodes k, k+1). ``method="newton"``
(default) solves the 2x2 system ``(h, T - F) = 0`` in ``(alpha, log R)`` by Newton,
vectorised over the forces, from a 4-point Lagrange interpolation in T through the
table, with forward-difference Jacobians (step 1e-7) kept fixed (chord steps) once a
step is below 1e-4, until both steps are below 1e-13 or two chord steps on one
Jacobian, of contraction ``rho = step_k / step_(k-1) < 1/2``, bound the error left,
``rho step_k / (1 - rho)``, below 1e-16. A result outside the bracket, or with
relative residuals above 1e-10, falls back to ``method="direct"`` (the reference):
``T(alpha(R), R) = T_target`` for ``log R`` by ``scipy.optimize.elementwise.find_root``
in the bracket, each evaluation solving (GE2) for alpha by the same routine. A force
equal to a node's tension is that node (both methods). The rules, the accuracy (the
two agree to 4.3e-14 over 5 mM-1 M, tested at 1e-10) and the cost (about 6
evaluations of the partials per force against 127-146 for the direct solve, the
measured factor for which hand-written Newton is kept; the fallback keeps scipy's
bracket guarantee): docs/theory/screened-interaction.md, section 8.

Errors: a force above ``T(r_min)`` would push R below the hard core (the strands would
pass through each other); a force below the branch's smallest tension has no
plectoneme state. Both raise :class:`~supercoil.exceptions.NoEquilibriumError`
naming the force.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from supercoil.core.dna.equilibrium_equations import (
    equilibrium_residuals,
    tension,
    tilt_residual,
    torque,
    xy_terms,
)
from supercoil.core.numerics import table_cubic
from supercoil.exceptions import NoEquilibriumError

__all__ = [
    "T_FLOOR",
    "Branch",
    "branch_table",
    "equilibrium_residuals",
    "grid_end_of",
    "solve_equilibrium",
    "solve_tilt",
    "tension",
    "tilt_residual",
    "torque",
]

_ALPHA_LO = 1e-9
_ALPHA_HI = 0.25 * np.pi
_TABLE_POINTS = 241
#: smallest tabulated tension (N) of a branch on which T only tends to zero
T_FLOOR = 1e-15
_FD_STEP = 1e-7  # forward-difference step of the Newton Jacobian (rad, and in log R)
_NEWTON_TOL = 1e-13  # last Newton step (rad, and in log R) below which it has converged
_NEWTON_MAXITER = 12
_CHORD_STEP = 1e-4  # after a step below this the Jacobian is kept (chord iteration)
_CHORD_ERROR = 1e-16  # chord error bound (rad, and in log R) below which it has converged
_RESIDUAL_TOL = 1e-10  # relative residuals of (GE2) and the tension accepted at the end
_TILT_SLACK = 1e-3  # rad: Newton's tilt may leave the bracket's tilts by this (an extremum)


class Branch(NamedTuple):
    """Tabulated physical branch: radii (m), tilts (rad), tensions (N), decreasing T."""

    radius: np.ndarray
    alpha: np.ndarray
    tension: np.ndarray
    ends_at_zero: bool  # True if T reaches 0 on the grid (else the grid ran out)
    fold: bool  # True if the branch starts at a maximum of T (not at the hard core)


def solve_tilt(R, B, partials, strict=True):
    """The root alpha in (0, pi/4) of (GE2) at each radius R (bracketed, to rounding).

    Where ``h`` does not change sign on (0, pi/4) (no repulsion left, e.g. far beyond
    the Debye length without confinement) this raises, or with ``strict=False``
    returns NaN there.
    """
    R = np.asarray(R, dtype=float)
    lo = np.full(R.shape, _ALPHA_LO)
    hi = np.full(R.shape, _ALPHA_HI)
    h_lo = tilt_residual(lo, R, B, partials)
    h_hi = tilt_residual(hi, R, B, partials)
    bad = ~((h_lo < 0) & (h_hi > 0))
    if strict and np.any(bad):
        r = R[bad].flat[0]
        raise NoEquilibriumError(
            f"no plectoneme tilt in (0, 45 deg) solves (GE2) at R = {r * 1e9:.6g} nm "
            "(the interaction is not repulsive there)"
        )
    from scipy.optimize.elementwise import find_root

    res = find_root(lambda a, r: tilt_residual(a, r, B, partials), (lo, hi), args=(R,),
                    tolerances=dict(xatol=1e-16, xrtol=1e-15), maxiter=200)
    return np.where(bad, np.nan, res.x)


def _tilt_near(R, a0, B, partials):
    """Root of (GE2) in alpha near ``a0`` by Newton (forward-difference slope), or by
    :func:`solve_tilt` where Newton leaves (0, pi/4) or does not settle in 8 steps."""
    a = np.full(np.shape(R), a0, dtype=float)
    for _ in range(8):
        h = tilt_residual(np.stack([a, a + _FD_STEP]), np.stack([R, R]), B, partials)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = -h[0] * _FD_STEP / (h[1] - h[0])
        a = a + step
        if not np.all(np.isfinite(a) & (a > 0.0) & (a < _ALPHA_HI)):
            break
        if np.all(np.abs(step) < _NEWTON_TOL):
            return a
    return solve_tilt(R, B, partials)


def _peak(B, partials, u, alpha0=None):
    """Refined maximum of T(log R) bracketed by the three grid points ``u``.

    With ``alpha0`` (the tilt at ``u[1]``) each evaluation's tilt is found by Newton
    from it (:func:`_tilt_near`; about ten times faster than the bracketed solve at
    10 mM), else by :func:`solve_tilt`.
    """
    def neg_t(x):
        R = np.exp(x)
        a = solve_tilt(R, B, partials) if alpha0 is None else _tilt_near(R, alpha0, B,
                                                                          partials)
        return -tension(a, R, B, partials)

    from scipy.optimize.elementwise import find_minimum

    res = find_minimum(neg_t, (u[0], u[1], u[2]), tolerances=dict(xatol=1e-12, xrtol=0.0))
    R = float(np.exp(res.x))
    a = float(solve_tilt(R, B, partials))
    return R, a, float(tension(a, R, B, partials))


def branch_table(B, partials, r_min, r_max, points=_TABLE_POINTS, t_floor=T_FLOOR,
                 grid_end=None):
    """Tabulate the stable branch ``T(R)`` between ``r_min`` and ``r_max`` (module doc).

    The branch starts at ``r_min`` if T decreases there, else at the first maximum of
    T (a fold: closer in, T rises with R and the state is unstable; above that
    maximum no plectoneme state exists). It ends where T stops decreasing, falls to
    zero, or (GE2) has no root any more; where T only tends to zero as R grows (no
    confinement) the table stops below ``t_floor`` (N, default 1 fN: far below any
    tweezers force, where the screened repulsion has died out numerically).

    ``grid_end`` (optional, e.g. :func:`grid_end_of` a table of nearby parameters): solve
    the grid's first ``grid_end`` radii only, and the whole grid only if the branch does
    not end inside them. The table is the same bit for bit (each radius's tilt is its
    own bracketed solve, and the end is the first radius where T stops decreasing).

    Raises
    ------
    NoEquilibriumError
        If no decreasing, positive stretch of T(R) exists on the grid.
    """
    grid = np.geomspace(r_min, r_max, points)
    if grid_end is not None and 2 <= grid_end < points:
        found = _branch_on(grid[:grid_end], B, partials, r_min, r_max, inside=True)
        if found is not None:
            return _finish(found, B, partials, r_min, t_floor)
    return _finish(_branch_on(grid, B, partials, r_min, r_max), B, partials, r_min, t_floor)


def grid_end_of(branch, r_min, r_max, points=_TABLE_POINTS, margin=8, t_floor=T_FLOOR):
    """The ``grid_end`` of :func:`branch_table` for parameters near those of ``branch``:
    ``margin`` radii past its last one (the grid spacing is 2.9 % for 241 radii over a
    factor 1000; a fit's steps in B move the end by a radius or two). None for a branch
    cut where T fell below ``t_floor``: whether T crosses zero further out, which would
    end it there instead, only the whole grid tells."""
    if not branch.ends_at_zero and branch.tension[-1] < t_floor:
        return None
    ratio = (r_max / r_min) ** (1.0 / (points - 1))
    last = round(math.log(branch.radius[-1] / r_min) / math.log(ratio))
    return last + 1 + margin


def _branch_on(R, B, partials, r_min, r_max, inside=False):
    """The decreasing stretch ``(R, alpha, T, j, ends_at_zero)`` of T on the radii R, its
    first point j; None with ``inside`` where T still decreases at the last radius (the
    radii a first part of the grid: the whole grid's branch may go on)."""
    alpha = solve_tilt(R, B, partials, strict=False)
    T = tension(alpha, R, B, partials)
    size = R.size
    n = int(np.argmax(~np.isfinite(T))) if not np.all(np.isfinite(T)) else T.size
    R, alpha, T = R[:n], alpha[:n], T[:n]
    dec = np.diff(T) < 0.0
    if not np.any(dec):
        if inside and n == size:
            return None
        raise NoEquilibriumError(
            f"no stable plectoneme branch between R = {r_min * 1e9:.6g} and "
            f"{r_max * 1e9:.6g} nm: the tension never decreases with R")
    j = int(np.argmax(dec))  # first point after which T decreases
    stop = np.nonzero(~dec[j:] | (T[j + 1:] <= 0.0))[0]
    if inside and n == size and not stop.size:
        return None  # T still decreases at the last radius solved: the end lies beyond
    # (a stop, or a non-finite T, inside the radii solved ends the whole grid's branch there)
    k = j + 1 + (stop[0] if stop.size else T.size - 1 - j)
    ends_at_zero = bool(k < T.size and T[k] <= 0.0)
    if ends_at_zero:  # keep the first point with T <= 0 as the bracket's end
        k += 1
    return R[j:k], alpha[j:k], T[j:k], j, ends_at_zero


def _finish(found, B, partials, r_min, t_floor):
    """:func:`branch_table`'s :class:`Branch` from the stretch :func:`_branch_on` found."""
    R, alpha, T, j, ends_at_zero = found
    if not ends_at_zero and T[-1] < t_floor:
        keep = max(int(np.argmax(T < t_floor)) + 1, 2)
        R, alpha, T = R[:keep], alpha[:keep], T[:keep]
    fold = j > 0
    if fold:  # replace the first point by the refined maximum of T
        u = np.log([r_min if j == 1 else R[0] / (R[1] / R[0]), R[0], R[1]])
        R = R.copy()
        alpha = alpha.copy()
        T = T.copy()
        R[0], alpha[0], T[0] = _peak(B, partials, u, alpha[0])
    if T[0] <= 0.0 or R.size < 2:
        raise NoEquilibriumError("no stable plectoneme branch with positive tension")
    for arr in (R, alpha, T):
        arr.setflags(write=False)
    return Branch(R, alpha, T, ends_at_zero, fold)


def _no_state(force, covered, branch, contact):
    """NoEquilibriumError naming the first force no branch covers."""
    bad = ~covered
    if not np.any(bad):
        return
    f = force[bad].flat[0]
    T_max = branch.tension[0]
    T_min = 0.0 if branch.ends_at_zero else branch.tension[-1]
    head = f"no plectoneme equilibrium at force {f * 1e12:.6g} pN: "
    if f <= 0.0:
        raise NoEquilibriumError(head + "the tension must be positive")
    if f <= T_min:
        raise NoEquilibriumError(
            head + f"below {T_min * 1e12:.6g} pN the plectoneme radius leaves the tabulated "
            f"range (R > {branch.radius[-1] * 1e9:.6g} nm)")
    if contact is not None:  # pragma: no cover - the contact branch reaches T -> inf
        raise NoEquilibriumError(head + "outside the free and the contact branch")
    if branch.fold:
        raise NoEquilibriumError(
            head + f"above {T_max * 1e12:.6g} pN (the largest tension of the stable branch, "
            f"at R = {branch.radius[0] * 1e9:.6g} nm) the repulsion cannot hold the strands "
            "apart; they would be pressed together onto the hard core (no contact state "
            "allowed)")
    raise NoEquilibriumError(
        head + f"above {T_max * 1e12:.6g} pN the superhelix radius would fall below the "
        f"hard-core radius {branch.radius[0] * 1e9:.6g} nm (the strands would pass through "
        "each other; no contact state allowed)")


def _solve_free_direct(flat, B, partials, branch, xatol):
    """Reference: nested bracketed solve, T(alpha(R), R) = F for log R (module doc)."""
    T_t = branch.tension
    k = np.clip(np.searchsorted(-T_t, -flat, side="left") - 1, 0, T_t.size - 2)
    u_lo = np.log(branch.radius[k])
    u_hi = np.log(branch.radius[k + 1])

    def g(u, target):
        R = np.exp(u)
        a = solve_tilt(R, B, partials)
        return tension(a, R, B, partials) - target

    # within rounding of a node's tension, T recomputed at the node (exp(log R) a few ulp
    # off) may lie on the wrong side: no sign change, the root is that node
    g_lo, g_hi = g(u_lo, flat), g(u_hi, flat)
    inside = (g_lo >= 0.0) & (g_hi <= 0.0)
    u = np.where(np.abs(g_lo) <= np.abs(g_hi), u_lo, u_hi)
    if np.any(inside):
        from scipy.optimize.elementwise import find_root

        res = find_root(g, (u_lo[inside], u_hi[inside]), args=(flat[inside],),
                        tolerances=dict(xatol=xatol, xrtol=0.0), maxiter=200)
        if not np.all(res.success):  # pragma: no cover - bracketed, cannot fail
            raise NoEquilibriumError("plectoneme equilibrium: root finding did not converge")
        u[inside] = res.x
    R = np.exp(u)
    alpha = solve_tilt(R, B, partials)
    return alpha, R, torque(alpha, R, B, partials)


def _h_t_m(alpha, R, B, partials):
    """``(h, T, M, scale of h, w)`` at (alpha, R) from one call of ``partials``."""
    X, Y, w, kappa = xy_terms(alpha, R, B, partials)
    s2, c2 = np.sin(2.0 * alpha), np.cos(2.0 * alpha)
    h = 0.5 * s2 * X + R * c2 * Y
    M = R * X / c2
    T = -0.5 * B * kappa * kappa + M * 0.5 * s2 / R - w
    return h, T, M, np.abs(0.5 * s2 * X) + np.abs(R * c2 * Y), w


def _start(flat, branch, k):
    """Start ``(alpha, log R)``: 4-point Lagrange interpolation in T through the table
    nodes around the bracket ``k`` (:func:`~supercoil.core.numerics.table_cubic`),
    log R clipped into the bracket."""
    T_t, a_t, u_t = branch.tension, branch.alpha, np.log(branch.radius)
    u, a = table_cubic(flat, k, T_t, u_t, a_t)
    return a, np.clip(u, u_t[k], u_t[k + 1])


def _solve_free_newton(flat, B, partials, branch):
    """Newton on ``(h, T - F) = 0`` in ``(alpha, log R)`` (module doc, Method).

    Returns ``(alpha, R, M, w, ok)`` (``w`` the interaction at the state, from the last
    evaluation); where ``ok`` is False the iteration left the table's
    bracket or did not converge, and the caller falls back to the direct solve.
    """
    T_t, a_t, u_t = branch.tension, branch.alpha, np.log(branch.radius)
    k = np.clip(np.searchsorted(-T_t, -flat, side="left") - 1, 0, T_t.size - 2)
    a, u = _start(flat, branch, k)
    n = flat.size
    live = np.arange(n)
    done = np.zeros(n, bool)
    jac = np.zeros((4, n))  # h_a, h_u, g_a, g_u (forward differences)
    fresh = np.ones(n, bool)  # a new Jacobian at the next step (else the last one: chord)
    last = np.full(n, np.inf)  # the last step, where it was a chord step (else inf)
    for _ in range(_NEWTON_MAXITER):
        if live.size == 0:
            break
        al, ul, F = a[live], u[live], flat[live]
        m, nj = live.size, live[fresh[live]]
        aj, uj = a[nj], u[nj]
        A = np.concatenate([al, aj + _FD_STEP, aj])
        U = np.concatenate([ul, uj, uj + _FD_STEP])
        with np.errstate(all="ignore"):  # a wild iterate is caught below (fallback)
            h, T = _h_t_m(A, np.exp(U), B, partials)[:2]
        h0, g0 = h[:m], T[:m] - F
        base = fresh[live]
        c = nj.size
        jac[0, nj] = (h[m:m + c] - h0[base]) / _FD_STEP
        jac[1, nj] = (h[m + c:] - h0[base]) / _FD_STEP
        jac[2, nj] = (T[m:m + c] - T[:m][base]) / _FD_STEP
        jac[3, nj] = (T[m + c:] - T[:m][base]) / _FD_STEP
        h_a, h_u, g_a, g_u = jac[:, live]
        with np.errstate(divide="ignore", invalid="ignore"):
            det = h_a * g_u - h_u * g_a
            da = -(g_u * h0 - h_u * g0) / det
            du = -(h_a * g0 - g_a * h0) / det
        a[live] = al + da
        u[live] = ul + du
        # leaving the bracket (by more than its width) or (0, pi/4): the direct solve
        kl = k[live]
        width = u_t[kl + 1] - u_t[kl]
        bad = ~(np.isfinite(da) & np.isfinite(du) & (a[live] > 0.0) & (a[live] < _ALPHA_HI)
                & (u[live] > u_t[kl] - width) & (u[live] < u_t[kl + 1] + width))
        step = np.maximum(np.abs(da), np.abs(du))
        # two chord steps on one Jacobian: contraction rho = step / last, the error left
        # after this step is below rho step / (1 - rho)
        rho = step / last[live]  # 0 after a fresh step (last = inf): no estimate
        conv = (step < _NEWTON_TOL) | ((rho > 0.0) & (rho < 0.5)
                                       & (rho * step <= _CHORD_ERROR * (1.0 - rho)))
        last[live] = np.where(base, np.inf, step)
        fresh[live] = step > _CHORD_STEP
        done[live[conv & ~bad]] = True
        live = live[~(conv | bad)]
    R = np.exp(u)
    with np.errstate(all="ignore"):  # forces not done are not used (fallback)
        h, T, M, h_scale, w = _h_t_m(a, R, B, partials)
        span = np.abs(a_t[k + 1] - a_t[k]) + _TILT_SLACK
        ok = (done & (u >= u_t[k] - 1e-12) & (u <= u_t[k + 1] + 1e-12)
              & (a > 0.0) & (a < _ALPHA_HI)
              & (a >= np.minimum(a_t[k], a_t[k + 1]) - span)
              & (a <= np.maximum(a_t[k], a_t[k + 1]) + span)
              & (np.abs(h) <= _RESIDUAL_TOL * h_scale)
              & (np.abs(T - flat) <= _RESIDUAL_TOL * np.abs(flat)))
    return a, R, M, w, ok


def _solve_free(flat, B, partials, branch, xatol, method):
    """``(alpha, R, M, w)`` on the free branch; ``w`` NaN where the solve did not
    evaluate the interaction at the state (nodes, the direct solve)."""
    alpha, R, M = np.empty(flat.shape), np.empty(flat.shape), np.empty(flat.shape)
    w = np.full(flat.shape, np.nan)
    # a force equal to a node's tension is that node: recomputed there, T may lie a few
    # ulp on the wrong side of the target and the node's bracket hold no sign change
    # (the direct solve failed there); the fold's first node is also a double root
    T_t = branch.tension
    j = np.minimum(np.searchsorted(-T_t, -flat, side="left"), T_t.size - 1)
    node = T_t[j] == flat
    if np.any(node):
        alpha[node], R[node] = branch.alpha[j[node]], branch.radius[j[node]]
        M[node] = torque(alpha[node], R[node], B, partials)
    rest = ~node
    if method == "direct":
        alpha[rest], R[rest], M[rest] = _solve_free_direct(flat[rest], B, partials, branch,
                                                           xatol)
        return alpha, R, M, w
    a, r, m, e, ok = _solve_free_newton(flat[rest], B, partials, branch)
    if not np.all(ok):  # safeguard: the bracketed reference where Newton failed
        a[~ok], r[~ok], m[~ok] = _solve_free_direct(flat[rest][~ok], B, partials, branch,
                                                    xatol)
        e[~ok] = np.nan
    alpha[rest], R[rest], M[rest], w[rest] = a, r, m, e
    return alpha, R, M, w


def solve_equilibrium(force, B, partials, branch, contact=None, xatol=1e-14, method="newton",
                      energy=False):
    """``(alpha, R, M)`` of the uniform plectoneme at each tension (arrays like force),
    with ``energy=True`` ``(alpha, R, M, w)``.

    Implements docs/theory/plectoneme.md (GE1, GE2).

    Each force is solved on the free branch (if it lies in its range) and on the contact
    branch R = a (:mod:`supercoil.core.dna.contact`, if given and the force lies in its
    range); where both exist the state of lower torque is the equilibrium (module
    docstring of :mod:`supercoil.core.dna.contact`).

    Parameters
    ----------
    force : array
        Tensions T (N), positive, finite.
    B : float
        Bending rigidity (N m^2).
    partials : callable
        ``partials(alpha, R) -> (w, w_alpha, w_R)`` (J/m, J/m, J/m^2), elementwise.
    branch : Branch
        From :func:`branch_table` for the same B and interaction.
    contact : ContactBranch or None
        From :func:`supercoil.core.dna.contact.contact_table`; None: no contact states
        (forces beyond the free branch raise).
    xatol : float
        Absolute tolerance on log R of the direct solve.
    method : {"newton", "direct"}
        ``"newton"`` (default): Newton on the 2x2 system from the table, falling back to
        the direct solve where it fails; ``"direct"``: the nested bracketed solve, the
        reference (module docstring, Method).
    energy : bool
        Also return the interaction ``w = partials(alpha, R)[0]`` (J/m) at the states:
        Newton's last evaluation, where it has one (the same floats as a new call),
        else one call of ``partials`` on the remaining states.

    Raises
    ------
    NoEquilibriumError
        Naming the force (module docstring).
    """
    from supercoil.core.dna import contact as _ct

    if method not in ("newton", "direct"):
        raise ValueError(f"method must be 'newton' or 'direct', got {method!r}")
    force = np.asarray(force, dtype=float)
    if not np.all(np.isfinite(force)):
        raise ValueError(f"force must be finite, got {force!r}")
    flat = force.ravel()
    T_min = 0.0 if branch.ends_at_zero else branch.tension[-1]
    free = (flat > T_min) & (flat <= branch.tension[0])
    touch = np.zeros(flat.shape, bool) if contact is None else (
        (flat >= contact.tension[0]) & (flat <= contact.tension[-1]))
    _no_state(flat, free | touch, branch, contact)
    alpha = np.empty(flat.shape)
    R = np.empty(flat.shape)
    M = np.full(flat.shape, np.inf)
    w = np.full(flat.shape, np.nan)
    if np.any(free):
        alpha[free], R[free], M[free], w[free] = _solve_free(flat[free], B, partials, branch,
                                                             xatol, method)
    if np.any(touch):
        a_c, M_c = _ct.solve_contact(flat[touch], B, partials, contact)
        better = M_c < M[touch]  # the lower torque is the equilibrium
        idx = np.flatnonzero(touch)[better]
        alpha[idx], R[idx], M[idx], w[idx] = a_c[better], contact.radius, M_c[better], np.nan
    out = (alpha.reshape(force.shape), R.reshape(force.shape), M.reshape(force.shape))
    if not energy:
        return out
    miss = np.isnan(w)
    if np.any(miss):
        w[miss] = partials(alpha[miss], R[miss])[0]
    return (*out, w.reshape(force.shape))
