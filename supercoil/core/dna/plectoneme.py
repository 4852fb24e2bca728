"""Plectoneme equilibrium of DNA at fixed force (docs/theory/plectoneme.md). Float-only kernel.

Equations
---------
For a uniform double helix of tilt alpha and radius R with the Marko-Siggia
interaction ``w`` (:mod:`supercoil.core.dna.marko_siggia`), stationarity of the
energy [Eq Ep1] gives (docs/theory/plectoneme.md#equations)

* (GE1) ``C omega = (B kappa kappa_alpha + w_alpha) / tau_alpha``  (the torque M_3),
* (GE2) ``tau_R (B kappa kappa_alpha + w_alpha) - tau_alpha (B kappa kappa_R + w_R) = 0``,
* tension ``T = -(1/2) B kappa^2 + C omega tau - w``.

Eliminating ``C omega`` with (GE1) leaves two equations in (alpha, R) that do
not contain C: the torque ``M_3 = C omega`` and the geometry at a given force
are independent of C; only ``omega = M_3 / C`` depends on it.

Reduced form
------------
With ``rho = R/r0``, ``b = B/(kT r0)``, ``beta = b^(-1/3)``, ``t = tan(alpha)/pi``,
``s = sin alpha``, ``c2 = cos 2alpha``, and using ``(sin 2alpha / 2) t_alpha = t``,
``-rho^4 x (GE2)`` simplifies to

    h(alpha, rho) = b s^4 + 12 rho^-10 g2(alpha) + (2/3) beta rho^(4/3) g1(alpha) = 0,
    g1 = 2 s^2 t^(2/3) - c2,   g2 = 2 s^2 t^12 - c2,

(the bending terms collapse to ``b s^4``), and the tension (in kT/r0) to

    T' = b s^4 (2 + c2) / (2 c2 rho^2) + rho^-12 q2 + beta rho^(-2/3) q1,
    q2 = 12 t^12 / c2 - 1 - t^12,   q1 = (2/3) t^(2/3) / c2 - 1 - t^(2/3).

The bending part of T' is the rough-surface tension [eq tension] at R = rho.
The torque is ``M_3 / kT = (b s^2 sin 2alpha / rho + rho w'_alpha) / c2``.
The reduced problem depends on the single number b, so its solution curve is
computed once per b and cached.

Branches and the physical solution
----------------------------------
``h`` is strictly increasing in alpha on (0, pi/4) (``s^4``, g1 and g2 all
increase), negative at alpha -> 0 and positive at alpha = pi/4, and for
alpha >= pi/4 every term is positive. Hence for **every** rho > 0 (GE2) has
exactly one root ``alpha(rho)`` in (0, pi/4): the (GE2) solution set is one
curve, parametrised by rho. Read as a function of alpha it has two branches
(a hard-core branch rho ~ 1 and an entropic branch where rho grows without
bound as alpha -> alpha_1 ~ 37 deg), which meet at a fold in alpha.

Along the curve ``dT = tau dM_3`` (the equilibrium is a stationary point of
``f = B kappa^2/2 + w - M_3 tau`` at fixed torque and ``T = -f``). Going out in
rho, T' decreases monotonically from +infinity (rho -> 0, alpha -> pi/4) through
zero at ``rho_0`` (1.65 for the seed set b = 27.4) to a minimum (a cusp where
the torque M_3 turns, the stability limit of the minimum of f), and then rises
towards 0 from below as rho -> infinity (``T' ~ -rho^(-2/3) / (6 s^2)``). So
every positive force has exactly one solution, on the monotone part
``rho < rho_0``, which is the minimum of f at its torque (the stable
plectoneme); the entropic branch carries only negative tensions. The solver
tabulates T'(rho) on ``[RHO_MIN, rho_0]`` once per b, brackets each force in
that table, and solves ``T'(alpha(rho), rho) = T'`` for ``log rho`` by a
safeguarded Newton iteration (Newton steps that leave the bracket are
replaced by bisection), each step solving (GE2) for alpha by a safeguarded
Newton iteration in the bracket (0, pi/4). No starting guess is needed. A few
forces (up to 12) are solved one by one on Python floats, started from the
table of b rounded to 10 % in log b and bracketed by the whole branch, so that
a fit moving r0 builds one table per 10 % of b instead of one per step. The
reduced equations themselves are in :mod:`supercoil.core.dna.hard_core_equations`.

Limits: the force must be positive (no plectoneme is held at T <= 0), and the
table stops at ``rho = RHO_MIN = 0.5`` (strands overlapping to half the
hard-core radius, T above ~1e5 pN for the seed set): beyond that force
:class:`~supercoil.exceptions.NoEquilibriumError` is raised.
"""

