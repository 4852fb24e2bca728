"""Phases of a stretched, twisted DNA molecule in the (force, torque) ensemble.

Float-only kernel (SI units), the shared phase interface of the real-DNA models
(docs/theory/ensemble.md#2-phases). A phase is its Gibbs free energy per unit
B-DNA contour length ``phi(F, M)`` (J/m) with

* ``dphi/dF = -x`` (extension per contour length of the phase),
* ``dphi/dM = -Omega`` (excess twist density, rad/m),
* ``d2phi/dM2 = -dOmega/dM`` (negative: the phase is torsionally stable).

Phases here: the stretched worm-like chain with the exact Bouchiat force-extension
and the resummed Moroz-Nelson twist stiffness (:func:`stretched_gibbs`; or at the
Moroz-Nelson effective tension, :func:`effective_tension_gibbs`), a
plectoneme whose effective twist stiffness grows with torque
(:func:`plectoneme_gibbs`), the plectoneme of a superhelix tabulated at fixed torque
(:func:`tabulated_plectoneme_gibbs`), a simple torque-melted phase
(:func:`simple_melted_gibbs`), the cooperative two-state (Zimm-Bragg) mixture of two
phases along the tail (:func:`two_state_gibbs`) and the end loop of a plectoneme
domain as a per-domain Gibbs free energy (:func:`end_loop_gibbs`). Everything
broadcasts over ``F`` and ``M``.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from supercoil.core.numerics import safe_newton

__all__ = [
    "BOUCHIAT_COEFFICIENTS",
    "EFFECTIVE_TENSION_FLOOR",
    "MARKO_TENSION_FLOOR",
    "PhaseGibbs",
    "effective_tension",
    "effective_tension_gibbs",
    "end_loop_gibbs",
    "end_loop_torque_slope",
    "plectoneme_gibbs",
    "simple_melted_gibbs",
    "stretched_gibbs",
    "tabulated_plectoneme_gibbs",
    "two_state_gibbs",
    "wlc_exact_free_energy_gain",
    "wlc_extension",
]

#: a_2 ... a_7 of the 7-coefficient interpolation of the exact worm-like-chain
#: force-extension, F A / kT = x + 1/(4(1-x)^2) - 1/4 + sum a_i x^i (Bouchiat et al.,
#: Biophys. J. 76, 409, 1999, text below their eq. 11)
BOUCHIAT_COEFFICIENTS = (-0.5164228, -2.737418, 16.07497, -38.87607, 39.49944, -14.17718)
_TWO_PI = 2.0 * np.pi


class PhaseGibbs(NamedTuple):
    """Gibbs free energy per length of a phase and its derivatives (SI arrays)."""

    phi: np.ndarray  # J/m
    dphi_dF: np.ndarray  # -x, dimensionless
    dphi_dM: np.ndarray  # -Omega, 1/m
    d2phi_dM2: np.ndarray  # 1/(N m^2), negative


def _bouchiat_reduced_force(x):
    """``F A / kT`` of the Bouchiat interpolation at relative extension x."""
    out = x + 0.25 / (1.0 - x) ** 2 - 0.25
    for i, a in enumerate(BOUCHIAT_COEFFICIENTS):
        out = out + a * x ** (i + 2)
    return out


def _bouchiat_reduced_stiffness(x):
    """``d(F A / kT)/dx`` of the Bouchiat interpolation (positive on ``0 <= x < 1``)."""
    out = 1.0 + 0.5 / (1.0 - x) ** 3
    for i, a in enumerate(BOUCHIAT_COEFFICIENTS):
        out = out + (i + 2) * a * x ** (i + 1)
    return out


def _bouchiat_reduced_work(x):
    """``(A / kT) int_0^x F dx'`` of the Bouchiat interpolation."""
    out = 0.5 * x**2 + 0.25 / (1.0 - x) - 0.25 - 0.25 * x
    for i, a in enumerate(BOUCHIAT_COEFFICIENTS):
        out = out + a * x ** (i + 3) / (i + 3)
    return out


