"""Hard-core plectoneme equations in reduced units (docs/theory/plectoneme.md#reduced-form).

The (GE2) function ``h(alpha, rho)`` and the reduced tension ``T'(alpha, rho)``
of :mod:`supercoil.core.dna.plectoneme` in the variables ``rho = R/r0``,
``b = B/(kT r0)``, ``beta = b^(-1/3)``, ``t = tan(alpha)/pi``, with their partial
derivatives, the reduced torque, and the tilt ``alpha(rho)`` solving (GE2);
vectorised, and as pure-float formulas for one point (the scalar path of a few
forces, about ten times faster there; tested equal); and Newton on (GE2) and the
tension together (:func:`joint_solve`, :func:`scalar_joint_solve`), the first method
of the plectoneme equilibrium. Float-only kernel.
"""

from __future__ import annotations

import math

import numpy as np

from supercoil.core.dna import marko_siggia as _ms
from supercoil.core.numerics import safe_newton as _safe_newton

__all__ = [
    "ALPHA_HI",
    "ALPHA_LO",
    "joint_solve",
    "reduced_ge2",
    "reduced_tension",
    "reduced_tilt",
    "reduced_torque",
    "scalar_ge2_tension",
    "scalar_joint_solve",
    "scalar_state",
    "scalar_tilt",
]

#: bracket of the tilt in (GE2): (0, pi/4)
ALPHA_LO = 1e-12
ALPHA_HI = 0.25 * np.pi
_TWO_THIRDS = 2.0 / 3.0


def _trig(alpha):
    s = np.sin(alpha)
    c = np.cos(alpha)
    tan = s / c
    t = tan / np.pi
    t_a = (1.0 + tan * tan) / np.pi
    return s, c, t, t_a


def reduced_ge2(alpha, rho, b, derivatives=False):
    """``h = -rho^4 (GE2)`` in reduced units; with ``derivatives`` also ``(h_alpha, h_rho)``.

    Implements docs/theory/plectoneme.md (GE2).
    """
    beta = b ** (-1.0 / 3.0)
    s, c, t, t_a = _trig(alpha)
    s2 = s * s
    c2 = c * c - s2
    t13 = np.cbrt(t)
    t23 = t13 * t13
    t12 = t**12
    g1 = 2.0 * s2 * t23 - c2
    g2 = 2.0 * s2 * t12 - c2
    r43 = np.cbrt(rho) * rho
    rm10 = rho**-10
    k1 = _TWO_THIRDS * beta
    h = b * s2 * s2 + 12.0 * rm10 * g2 + k1 * r43 * g1
    if not derivatives:
        return h
    sin2a = 2.0 * s * c
    g1_a = 2.0 * sin2a * t23 + 2.0 * s2 * _TWO_THIRDS * t_a / t13 + 2.0 * sin2a
    g2_a = 2.0 * sin2a * t12 + 24.0 * s2 * t12 / t * t_a + 2.0 * sin2a
    h_a = 4.0 * b * s2 * s * c + 12.0 * rm10 * g2_a + k1 * r43 * g1_a
    h_r = -120.0 * rm10 / rho * g2 + (4.0 / 3.0) * k1 * r43 / rho * g1
    return h, h_a, h_r