from __future__ import annotations

import math
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from supercoil.core import geometry as _g
from supercoil.core.blocks import in_blocks
from supercoil.core.dna import hard_core_equations as _r
from supercoil.core.dna import marko_siggia as _ms
from supercoil.core.dna.hard_core_equations import (
    reduced_ge2,
    reduced_tension,
    reduced_tilt,
    reduced_torque,
)
from supercoil.core.numerics import safe_newton as _safe_newton
from supercoil.core.numerics import table_cubic
from supercoil.exceptions import NoEquilibriumError

__all__ = [
    "EQUILIBRIUM_RTOL",
    "RHO_MIN",
    "PlectonemeState",
    "equilibrium",
    "hard_core_residuals",
    "reduced_branch_table",
    "reduced_ge2",
    "reduced_tension",
    "reduced_tilt",
    "reduced_torque",
]

#: smallest reduced radius R/r0 of the tabulated branch (sets the largest force)
RHO_MIN = 0.5
#: Default step tolerance (on log R) of the equilibrium's Newton iteration. The
#: iteration converges quadratically, so once a step is below 1e-8 the next
#: error is at rounding level: the work-precision benchmark (supercoil bench)
#: measures the same 4e-16 relative error in (alpha, R) at 1e-8 as at 1e-12
#: against an independent MINPACK solve, for ~15 % less time.
EQUILIBRIUM_RTOL = 1e-8
_SCALAR_LOOP_MAX = 12
#: Forces solved together: larger inputs are processed in blocks of this size (8192: as
#: fast as one block of 1e6 and ~2 MB of temporaries)
BLOCK = 8192


class PlectonemeState(NamedTuple):
    """Plectoneme equilibrium at given forces, SI floats (arrays of the force's shape)."""

    force: np.ndarray  # N
    alpha: np.ndarray  # rad
    radius: np.ndarray  # m
    pitch: np.ndarray  # m
    omega: np.ndarray  # 1/m (twist density in the helix, = torque / C)
    torque: np.ndarray  # N m (M_3 = C omega)
    curvature: np.ndarray  # 1/m
    torsion: np.ndarray  # 1/m
    bending_energy: np.ndarray  # J/m per strand length: B kappa^2 / 2
    twist_energy: np.ndarray  # J/m: C omega^2 / 2
    interaction_energy: np.ndarray  # J/m: w


#: step in log b of the tables that start scalar solves (see :func:`_solve_scalar`)
_START_TABLE_STEP = 0.1
#: upper end of the tabulated radii (R/r0): the tension is negative there for every b
_RHO_TABLE_MAX = 1e4
#: the whole branch in u = log rho: where a joint Newton step must stay
_U_BRANCH = (math.log(RHO_MIN), math.log(_RHO_TABLE_MAX))


@lru_cache(maxsize=64)
def reduced_branch_table(b):
    """Tabulated physical branch ``(rho, alpha, T')`` for ``b = B/(kT r0)``.

    ``rho`` runs from :data:`RHO_MIN` out to the first grid point with
    ``T' <= 0``; ``T'`` is strictly decreasing on it (checked).
    """
    rho = np.geomspace(RHO_MIN, _RHO_TABLE_MAX, 600)
    alpha = reduced_tilt(rho, b)
    T = reduced_tension(alpha, rho, b)
    nonpos = np.nonzero(T <= 0.0)[0]
    if nonpos.size == 0 or nonpos[0] == 0:
        raise NoEquilibriumError(
            f"no plectoneme branch with positive tension for B/(kT r0) = {b:.6g}"
        )
    k = nonpos[0] + 1
    rho, alpha, T = rho[:k], alpha[:k], T[:k]
    if not np.all(np.diff(T) < 0):
        raise NoEquilibriumError(
            f"the plectoneme tension is not monotone in R for B/(kT r0) = {b:.6g}"
        )
    for arr in (rho, alpha, T):
        arr.setflags(write=False)
    return rho, alpha, T


@lru_cache(maxsize=256)
def _largest_tension(b):
    """``T'`` at :data:`RHO_MIN`, the largest reduced tension held (a table's first entry).

    One scalar tilt solve, no table; NoEquilibriumError as :func:`reduced_branch_table`
    if no positive tension is held.
    """
    beta = b ** (-1.0 / 3.0)
    a = _r.scalar_tilt(0.5, RHO_MIN, b, beta)
    T = _r.scalar_ge2_tension(a, RHO_MIN, b, beta)[3]
    if not T > 0.0:
        raise NoEquilibriumError(
            f"no plectoneme branch with positive tension for B/(kT r0) = {b:.6g}"
        )
    return T