def wlc_extension(force, A, kT):
    """Relative extension ``x(F)`` of the exact worm-like chain and ``dx/dF`` (1/N).

    The one inversion of the Bouchiat interpolation in the package (bracketing root in
    ``0 <= x < 1``, where ``F A / kT`` increases with x); ``dx/dF`` is
    ``A / (kT h'(x))``. ``force`` (N) non-negative; the callers validate it.

    Solved by :func:`~supercoil.core.numerics.safe_newton` on the analytic stiffness
    ``h'(x)`` from ``min(f / 1.5, 1 - 1 / (2 sqrt(f + 1/4)))`` (the small- and
    large-force limits of ``x(f)``, ``f = F A / kT``), in the bracket
    ``[0, 1 - 1e-13]``. Kept hand-written by measurement: for 1, 20 and 1000 forces of
    0-100 pN (A = 50 nm, kT at 25 degC) scipy.optimize.elementwise.find_root in the same
    bracket takes 7-19x its time, for the same roots (2.5e-16 apart; 6e-13 below
    1e-15 N, where the rounding of ``h`` near ``x = 0`` limits both).
    """
    f = np.asarray(force, dtype=float) * A / kT
    top = 1.0 - 1e-13
    # the start inside the bracket: at f > 1e25 the large-force limit rounds to 1.0
    start = np.clip(np.minimum(f / 1.5, 1.0 - 0.5 / np.sqrt(f + 0.25)), 0.0, top)
    x = safe_newton(lambda x: (_bouchiat_reduced_force(x) - f, _bouchiat_reduced_stiffness(x)),
                    start, np.zeros_like(f), np.full_like(f, top), xtol=1e-15)
    x = np.where(np.isnan(f), np.nan, x)[()]  # a NaN force stays NaN, as in find_root
    return x, A / (kT * _bouchiat_reduced_stiffness(x))


def wlc_exact_free_energy_gain(force, A, kT, slope=False):
    """``g(F) = int_0^F x dF'`` (N) and ``x(F)`` of the exact worm-like chain.

    Implements docs/theory/melting.md (MT2).

    ``x`` from :func:`wlc_extension` and ``g = F x - int_0^x F dx'`` (integration by
    parts), so ``dg/dF = x`` [ensemble.md#21-stretched]. ``slope``: also ``dx/dF`` (1/N).
    """
    x, dx = wlc_extension(force, A, kT)
    f = np.asarray(force, dtype=float) * A / kT
    g = (f * x - _bouchiat_reduced_work(x)) * kT / A
    return (g, x, dx) if slope else (g, x)


def stretched_gibbs(force, torque, A, C, kT, softening=1.0, exact=True, resummed=True,
                    wlc=None, effective_tension=False):
    """Stretched, twisted worm-like chain ``phi_s = -g(F) - M^2 / (2 kT c_s(F))``.

    Implements docs/theory/ensemble.md (E1).

    ``resummed``: ``1/c_s = 1/C + k (1/4A) sqrt(kT/(A F))`` (Moroz & Nelson, PNAS 94,
    14418, 1997, resummed; ``k`` = ``softening``, 1 for Moroz-Nelson); else the
    first-order ``c_s = C (1 - k (C/4A) sqrt(kT/(A F)))`` of Marko (2007).
    ``exact``: Bouchiat's g(F); else Marko's ``g = F - sqrt(kT F / A)``
    [ensemble.md#21-stretched]. ``wlc``: ``(g, x)`` precomputed by
    :func:`wlc_exact_free_energy_gain` at these forces (saves its root solve).
    ``effective_tension``: the chain at the Moroz-Nelson effective tension instead
    (:func:`effective_tension_gibbs`; ``resummed`` and ``wlc`` unused).
    """
    if effective_tension:
        return effective_tension_gibbs(force, torque, A, C, kT, softening, exact)
    F, M = np.broadcast_arrays(np.asarray(force, float), np.asarray(torque, float))
    root = np.sqrt(kT / (A * F))
    if exact and wlc is not None:
        g, x = (np.broadcast_to(a, F.shape) for a in wlc)
    elif exact:
        g, x = wlc_exact_free_energy_gain(F, A, kT)
    else:
        g, x = F * (1.0 - root), 1.0 - 0.5 * root
    if resummed:
        inv_c = 1.0 / C + softening * root / (4.0 * A)
        dinv_dF = -softening * root / (8.0 * A * F)
    else:
        u = softening * C * root / (4.0 * A)
        cs = C * (1.0 - u)
        inv_c = 1.0 / cs
        dinv_dF = -(C * u / (2.0 * F)) / cs**2
    q = 1.0 / kT
    return PhaseGibbs(-g - 0.5 * q * inv_c * M**2, -x - 0.5 * q * dinv_dF * M**2,
                      -q * inv_c * M, -q * inv_c + 0.0 * M)


