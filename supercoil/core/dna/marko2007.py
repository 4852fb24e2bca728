"""Marko's two-phase model of stretched supercoiled DNA (Marko, PRE 76, 021926, 2007).

Float-only kernel (SI units); every formula and its source is in
``docs/theory/marko2007.md``. A stretched worm-like chain coexists with a
plectoneme phase of twist stiffness P. With ``Omega = 2 pi N / L`` the excess twist
density (rad/m; the helical repeat cancels when N is counted in turns):

* stretched (``|N| <= N_b``), free energy per length
  ``-g(F) + (c_s kT / 2) Omega^2`` with ``g = F - sqrt(kT F / A)`` and
  ``c_s = C (1 - (C / 4A) sqrt(kT / (A F)))`` [marko2007.md#2-stretched];
* plectoneme, free energy per length ``(P kT / 2) Omega^2`` (no extension)
  [marko2007.md#3-plectoneme];
* coexistence (common tangent): torque ``M_b = sqrt(2 P kT g / (1 - P / c_s))``
  independent of N, ``G = -L g / (1 - P / c_s) + 2 pi M_b |N|``, tail length
  ``L_s = (Omega_p L - 2 pi |N|) / (Omega_p - Omega_s)`` with
  ``Omega_s = M_b / (c_s kT)``, ``Omega_p = M_b / (P kT)`` [marko2007.md#4-coexistence];
* fully plectonemic for ``L_s <= 0``.

Extension ``z = -dG/dF`` and torque ``M = dG/dN / (2 pi)`` in closed form.
``thermal=False`` is the athermal limit at fixed rigidities (B, C and the
plectoneme's ``P kT``): ``g = F``, ``c_s = C/kT``, stretched extension L.

Optional end loop (:mod:`supercoil.core.dna.end_loop`): the coexisting and fully
plectonemic states carry one loop of radius R; buckling becomes a jump at
``N* > N_b`` where the stretched and looped free energies cross
[end-loop.md#3-jump]. Everything broadcasts; torque carries sign(N).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from supercoil.core.blocks import points_in_blocks
from supercoil.core.dna.interface import FULLY_COILED, PLECTONEME
from supercoil.exceptions import ValidityError

from . import end_loop as _loop

__all__ = [
    "MarkoParameters",
    "MarkoPoints",
    "free_energy",
    "marko_parameters",
    "points",
    "stretched_extension_factor",
    "stretched_twist_stiffness",
    "wlc_free_energy_gain",
]

_TWO_PI = 2.0 * np.pi


class MarkoParameters(NamedTuple):
    """Per-force constants of the model (SI arrays of the force's shape)."""

    force: np.ndarray  # N
    g: np.ndarray  # WLC free energy gain per length g(F), N
    g_prime: np.ndarray  # dg/dF (extension per length of a torsionless chain)
    twist_stiffness: np.ndarray  # c_s, m (a persistence length)
    twist_stiffness_prime: np.ndarray  # dc_s/dF, m/N
    torque: np.ndarray  # coexistence (buckling) torque M_b, N m
    torque_prime: np.ndarray  # dM_b/dF, m
    omega_stretched: np.ndarray  # Omega_s = M_b / (c_s kT), 1/m
    omega_plectoneme: np.ndarray  # Omega_p = M_b / (P kT), 1/m
    extension_factor: np.ndarray  # z/L of the stretched phase at Omega_s
    gamma: np.ndarray  # g / (1 - P/c_s), N
    buckling_turns: np.ndarray  # N_b (tangent point, no loop)
    slope: np.ndarray  # dz/dN in the coexistence for N > 0, m per turn (negative)
    loop_length: np.ndarray  # contour of the end loop, m (0: no loop)
    loop_energy: np.ndarray  # bending + twist energy of the loop, J (0: no loop)
    loop_writhe: np.ndarray  # turns absorbed by the loop as writhe (0: no loop)
    loop_linking: np.ndarray  # writhe + twist turns absorbed by the loop (0: no loop)
    loop_excess: np.ndarray  # excess free energy eps of the loop, J (0: no loop)
    jump_turns: np.ndarray  # N*: where buckling happens (N_b without loop)
    torque_overshoot: np.ndarray  # stretched torque at N* minus M_b, N m
    extension_jump: np.ndarray  # z just below N* minus z just above, m (0: no loop)


class MarkoPoints(NamedTuple):
    """Points of the rotation curve (same-shape SI arrays)."""

    extension: np.ndarray  # m
    torque: np.ndarray  # N m, sign of N
    tail_length: np.ndarray  # stretched length L_s, m
    phase: np.ndarray  # int8: 0 stretched, 1 coexistence, 2 fully plectonemic
    zeta: np.ndarray  # extension / tail length (0 fully coiled)
    free_energy: np.ndarray  # J


def wlc_free_energy_gain(force, A, kT, thermal=True):
    """``g(F) = F - sqrt(kT F / A)`` and ``g'(F) = 1 - sqrt(kT / (A F)) / 2`` (N, 1).

    Athermal: ``g = F``, ``g' = 1`` [marko2007.md#2-stretched].

    Implements docs/theory/marko2007.md (M1).
    """
    force = np.asarray(force, dtype=float)
    if not thermal:
        return force.copy(), np.ones_like(force)
    root = np.sqrt(kT / (A * force))
    return force * (1.0 - root), 1.0 - 0.5 * root


def stretched_twist_stiffness(force, A, Ct, kT, thermal=True):
    """``c_s = C (1 - (C / 4A) sqrt(kT / (A F)))`` (m) and ``dc_s/dF`` (m/N).

    Athermal: ``c_s = C``. It is the first-order expansion of the Moroz-Nelson
    ``C/(1 + (C/4A) sqrt(kT/(A F)))`` [marko2007.md#2-stretched].

    Implements docs/theory/marko2007.md (M2).
    """
    force = np.asarray(force, dtype=float)
    if not thermal:
        return np.full_like(force, Ct), np.zeros_like(force)
    root = np.sqrt(kT / (A * force))
    with np.errstate(over="ignore"):  # C_t >> A: -inf, named by marko_parameters' c_s > P
        x = Ct / (4.0 * A) * root
        return Ct * (1.0 - x), Ct * x / (2.0 * force)


def stretched_extension_factor(omega, force, A, Ct, kT, thermal=True):
    """``z / L = g'(F) - (kT / 2) c_s'(F) Omega^2`` of the stretched phase.

    Implements docs/theory/marko2007.md (M3).
    """
    _, gp = wlc_free_energy_gain(force, A, kT, thermal)
    _, csp = stretched_twist_stiffness(force, A, Ct, kT, thermal)
    return gp - 0.5 * kT * csp * np.asarray(omega, float) ** 2


def _check(bad, force, what):
    if np.any(bad):
        i = np.flatnonzero(np.broadcast_to(bad, np.shape(force)))[0]
        raise ValidityError(f"Marko 2007 model at force {np.ravel(force)[i] * 1e12:.6g} pN: "
                            + what)


def marko_parameters(force, length, A, Ct, P, kT, thermal=True, end_loop=False,
                     loop_writhe=_loop.LOOP_WRITHE):
    """Buckling torque, turns, slope and the end-loop constants at each force.

    Parameters
    ----------
    force : array (N); length L (m); A, Ct, P : bending, twist and plectoneme
        twist persistence lengths (m); kT (J); thermal : bool;
        end_loop : bool; loop_writhe : turns absorbed by the loop.

    Raises
    ------
    ValidityError
        If ``g(F) <= 0`` (needs ``F > kT/A``), ``c_s <= P`` (no coexistence:
        needs ``c_s > P``), the stretched extension at buckling is not
        positive, or (end loop) the loop does not fit: non-positive excess free
        energy, or no plectoneme or no tail at the jump.

    Notes
    -----
    Implements docs/theory/marko2007.md (M4, M6).
    Implements docs/theory/end-loop.md (EL4, EL5) (``end_loop=True``).
    """
    force = np.asarray(force, dtype=float)
    B = A * kT
    g, gp = wlc_free_energy_gain(force, A, kT, thermal)
    _check(~(g > 0.0), force, f"g(F) = F - sqrt(kT F/A) is not positive "
           f"(the formula needs F > kT/A = {kT / A * 1e12:.4g} pN)")
    cs, csp = stretched_twist_stiffness(force, A, Ct, kT, thermal)
    _check(~(cs > P), force, f"stretched twist stiffness c_s = {np.min(cs) * 1e9:.4g} nm is not "
           f"above the plectoneme's P = {P * 1e9:.4g} nm: no buckling (needs c_s > P)")
    q = 1.0 - P / cs
    gamma = g / q
    M = np.sqrt(2.0 * P * kT * gamma)
    # d ln M / dF = (1/2) (g'/g - P c_s' / (c_s (c_s - P)))
    Mp = 0.5 * M * (gp / g - P * csp / (cs * (cs - P)))
    om_s = M / (cs * kT)
    om_p = M / (P * kT)
    zhat = gp - 0.5 * kT * csp * om_s**2
    _check(~(zhat > 0.0), force, "the stretched extension per length at buckling, "
           "g' - (kT/2) c_s' Omega_s^2, is not positive")
    Nb = length * om_s / _TWO_PI
    slope = -_TWO_PI * zhat / (om_p - om_s)
    zero = np.zeros_like(force)
    if not end_loop:
        return MarkoParameters(force, g, gp, cs, csp, M, Mp, om_s, om_p, zhat, gamma, Nb,
                               slope, zero, zero, zero, zero, zero, Nb, zero, zero)
    C = Ct * kT  # bare twist rigidity of the tightly bent loop
    # eps* / (2 pi M_b) = sqrt(A/P - A/C) - w > 0  <=>  P < 1 / (w^2/A + 1/C)
    Pmax = 1.0 / (loop_writhe**2 / A + 1.0 / Ct)
    _check(np.full(force.shape, not P < Pmax), force, "the end loop would not delay "
           f"buckling (its excess free energy is not positive): needs P < 1/(w^2/A + 1/C) = "
           f"{Pmax * 1e9:.4g} nm, got P = {P * 1e9:.4g} nm [end-loop.md#2-loop]")
    gl = _loop.loop_tension(gamma, M, C)
    R = _loop.loop_radius(gl, B)
    ell = _TWO_PI * R
    # loop energy: bending + twist at the common torque; linking: writhe + twist
    El = _loop.loop_bending_energy(R, B) + M**2 * ell / (2.0 * C)
    link = loop_writhe + _loop.loop_twist(M, ell, C)
    eps = _loop.loop_excess_free_energy(gl, M, B, loop_writhe)
    Nstar = Nb + _loop.buckling_shift(eps, cs * kT, length)
    dM = _loop.torque_overshoot(eps, cs * kT, length)
    Ls = (om_p * (length - ell) - _TWO_PI * (Nstar - link)) / (om_p - om_s)
    _check(~(Ls > 0.0), force, "with the end loop the molecule is too short: the stretched "
           "state would jump straight to a fully coiled one")
    # plectoneme length at N* >= 0  <=>  L >= c (2 pi (w + t) - Omega_s l)^2 / (2 eps)
    Lmin = cs * kT * (_TWO_PI * link - om_s * ell) ** 2 / (2.0 * eps)
    _check(~(Ls < length - ell), force, "with the end loop the molecule is too short: the "
           "jump would go into a curl (a loop without plectoneme), which is not modelled; "
           f"needs L >= {np.max(Lmin) * 1e9:.4g} nm [end-loop.md#3-jump]")
    w = np.full_like(force, loop_writhe)
    # [end-loop.md#3-jump]: stretched z at N* minus the looped coexistence's L_s zhat_s
    om_star = _TWO_PI * Nstar / length
    jump = length * (gp - 0.5 * kT * csp * om_star**2) - Ls * zhat
    return MarkoParameters(force, g, gp, cs, csp, M, Mp, om_s, om_p, zhat, gamma, Nb, slope,
                           ell, El, w, link, eps, Nstar, dM, jump)


def points(turns, force, length, A, Ct, P, kT, thermal=True, end_loop=False,
           loop_writhe=_loop.LOOP_WRITHE):
    """Extension, torque, tail length, phase and free energy at (N, F).

    ``turns`` and ``force`` broadcast. The free energy is relative to the
    straight, untwisted, unstretched chain [marko2007.md#5-summary].

    Implements docs/theory/marko2007.md (M3, M5).
    Implements docs/theory/end-loop.md (EL3) (``end_loop=True``).
    """
    turns, force = np.broadcast_arrays(np.asarray(turns, float), np.asarray(force, float))
    shape = turns.shape
    flat = force.reshape(-1)
    one = flat.size > 0 and flat.min() == flat.max()
    uf = flat[:1].copy() if one else np.unique(flat)
    per_force = marko_parameters(uf, length, A, Ct, P, kT, thermal, end_loop, loop_writhe)

    def block(N, F):  # the per-force constants: scalars for one force, else gathered
        at = 0 if one else np.searchsorted(uf, F)
        par = MarkoParameters(*(a[at] for a in per_force))
        return _points(N, F, par, length, A, Ct, P, kT, thermal, end_loop)

    out = points_in_blocks(block, turns.reshape(-1), flat, BLOCK)
    if len(shape) == 1:  # the arrays themselves (owned: the public layer scales them in place)
        return out
    return MarkoPoints(*(a.reshape(shape) for a in out))


#: points per block of :func:`points` (the per-point temporaries are ~10 arrays:
#: peak memory 3.1x the public table at 1e6 points unblocked)
BLOCK = 1 << 15


def _points(turns, force, par, length, A, Ct, P, kT, thermal, end_loop):
    """:func:`points` on 1-D arrays of one block; ``par`` its per-point (or scalar) constants."""
    n, sign = np.abs(turns), np.sign(turns)
    L, K = length, P * kT
    omega = _TWO_PI * n / L
    # stretched branch
    G = L * (-par.g + 0.5 * par.twist_stiffness * kT * omega**2)
    zeta = stretched_extension_factor(omega, force, A, Ct, kT, thermal)
    M = par.twist_stiffness * kT * omega
    tail = np.full(turns.shape, L)
    phase = np.zeros(turns.shape, np.int8)
    # coexistence of a tail, a plectoneme and (optionally) the end loop
    ell, link = par.loop_length, par.loop_linking
    om_s, om_p = par.omega_stretched, par.omega_plectoneme
    Ls = (om_p * (L - ell) - _TWO_PI * (n - link)) / (om_p - om_s)
    co = (n > par.jump_turns) & (Ls > 0.0)
    Gc = -(L - ell) * par.gamma + _TWO_PI * par.torque * (n - link) + par.loop_energy
    G = np.where(co, Gc, G)
    zeta = np.where(co, par.extension_factor, zeta)
    M = np.where(co, par.torque, M)
    tail = np.where(co, Ls, tail)
    phase[co] = PLECTONEME
    # fully plectonemic
    full = (n > par.jump_turns) & ~co
    if np.any(full):
        nf = (n - par.loop_writhe)[full]
        if end_loop:
            Gf, Mf, _ = _loop.coiled_state(nf, L, A * kT, K, Ct * kT)
        else:
            Gf, Mf = 0.5 * K * (_TWO_PI * nf) ** 2 / L, K * _TWO_PI * nf / L
        G[full], M[full], zeta[full], tail[full] = Gf, Mf, 0.0, 0.0
        phase[full] = FULLY_COILED
    return MarkoPoints(zeta * tail, sign * M, tail, phase, zeta, G)


def free_energy(turns, force, length, A, Ct, P, kT, thermal=True, end_loop=False,
                loop_writhe=_loop.LOOP_WRITHE):
    """Free energy G(N, F) (J) of the three regimes [marko2007.md#5-summary].

    Implements docs/theory/marko2007.md (M1, M5).
    """
    return points(turns, force, length, A, Ct, P, kT, thermal, end_loop,
                  loop_writhe).free_energy