def _start_table(b):
    """The table that starts a scalar solve at ``b``: the branch of ``b`` rounded to a
    grid of step :data:`_START_TABLE_STEP` in log b (within 5 %).

    A fit moves r0, hence b, a little at every step and every Jacobian column; a
    table costs 600 tilt solves, about 25 scalar solves, and a new molecule's fit
    built 12 of them (about 40 % of its time). One table
    per 10 % of b serves them all; the start (hence the result, to the last bit)
    depends on b alone, not on which tables earlier calls built.
    """
    step = _START_TABLE_STEP
    return reduced_branch_table(math.exp(step * round(math.log(b) / step)))


def _format_force(force):
    return f"{force * 1e12:.6g} pN"


def _solve_scalar(T_target, b, rtol=EQUILIBRIUM_RTOL):
    """One reduced tension: ``(alpha, rho)`` on Python floats (about ten times faster than
    :func:`solve_reduced` for a single force).

    Started from the table of a b within 5 % (:func:`_start_table`). First Newton on
    (GE2) and the tension together in ``(alpha, log rho)``
    (:func:`~supercoil.core.dna.hard_core_equations.scalar_joint_solve`: one
    evaluation of both per step), accepted only if it settles inside the branch and its
    tension residual is at rounding level; else the safeguarded nested Newton of
    :func:`solve_reduced` (:func:`_nested_newton`), bracketed by the whole branch
    ``[RHO_MIN, 1e4]``, where ``T' - T_target`` changes sign once. Either way (GE2) is
    solved last at the final rho (evaluation counts and the measured gain:
    :func:`~supercoil.core.dna.hard_core_equations.scalar_joint_solve`).
    """
    rho_t, alpha_t, T_t = _start_table(b)
    beta = b ** (-1.0 / 3.0)
    k = int(np.searchsorted(-T_t, -T_target, side="left")) - 1
    k = min(max(k, 0), rho_t.size - 2)
    u_lo, u_hi = math.log(rho_t[k]), math.log(rho_t[k + 1])
    frac = min(max((T_t[k] - T_target) / (T_t[k] - T_t[k + 1]), 0.0), 1.0)
    u = u_lo + frac * (u_hi - u_lo)
    a = float(alpha_t[k] + frac * (alpha_t[k + 1] - alpha_t[k]))
    joint = _r.scalar_joint_solve(T_target, a, u, b, beta, rtol, _U_BRANCH)
    if joint is not None:
        return np.array([joint[0]]), np.array([joint[1]])
    a, u = _nested_newton(T_target, a, u, b, beta, rtol)
    rho = math.exp(u)
    a = _r.scalar_tilt(a, rho, b, beta)  # (GE2) at the final rho
    return np.array([a]), np.array([rho])


def _nested_newton(T_target, a, u, b, beta, rtol):
    """``(alpha, u)`` by Newton in u on the tension with (GE2) solved for alpha at each
    iterate, safeguarded by bisection in the whole branch (the method of
    :func:`solve_reduced` on floats)."""
    u_lo, u_hi = _U_BRANCH
    for _ in range(200):
        rho = math.exp(u)
        a = _r.scalar_tilt(a, rho, b, beta)
        _, h_a, h_r, T, T_a, T_r = _r.scalar_ge2_tension(a, rho, b, beta)
        G = T_target - T
        if G < 0.0:
            u_lo = u
        elif G > 0.0:
            u_hi = u
        else:
            break
        dG = -rho * (T_r - T_a * h_r / h_a)
        un = u - G / dG
        if not u_lo <= un <= u_hi:
            un = 0.5 * (u_lo + u_hi)
        du = abs(un - u)
        u = un
        if du <= rtol * (1.0 + abs(u)):
            break
    return a, u


def _reduced_start(T_target, b):
    """``(u0, u_lo, u_hi, alpha0)``: the start of each tension in b's branch table and the
    table interval that brackets it (``u = log rho``).

    The start is the cubic through the four table rows around the tension (Lagrange in
    T', kept inside the bracket): within 2e-5 of the root in u and alpha (the linear
    interpolation between the two rows: 4e-4; b from 0.3 to 3 times the seed set's), so
    the joint Newton takes 2 steps instead of 3
    (:func:`~supercoil.core.numerics.table_cubic`, as the screened solver's start).
    """
    rho_t, alpha_t, T_t = reduced_branch_table(float(b))
    # T_t decreasing: index of the interval [k, k+1] with T_t[k] >= T > T_t[k+1]
    k = np.searchsorted(-T_t, -T_target, side="left") - 1
    k = np.clip(k, 0, rho_t.size - 2)
    u_t = _log_rho_table(float(b))
    u_lo, u_hi = u_t[k], u_t[k + 1]
    a_lo, a_hi = alpha_t[k], alpha_t[k + 1]
    u0, a0 = (v.reshape(k.shape) for v in table_cubic(T_target.ravel(), k.ravel(), T_t, u_t,
                                                      alpha_t))
    return (np.minimum(np.maximum(u0, u_lo), u_hi), u_lo, u_hi,
            np.minimum(np.maximum(a0, np.minimum(a_lo, a_hi)), np.maximum(a_lo, a_hi)))