#: the continuation of the effective-tension phase starts below this reduced tension
#: ``F_eff A / kT``: with the exact WLC the ensemble model's lowest force (0.25, where
#: x = 0.16); with Marko's g 1 (x = 1/2; his x is 0 at 0.25)
EFFECTIVE_TENSION_FLOOR = 0.25
MARKO_TENSION_FLOOR = 1.0


_TABLE_LOG_F = np.linspace(np.log(EFFECTIVE_TENSION_FLOOR), np.log(1e12), 2400)


def _table_x():
    x = np.linspace(0.0, 1.0 - 1e-7, 200001)
    return np.interp(_TABLE_LOG_F, np.log(np.maximum(_bouchiat_reduced_force(x), 1e-300)), x)


_TABLE_X = _table_x()


_A = BOUCHIAT_COEFFICIENTS


def _h_and_slope(x):
    """``h(x) = F A / kT`` of the Bouchiat interpolation and ``h'(x)``, by Horner (the
    same polynomial as :func:`_bouchiat_reduced_force`, faster)."""
    u = 1.0 / (1.0 - x)
    p = _A[5]
    dp = 7.0 * _A[5]
    for i in range(4, -1, -1):  # p = sum a_i x^(i-2) for i = 2..7; dp = sum i a_i x^(i-2)
        p = p * x + _A[i]
        dp = dp * x + (i + 2) * _A[i]
    return x + 0.25 * (u * u - 1.0) + p * x * x, 1.0 + 0.5 * u**3 + dp * x


def _wlc_newton(f):
    """``x`` with ``h(x) = f`` of the Bouchiat interpolation for ``f >= 0.25``: a start
    interpolated in ``ln f`` (beyond 1e12 the high-force ``1 - 1/(2 sqrt f)``), then
    Newton steps on ``h(x)^(-1/2) = f^(-1/2)`` (h monotone on ``0 <= x < 1``) to round-off."""
    lf = np.log(f)
    x = np.where(lf < _TABLE_LOG_F[-1], np.interp(lf, _TABLE_LOG_F, _TABLE_X),
                 1.0 - 0.5 / np.sqrt(f))
    r = 1.0 / np.sqrt(f)
    for _ in range(3):  # on h^(-1/2) - f^(-1/2), nearly linear in x where x -> 1
        h, dh = _h_and_slope(x)
        sh = np.sqrt(h)
        x = np.clip(x + (1.0 / sh - r) * 2.0 * h * sh / dh, 0.0, 1.0 - 1e-13)
    return x, _h_and_slope(x)[1]


def effective_tension(force, torque, A, kT, softening=1.0):
    """Moroz-Nelson effective tension ``F_eff = F - k M^2 / (4 kT A)`` (N)."""
    return np.asarray(force, float) - softening * np.asarray(torque, float) ** 2 / (4.0 * kT * A)