def reduced_tension(alpha, rho, b, derivatives=False):
    """Reduced tension ``T' = T r0 / kT`` on the (GE1)-eliminated tension equation.

    With ``derivatives`` also returns ``(T'_alpha, T'_rho)``.
    """
    beta = b ** (-1.0 / 3.0)
    s, c, t, t_a = _trig(alpha)
    s2 = s * s
    s4 = s2 * s2
    c2 = c * c - s2
    t13 = np.cbrt(t)
    t23 = t13 * t13
    t12 = t**12
    q2 = 12.0 * t12 / c2 - 1.0 - t12
    q1 = _TWO_THIRDS * t23 / c2 - 1.0 - t23
    rm2 = 1.0 / (rho * rho)
    rm12 = rm2**6
    rm23 = 1.0 / np.cbrt(rho * rho)
    bend = b * s4 * (2.0 + c2) / (2.0 * c2) * rm2
    T = bend + rm12 * q2 + beta * rm23 * q1
    if not derivatives:
        return T
    sin2a = 2.0 * s * c
    c2sq = c2 * c2
    d_bend = 4.0 * s2 * s * c * (1.0 + 2.0 / c2) + 4.0 * s4 * sin2a / c2sq
    q2_a = 144.0 * t12 / t * t_a / c2 + 24.0 * t12 * sin2a / c2sq - 12.0 * t12 / t * t_a
    q1_a = ((4.0 / 9.0) * t_a / t13 / c2 + (4.0 / 3.0) * t23 * sin2a / c2sq
            - _TWO_THIRDS * t_a / t13)
    T_a = 0.5 * b * rm2 * d_bend + rm12 * q2_a + beta * rm23 * q1_a
    T_r = (-2.0 * bend - 12.0 * rm12 * q2 - _TWO_THIRDS * beta * rm23 * q1) / rho
    return T, T_a, T_r


def reduced_torque(alpha, rho, b):
    """Reduced torque ``M_3 / kT = (B kappa kappa_alpha + w_alpha) / (kT tau_alpha)`` (GE1).

    Implements docs/theory/plectoneme.md (GE1).
    """
    beta = b ** (-1.0 / 3.0)
    s, c, _, _ = _trig(alpha)
    c2 = c * c - s * s
    w_a, _ = _ms.reduced_interaction_partials(alpha, rho, beta)
    return (b * s * s * 2.0 * s * c / rho + rho * w_a) / c2


def scalar_state(a, rho, b, beta):
    """Pure-float ``(M', sin, cos, tan, w')`` at one root: the reduced torque
    (:func:`reduced_torque`), the tilt's functions and the reduced interaction
    (:func:`~supercoil.core.dna.marko_siggia.reduced_interaction`), by the formulas of
    the vector functions in their order (the scalar path's state: the same values to a
    few ulp, tested)."""
    s = math.sin(a)
    c = math.cos(a)
    tan = math.tan(a)
    t = tan / math.pi
    t_a = (1.0 + tan * tan) / math.pi
    cbrt_r2 = math.cbrt(rho * rho)
    rho_m12 = rho**-12
    w_a = t_a * (12.0 * t**11 * rho_m12 + _TWO_THIRDS * beta / math.cbrt(t) * (1.0 / cbrt_r2))
    torque = (b * s * s * 2.0 * s * c / rho + rho * w_a) / (c * c - s * s)
    w = (1.0 + t**12) * rho_m12 + beta * (1.0 + math.cbrt(t * t)) / cbrt_r2
    return torque, s, c, tan, w


# ---------------------------------------------------------------------------
# (GE2) tilt by safeguarded Newton (supercoil.core.numerics.safe_newton)
# ---------------------------------------------------------------------------


def reduced_tilt(rho, b, alpha0=None, xtol=1e-15):
    """The unique root alpha in (0, pi/4) of (GE2) at reduced radius ``rho``."""
    rho = np.asarray(rho, dtype=float)
    if alpha0 is None:
        alpha0 = np.full(rho.shape, 0.5)

    def fun(a):
        h, h_a, _ = reduced_ge2(a, rho, b, derivatives=True)
        return h, h_a

    lo = np.full(rho.shape, ALPHA_LO)
    hi = np.full(rho.shape, ALPHA_HI)
    return _safe_newton(fun, alpha0, lo, hi, xtol)