@lru_cache(maxsize=64)
def _log_rho_table(b):
    """``log rho`` of :func:`reduced_branch_table` (cached with it)."""
    return np.log(reduced_branch_table(b)[0])


def _nested_reduced(T_target, b, rtol, u0, u_lo, u_hi, alpha0):
    """``(alpha, rho)`` by Newton in u on the tension, (GE2) solved for alpha at each
    iterate (:func:`~supercoil.core.dna.hard_core_equations.reduced_tilt`), safeguarded
    by bisection in ``[u_lo, u_hi]``."""
    state = {"alpha": alpha0}

    def fun(u):
        rho = np.exp(u)
        a = reduced_tilt(rho, b, alpha0=state["alpha"])
        state["alpha"] = a
        T, T_a, T_r = reduced_tension(a, rho, b, derivatives=True)
        _, h_a, h_r = reduced_ge2(a, rho, b, derivatives=True)
        dT_drho = T_r - T_a * h_r / h_a
        return T_target - T, -rho * dT_drho

    u = _safe_newton(fun, u0, u_lo, u_hi, rtol)
    rho = np.exp(u)
    alpha = reduced_tilt(rho, b, alpha0=state["alpha"])
    return alpha, rho


def solve_reduced(T_target, b, rtol=EQUILIBRIUM_RTOL):
    """Solve the reduced equations at reduced tensions ``T_target > 0``: ``(alpha, rho)``.

    Started by interpolation in b's branch table; first Newton on (GE2) and the tension
    together (:func:`~supercoil.core.dna.hard_core_equations.joint_solve`), then, for
    the tensions it leaves unsettled, the safeguarded nested Newton bracketed by the
    table's interval (:func:`_nested_reduced`): about twice as fast as the nested solve
    alone, to 2e-15 (measured in the docstring of ``joint_solve``). On the tensions of
    b from 0.1 to 10 times the seed set's, from 1e-5 to the largest held, 9 % of the
    tensions (12 % one by one: below T' = 2e-4 and within 1e-3 of the largest) fall
    back to the nested solve.
    """
    T_target = np.asarray(T_target, dtype=float)
    start = _reduced_start(T_target, b)
    alpha, rho, ok = _r.joint_solve(T_target, start[3], start[0], b, rtol, _U_BRANCH)
    if not ok.all():
        bad = ~ok
        alpha[bad], rho[bad] = _nested_reduced(T_target[bad], b, rtol,
                                               *(x[bad] for x in start))
    return alpha, rho


def equilibrium(force, B, C, kT, r0, rtol=EQUILIBRIUM_RTOL):
    """Plectoneme equilibrium at fixed force: solves (GE1), (GE2) and the tension equation.

    Implements docs/theory/plectoneme.md (GE1, GE2).

    Parameters
    ----------
    force : float or array
        Tension T (N), positive, finite.
    B, C : float
        Bending and torsional rigidity (N m^2).
    kT : float
        Thermal energy (J).
    r0 : float
        Hard-core radius of the Marko-Siggia interaction (m).
    rtol : float
        Step tolerance on log R of the Newton iteration (default
        :data:`EQUILIBRIUM_RTOL` = 1e-8; quadratic convergence leaves residuals
        at ~1e-15).

    Returns
    -------
    PlectonemeState
        SI arrays of the shape of ``force``.

    Raises
    ------
    NoEquilibriumError
        Naming the force, if it is not positive or exceeds the largest
        tabulated force (R < r0/2).
    ValueError
        If a force is not finite.
    """
    force = np.asarray(force, dtype=float)
    if not np.all(np.isfinite(force)):
        raise ValueError(f"force must be finite, got {force!r}")
    b = float(B / (kT * r0))
    bad = force <= 0.0
    if np.any(bad):
        f = force[bad].flat[0]
        raise NoEquilibriumError(
            f"no plectoneme equilibrium at force {_format_force(f)}: "
            "the tension must be positive"
        )
    T_max = _largest_tension(b)
    f_max = T_max * kT / r0
    if np.any(force * (r0 / kT) > T_max):
        f = force[force * (r0 / kT) > T_max].flat[0]
        raise NoEquilibriumError(
            f"no plectoneme equilibrium at force {_format_force(f)}: above "
            f"{_format_force(f_max)} the superhelix radius would fall below "
            f"r0/2 (alpha -> pi/4)"
        )
    # in blocks: the solver's ~30 temporaries are bounded by BLOCK, not the input
    return in_blocks(lambda f: _equilibrium_block(f, B, C, kT, r0, b, rtol), force, BLOCK,
                     keep="force")