def effective_tension_gibbs(force, torque, A, C, kT, softening=1.0, exact=True):
    """Stretched chain at the effective tension ``phi_s = -F + W(F_eff) - M^2/(2 kT C)``.

    Implements docs/theory/ensemble.md (E1').

    ``W(F) = F - g(F)`` is the chain's bending-fluctuation free energy (Bouchiat's g, or
    Marko's ``W = sqrt(kT F / A)`` for ``exact=False``, which is Moroz & Nelson's
    closed form); ``F_eff`` from :func:`effective_tension` with ``k`` = ``softening``,
    so ``x = -dphi/dF = x_WLC(F_eff)``. Below the floor ``F_c``
    (:data:`EFFECTIVE_TENSION_FLOOR` or :data:`MARKO_TENSION_FLOOR` times kT/A; the
    torque-induced instability is at ``F_eff = 0``) the extension is continued as
    ``x = x_c exp((F_eff - F_c) x'_c / x_c)``, with ``x`` and ``x'`` continuous: it
    stays in ``[0, x_c]``, ``W' = 1 - x > 0`` and ``W'' = -x' < 0``, so phi is finite
    and concave in M (``d2phi/dM2 < 0``) for every torque [ensemble.md#211-effective-tension].
    """
    F, M = np.broadcast_arrays(np.asarray(force, float), np.asarray(torque, float))
    Fc = (EFFECTIVE_TENSION_FLOOR if exact else MARKO_TENSION_FLOOR) * kT / A
    Fe = effective_tension(F, M, A, kT, softening)
    Fk = np.maximum(Fe, Fc)
    if exact:  # the exact WLC at Fk (as wlc_exact_free_energy_gain, Newton's inversion)
        f = Fk * A / kT
        x, dh = _wlc_newton(f)
        W = Fk - (f * x - _bouchiat_reduced_work(x)) * kT / A
        dx = A / (kT * dh)
    else:
        root = np.sqrt(kT / (A * Fk))
        W, x, dx = Fk * root, 1.0 - 0.5 * root, 0.25 * root / Fk
    d = np.minimum(Fe - Fc, 0.0)  # 0 above the floor: the chain itself
    lam = x / dx
    e = np.exp(d / lam)
    W = W + d - lam * x * (e - 1.0)  # int_Fc^Fe (1 - x) dF' of the continued x
    x, dx = x * e, dx * e
    s = softening / (2.0 * kT * A)  # -dF_eff/dM = s M
    q = 1.0 / (kT * C)
    return PhaseGibbs(-F + W - 0.5 * q * M**2, -x, -(1.0 - x) * s * M - q * M,
                      -dx * (s * M) ** 2 - (1.0 - x) * s - q)


def plectoneme_gibbs(force, torque, P0, exponent, M0, kT):
    """Plectoneme of torque-dependent twist stiffness ``P(M) = P0 (|M|/M0)^a``.

    Implements docs/theory/ensemble.md (E2).

    ``phi_p = -|M|^(2-a) M0^a / ((2-a) kT P0)``, so ``Omega_p = M / (kT P(M))``; no
    extension. ``a = 0`` is Marko's (2007) constant-P plectoneme
    [ensemble.md#22-plectoneme].
    """
    F, M = np.broadcast_arrays(np.asarray(force, float), np.asarray(torque, float))
    a = exponent
    am = np.abs(M)
    scale = (am / M0) ** a if a != 0.0 else np.ones_like(am)
    inv = 1.0 / (kT * P0 * scale)  # 1 / (kT P(M)); finite at M = 0 only for a <= 0
    return PhaseGibbs(-am**2 * inv / (2.0 - a), np.zeros_like(F), -M * inv,
                      -(1.0 - a) * inv)