def scalar_ge2_tension(a, rho, b, beta):
    """Pure-float ``(h, h_a, h_r, T, T_a, T_r)``: the formulas of :func:`reduced_ge2`
    and :func:`reduced_tension` for one point (the scalar fast path; tested equal)."""
    s = math.sin(a)
    c = math.cos(a)
    tan = s / c
    t = tan / math.pi
    t_a = (1.0 + tan * tan) / math.pi
    s2 = s * s
    s4 = s2 * s2
    c2 = c * c - s2
    sin2a = 2.0 * s * c
    t13 = math.cbrt(t)
    t23 = t13 * t13
    t11 = t**11
    t12 = t11 * t
    # (GE2)
    g1 = 2.0 * s2 * t23 - c2
    g2 = 2.0 * s2 * t12 - c2
    r13 = math.cbrt(rho)
    r43 = r13 * rho
    rm10 = rho**-10
    k1 = _TWO_THIRDS * beta
    h = b * s4 + 12.0 * rm10 * g2 + k1 * r43 * g1
    g1_a = 2.0 * sin2a * t23 + 2.0 * s2 * _TWO_THIRDS * t_a / t13 + 2.0 * sin2a
    g2_a = 2.0 * sin2a * t12 + 24.0 * s2 * t11 * t_a + 2.0 * sin2a
    h_a = 4.0 * b * s2 * s * c + 12.0 * rm10 * g2_a + k1 * r43 * g1_a
    h_r = -120.0 * rm10 / rho * g2 + (4.0 / 3.0) * k1 * r13 * g1
    # tension
    q2 = 12.0 * t12 / c2 - 1.0 - t12
    q1 = _TWO_THIRDS * t23 / c2 - 1.0 - t23
    rm2 = 1.0 / (rho * rho)
    rm12 = rm2**6
    rm23 = 1.0 / (r13 * r13)
    bend = b * s4 * (2.0 + c2) / (2.0 * c2) * rm2
    T = bend + rm12 * q2 + beta * rm23 * q1
    c2sq = c2 * c2
    d_bend = 4.0 * s2 * s * c * (1.0 + 2.0 / c2) + 4.0 * s4 * sin2a / c2sq
    q2_a = 144.0 * t11 * t_a / c2 + 24.0 * t12 * sin2a / c2sq - 12.0 * t11 * t_a
    q1_a = ((4.0 / 9.0) * t_a / t13 / c2 + (4.0 / 3.0) * t23 * sin2a / c2sq
            - _TWO_THIRDS * t_a / t13)
    T_a = 0.5 * b * rm2 * d_bend + rm12 * q2_a + beta * rm23 * q1_a
    T_r = (-2.0 * bend - 12.0 * rm12 * q2 - _TWO_THIRDS * beta * rm23 * q1) / rho
    return h, h_a, h_r, T, T_a, T_r


def scalar_tilt(a, rho, b, beta):
    """(GE2) for alpha at reduced radius ``rho``: safeguarded Newton in (0, pi/4), floats."""
    a_lo, a_hi = ALPHA_LO, ALPHA_HI
    for _ in range(200):
        h, h_a = scalar_ge2_tension(a, rho, b, beta)[:2]
        if h == 0.0:
            break
        if h < 0.0:
            a_lo = a
        else:
            a_hi = a
        an = a - h / h_a
        if not a_lo <= an <= a_hi:
            an = 0.5 * (a_lo + a_hi)
        da = abs(an - a)
        a = an
        if da <= 1e-15 * (1.0 + a):
            break
    return a


#: most steps of the joint Newton (3 from the start tables at 0.3-20 pN, seed set)
JOINT_MAXITER = 8
#: largest relative tension residual the joint Newton accepts (its steps converge
#: quadratically: once a step is below 1e-8 the residual is at rounding, ~1e-15)
JOINT_RESIDUAL = 1e-12


def _joint_step(h, h_a, h_r, T, T_a, T_r, rho, T_target):
    """``(d alpha, d u)``: the Newton step of ``(h, T' - T_target) = 0`` in
    ``(alpha, u = log rho)`` (Cramer's rule on the 2x2 Jacobian of the partials)."""
    h_u, T_u = h_r * rho, T_r * rho
    du = (T_a * h - h_a * (T - T_target)) / (h_a * T_u - h_u * T_a)
    return -(h + h_u * du) / h_a, du