def _equilibrium_block(force, B, C, kT, r0, b, rtol):
    """:func:`equilibrium` for checked forces (all in the tabulated range)."""
    Tr = force * (r0 / kT)
    if Tr.size <= _SCALAR_LOOP_MAX:  # a few forces: the pure-float path is faster
        return _scalar_block(force, Tr, B, C, kT, r0, b, rtol)
    alpha, rho = solve_reduced(Tr, b, rtol=rtol)
    del Tr
    M = reduced_torque(alpha, rho, b) * kT
    R = rho * r0
    kappa = _g.curvature(alpha, R)
    tau = _g.torsion(alpha, R)
    omega = M / C
    w = _ms.interaction(alpha, R, B, kT, r0)
    return PlectonemeState(
        force=force,
        alpha=alpha,
        radius=R,
        pitch=_g.pitch_from_tilt(alpha, R),
        omega=omega,
        torque=M,
        curvature=kappa,
        torsion=tau,
        bending_energy=0.5 * B * kappa * kappa,
        twist_energy=0.5 * C * omega * omega,
        interaction_energy=w,
    )


def _scalar_block(force, Tr, B, C, kT, r0, b, rtol):
    """:func:`_equilibrium_block` of a few forces on Python floats: the roots by
    :func:`_solve_scalar`, the state by
    :func:`~supercoil.core.dna.hard_core_equations.scalar_state` (the vector formulas on
    floats: on one force about a fifth of their array operations' CPU, measured)."""
    beta = b ** (-1.0 / 3.0)
    rows = []
    for t in Tr.ravel().tolist():
        a, rho = (float(x[0]) for x in _solve_scalar(t, b, rtol=rtol))
        R = rho * r0
        torque, s, c, tan, w = _r.scalar_state(a, rho, b, beta)
        if R / r0 != rho:  # the interaction at R/r0, as marko_siggia.interaction takes it
            w = _r.scalar_state(a, R / r0, b, beta)[4]
        w *= kT / r0
        M = torque * kT
        kappa = s**2 / R
        omega = M / C
        rows.append((a, R, _g.TWO_PI * R / tan, omega, M, kappa, s * c / R,
                     0.5 * B * kappa * kappa, 0.5 * C * omega * omega, w))
    cols = np.array(rows, float).reshape(Tr.size, 10).T
    return PlectonemeState(force, *(col.reshape(Tr.shape) for col in cols))


def hard_core_residuals(force, alpha, radius, omega, B, C, kT, r0):
    """Relative residuals ``(GE1, GE2, tension)`` of a solution, from the general equations.

    Uses the un-reduced forms of docs/theory/plectoneme.md#equations (geometry partials of
    :mod:`supercoil.core.geometry`, ``w`` and its partials of
    :mod:`supercoil.core.dna.marko_siggia`), each divided by the sum of the
    magnitudes of its terms. Independent of the reduced forms the solver uses.
    """
    kappa = _g.curvature(alpha, radius)
    tau = _g.torsion(alpha, radius)
    k_a, k_r = _g.curvature_partials(alpha, radius)
    t_a, t_r = _g.torsion_partials(alpha, radius)
    w = _ms.interaction(alpha, radius, B, kT, r0)
    w_a, w_r = _ms.interaction_partials(alpha, radius, B, kT, r0)
    X = B * kappa * k_a + w_a
    Y = B * kappa * k_r + w_r
    ge1 = (C * omega * t_a - X) / (np.abs(C * omega * t_a) + np.abs(B * kappa * k_a) + np.abs(w_a))
    ge2 = (t_r * X - t_a * Y) / (np.abs(t_r * X) + np.abs(t_a * B * kappa * k_r)
                                 + np.abs(t_a * w_r))
    terms = (0.5 * B * kappa**2, C * omega * tau, w, force)
    tension = (-terms[0] + terms[1] - terms[2] - force) / sum(np.abs(x) for x in terms)
    return ge1, ge2, tension