def tabulated_plectoneme_gibbs(force, torque, table, C, kT):
    """Plectoneme of a superhelix tabulated at fixed torque: ``phi_p = -T(|M|) - M^2/(2 kT C)``.

    Implements docs/theory/ensemble.md (E2').

    ``table = (M_k, T_k, tau_k)``: torques (N m, increasing, positive), the superhelix's
    tension ``T_k`` (N) and writhe density ``tau_k`` (rad/m) along its equilibrium at
    those torques, where ``dT/dM = tau`` holds exactly [ensemble.md#221-derived-plectoneme].
    ``T(M)`` is the cubic Hermite interpolant of ``(T_k, tau_k)``, so its derivative is
    its own ``tau`` and ``Omega_p = tau(|M|) sign(M) + M / (kT C)`` is the exact
    derivative of ``phi_p``. Below ``M_0`` ``T = T_0 + tau_0 (M^2 - M_0^2) / (2 M_0)``
    (constant writhe stiffness), above ``M_K`` ``T = T_K + tau_K (M - M_K)`` (the radius
    stays at the table's end); both join with continuous ``T`` and ``tau``. No
    extension. Symmetric in ``M`` (either handedness).
    """
    F, M = np.broadcast_arrays(np.asarray(force, float), np.asarray(torque, float))
    base, c0, c1, c2, c3 = _hermite_rows(*table)
    am = np.abs(M)
    j = np.searchsorted(table[0], am, side="right")  # 0: below, K: beyond the table
    d = am - base[j]
    a1, a2, a3 = c1[j], c2[j], c3[j]
    T = c0[j] + d * (a1 + d * (a2 + d * a3))
    tau = a1 + d * (2.0 * a2 + 3.0 * d * a3)
    q = 1.0 / (kT * C)
    return PhaseGibbs(-T - 0.5 * q * M**2, np.zeros_like(F), -np.sign(M) * tau - q * M,
                      -(2.0 * a2 + 6.0 * d * a3) - q)


def _hermite_rows(Mk, Tk, tk):
    """Cubic coefficients in ``d = |M| - base`` of the K + 1 pieces of the tabulated T(M):
    row 0 below ``M_0``, rows 1..K-1 the Hermite intervals, row K beyond ``M_K``."""
    h = np.diff(Mk)
    slope = np.diff(Tk) / h
    c2 = (3.0 * slope - 2.0 * tk[:-1] - tk[1:]) / h
    c3 = (tk[:-1] + tk[1:] - 2.0 * slope) / h**2
    base = np.concatenate([Mk[:1], Mk[:-1], Mk[-1:]])
    c0 = np.concatenate([Tk[:1], Tk[:-1], Tk[-1:]])
    c1 = np.concatenate([tk[:1], tk[:-1], tk[-1:]])
    c2 = np.concatenate([[0.5 * tk[0] / Mk[0]], c2, [0.0]])
    c3 = np.concatenate([[0.0], c3, [0.0]])
    return base, c0, c1, c2, c3


def simple_melted_gibbs(force, torque, energy, extension, twist):
    """Torque-melted DNA ``phi_m = e - x_m F - M Omega_m`` (no twist compliance).

    Implements docs/theory/ensemble.md (E3).

    ``energy`` per B-DNA length (J/m), ``extension`` x_m, ``twist`` Omega_m (rad/m,
    negative: melting unwinds) [ensemble.md#23-melted].
    """
    F, M = np.broadcast_arrays(np.asarray(force, float), np.asarray(torque, float))
    return PhaseGibbs(energy - extension * F - twist * M, np.full_like(F, -extension),
                      np.full_like(F, -twist), np.zeros_like(F))