def scalar_joint_solve(T_target, a, u, b, beta, rtol, u_branch):
    """``(alpha, rho)`` at one reduced tension by the joint Newton, or None (not settled).

    From ``(a, u = log rho)``: one :func:`scalar_ge2_tension` per step, until the step
    in u is below ``rtol (1 + |u|)`` and in alpha below ``rtol``; then (GE2) solved at
    the final rho (:func:`scalar_tilt`) and the tension checked there. None where a step
    leaves ``(ALPHA_LO, ALPHA_HI)`` or ``u_branch`` (or is not finite), after
    :data:`JOINT_MAXITER` steps, or where the residual exceeds :data:`JOINT_RESIDUAL`:
    the caller's safeguarded solve then runs. On the seed set at 0.3-20 pN: 3 steps,
    5 evaluations of :func:`scalar_ge2_tension` with the final tilt and check, against
    11-16 for the nested Newton (a tilt solve at every step): 1.9-3.6x less CPU, the same
    rho to the last bit.
    """
    for _ in range(JOINT_MAXITER):
        rho = math.exp(u)
        h, h_a, h_r, T, T_a, T_r = scalar_ge2_tension(a, rho, b, beta)
        try:
            da, du = _joint_step(h, h_a, h_r, T, T_a, T_r, rho, T_target)
        except ZeroDivisionError:
            return None
        a, u = a + da, u + du
        if not (ALPHA_LO < a < ALPHA_HI and u_branch[0] <= u <= u_branch[1]):  # also NaN
            return None
        if abs(du) <= rtol * (1.0 + abs(u)) and abs(da) <= rtol:
            break
    else:
        return None
    rho = math.exp(u)
    a = scalar_tilt(a, rho, b, beta)
    T = scalar_ge2_tension(a, rho, b, beta)[3]
    if not abs(T - T_target) <= JOINT_RESIDUAL * T_target:
        return None
    return a, rho


def joint_solve(T_target, a, u, b, rtol, u_branch):
    """The joint Newton of :func:`scalar_joint_solve` on arrays: ``(alpha, rho, ok)``.

    Each tension steps until its own steps are below the tolerances and is then held
    (its result does not depend on the other tensions of the call: tested). ``ok`` False where
    a tension left ``(ALPHA_LO, ALPHA_HI)`` or ``u_branch``, was not settled after
    :data:`JOINT_MAXITER` steps, or its tension residual after the final (GE2) solve
    (:func:`reduced_tilt`) exceeds :data:`JOINT_RESIDUAL`; ``alpha`` and ``rho`` are
    then the start's (finite), for the caller's safeguarded solve. On the seed set
    (with the final tilt solve) it takes 0.46-0.55 of the nested Newton's CPU for 33,
    1000 and 1e5 tensions at 0.2-20 pN; rho and alpha within 1.6e-15 of the nested
    solve's.
    """
    T_target = np.asarray(T_target, dtype=float)
    a0, u0 = np.array(a, dtype=float), np.array(u, dtype=float)
    a, u = a0.copy(), u0.copy()
    active = np.ones(T_target.shape, bool)
    ok = np.ones(T_target.shape, bool)
    with np.errstate(all="ignore"):
        for _ in range(JOINT_MAXITER):
            rho = np.exp(u)
            h, h_a, h_r = reduced_ge2(a, rho, b, derivatives=True)
            T, T_a, T_r = reduced_tension(a, rho, b, derivatives=True)
            da, du = _joint_step(h, h_a, h_r, T, T_a, T_r, rho, T_target)
            a = np.where(active, a + da, a)
            u = np.where(active, u + du, u)
            out = active & ~((a > ALPHA_LO) & (a < ALPHA_HI) & (u >= u_branch[0])
                             & (u <= u_branch[1]))
            ok &= ~out
            a, u = np.where(out, a0, a), np.where(out, u0, u)
            active &= ~out & ~((np.abs(du) <= rtol * (1.0 + np.abs(u))) & (np.abs(da) <= rtol))
            if not active.any():
                break
    ok &= ~active
    rho = np.exp(u)
    a = np.where(ok, a, 0.5)
    alpha = reduced_tilt(rho, b, alpha0=a)
    with np.errstate(all="ignore"):
        ok &= np.abs(reduced_tension(alpha, rho, b) - T_target) <= JOINT_RESIDUAL * T_target
    return np.where(ok, alpha, a0), np.where(ok, rho, np.exp(u0)), ok