def two_state_gibbs(b, m, segment, cooperativity, kT):
    """Cooperative mixture of two phases along the tail (Zimm-Bragg transfer matrix).

    Implements docs/theory/ensemble.md (E4).

    Segments of length ``segment`` are in phase ``b`` or ``m``; each boundary costs
    ``cooperativity / 2`` (``sigma = exp(-cooperativity/kT)``). In the long-chain limit
    ``phi = phi_b - (kT/l) ln lambda``, ``lambda = (1 + s + sqrt((1-s)^2 + 4 sigma s))/2``,
    ``s = exp(-(phi_m - phi_b) l / kT)``; ``dphi = (1-theta) dphi_b + theta dphi_m``
    with the fraction ``theta = dln lambda / dln s`` [ensemble.md#24-tail].

    Returns
    -------
    (PhaseGibbs, theta)
    """
    sig = np.exp(-cooperativity / kT)
    d = (m.phi - b.phi) * segment / kT
    dc = np.clip(d, -600.0, 600.0)
    s = np.exp(-dc)
    R = np.sqrt((1.0 - s) ** 2 + 4.0 * sig * s)
    lam = 0.5 * (1.0 + s + R)
    theta = 0.5 * s * (1.0 + (s - 1.0 + 2.0 * sig) / R) / lam
    # d theta / d ln s = theta - theta^2 + s^2 lambda'' / lambda, lambda'' = 2 sig (1-sig)/R^3
    chi = theta - theta**2 + s**2 * 2.0 * sig * (1.0 - sig) / (R**3 * lam)
    far = d < -600.0  # deep in phase m: ln lambda = -d to round-off
    lnlam = np.where(far, -d, np.log(lam))
    theta = np.where(far, 1.0, theta)
    chi = np.where(far, 0.0, chi)
    w = 1.0 - theta
    dm = m.dphi_dM - b.dphi_dM
    out = PhaseGibbs(b.phi - kT / segment * lnlam,
                     w * b.dphi_dF + theta * m.dphi_dF,
                     w * b.dphi_dM + theta * m.dphi_dM,
                     w * b.d2phi_dM2 + theta * m.d2phi_dM2 - segment / kT * chi * dm**2)
    return out, theta


def end_loop_gibbs(tail, torque, A, C, kT, writhe, chirality, extra=0.0, physical=True):
    """Gibbs free energy of one plectoneme domain's end loop (J) and its derivatives.

    Implements docs/theory/ensemble.md (E5).

    ``physical``: a circle of radius R cut out of the tail (docs/theory/end-loop.md#2-loop)
    at common torque, minimised over R:
    ``eps = 2 pi sqrt(2 B gamma) - 2 pi chi w M + extra``,
    ``gamma = -phi_tail - M^2/(2 kT C)``; ``d eps = l d gamma`` with ``l = 2 pi R``.
    Else a constant nucleation ``extra - 2 pi chi w M`` (the loop absorbs ``chi w``
    turns). ``chirality`` is +1 or -1 (the domain's handedness)
    [ensemble.md#31-domains].

    Returns
    -------
    (eps, deps_dF, deps_dM) : J, m, rad (same shape as ``torque``)
    """
    M = np.asarray(torque, float)
    lin = _TWO_PI * writhe * chirality
    if not physical:
        return extra - lin * M, np.zeros_like(M), -lin + 0.0 * M
    B = A * kT
    gam = -tail.phi - M**2 / (2.0 * kT * C)
    gam = np.where(gam > 0.0, gam, np.nan)
    ell = np.pi * np.sqrt(2.0 * B / gam)
    eps = _TWO_PI * np.sqrt(2.0 * B * gam) - lin * M + extra
    return eps, -ell * tail.dphi_dF, ell * (-tail.dphi_dM - M / (kT * C)) - lin


def end_loop_torque_slope(tail, torque, A, C, kT, physical=True):
    """``d^2 eps / dM^2`` of :func:`end_loop_gibbs` (1/N): the slope of the loop's linking.

    With ``g1 = d gamma/dM = -dphi_tail/dM - M/(kT C)`` and ``l = pi sqrt(2B/gamma)``,
    ``deps/dM = l g1 - 2 pi chi w`` gives
    ``d^2 eps/dM^2 = l (-d^2phi_tail/dM^2 - 1/(kT C)) - l g1^2 / (2 gamma)``
    (0 for the constant loop, ``physical=False``); NaN where ``gamma <= 0``.
    """
    M = np.asarray(torque, float)
    if not physical:
        return np.zeros_like(M)
    gam = -tail.phi - M**2 / (2.0 * kT * C)
    gam = np.where(gam > 0.0, gam, np.nan)
    ell = np.pi * np.sqrt(2.0 * A * kT / gam)
    g1 = -tail.dphi_dM - M / (kT * C)
    return ell * (-tail.d2phi_dM2 - 1.0 / (kT * C)) - ell * g1**2 / (2.0 * gam)
