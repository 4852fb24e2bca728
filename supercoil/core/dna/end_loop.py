"""End loop of a plectoneme: free energy, size and the first-order buckling it causes.

Float-only kernel (SI units). The derivation is in ``docs/theory/end-loop.md``;
it is the package's own estimate, not a formula copied from a paper: the end
loop is a circle of radius R closing the plectoneme, in a two-phase model whose
coexistence free energy is a straight line in the turns N,
``G_line(N) = -gamma L + 2 pi M_p |N|`` (docs/theory/end-loop.md#1-setting).

* The loop has contour ``l = 2 pi R``, bending energy ``E_b = pi B / R``, absorbs
  ``w`` turns of linking as writhe (``w = 1`` for one closed loop) and, at the
  common torque ``M_p``, ``t = M_p l / (2 pi C)`` turns as twist of bare twist
  rigidity C (twist energy ``M_p^2 l / (2 C)``).
* Moving ``l`` of contour out of the coexisting phases into the loop costs
  ``gamma l``; the linking the loop absorbs saves ``2 pi M_p (w + t)``. The
  excess free energy is ``eps(R) = pi B / R + 2 pi R gamma_l - 2 pi M_p w`` with
  the loop tension ``gamma_l = gamma - M_p^2 / (2 C)``; it is minimal at
  ``R* = sqrt(B / (2 gamma_l))``, where
  ``eps* = 2 pi sqrt(2 B gamma_l) - 2 pi M_p w`` (docs/theory/end-loop.md#2-loop).
* With a stretched phase of free energy ``G_s = -L g + (c/2) L (2 pi N / L)^2``
  tangent to the line at ``N_b``, the loop shifts buckling to the crossing
  ``N* = N_b + (L / 2 pi) sqrt(2 eps / (c L))``; the torque overshoots the
  plectoneme torque by ``dM = sqrt(2 eps c / L)`` just before buckling
  (docs/theory/end-loop.md#3-jump). ``c`` is the stretched twist rigidity (N m^2).

For a tail whose free energy at fixed torque is not quadratic (the free-energy
model's Moroz-Nelson tail), :func:`looped_coexistence` finds the crossing from the
tail's own ``g(M)`` (docs/theory/end-loop.md#7-free-energy).

Everything broadcasts; nothing here imports pint.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from supercoil.exceptions import ValidityError

__all__ = [
    "LOOP_WRITHE",
    "LoopedCoexistence",
    "buckling_shift",
    "coiled_state",
    "loop_bending_energy",
    "loop_excess_free_energy",
    "loop_length",
    "loop_radius",
    "loop_tension",
    "loop_twist",
    "looped_coexistence",
    "torque_overshoot",
]

#: writhe (turns of linking) absorbed by one closed end loop
LOOP_WRITHE = 1.0
_TWO_PI = 2.0 * np.pi


def loop_tension(gamma, torque, C):
    """Loop tension ``gamma_l = gamma - M_p^2 / (2 C)`` (N) [end-loop.md#2-loop].

    Parameters
    ----------
    gamma : float or array
        Free energy per length of the coexisting state at zero turns, taken
        positive (N); for Marko's model ``g / (1 - P / c_s)``.
    torque : float or array
        Coexistence (plectoneme) torque M_p (N m).
    C : float
        Bare twist rigidity of the loop's DNA (N m^2); ``inf`` for a loop that
        stores no twist.

    Raises
    ------
    ValidityError
        If ``gamma_l <= 0``: no loop of finite size.

    Notes
    -----
    Implements docs/theory/end-loop.md (EL1).
    """
    gl = np.asarray(gamma, float) - np.asarray(torque, float) ** 2 / (2.0 * C)
    if np.any(~(gl > 0.0)):
        raise ValidityError("end loop undefined: the loop tension gamma - M_p^2/(2 C) must be "
                            f"positive, got {np.min(gl):.6g} N")
    return gl


def loop_radius(gamma_l, B):
    """Radius ``R* = sqrt(B / (2 gamma_l))`` (m) of the end loop [end-loop.md#2-loop].

    Implements docs/theory/end-loop.md (EL2).
    """
    gamma_l = np.asarray(gamma_l, dtype=float)
    if np.any(~(gamma_l > 0.0)):
        raise ValidityError("end loop undefined: the loop tension gamma_l must be positive, "
                            f"got {np.min(gamma_l):.6g} N")
    return np.sqrt(B / (2.0 * gamma_l))


def loop_length(gamma_l, B):
    """Contour length ``l = 2 pi R*`` (m) taken up by the end loop.

    Implements docs/theory/end-loop.md (EL2).
    """
    return _TWO_PI * loop_radius(gamma_l, B)


def loop_bending_energy(radius, B):
    """Bending energy ``pi B / R`` (J) of a circular loop of radius R (contour 2 pi R)."""
    return np.pi * B / np.asarray(radius, dtype=float)


def loop_twist(torque, loop_contour, C):
    """Turns of twist ``t = M_p l / (2 pi C)`` stored in the loop at torque M_p."""
    return np.asarray(torque, float) * np.asarray(loop_contour, float) / (_TWO_PI * C)


def loop_excess_free_energy(gamma_l, torque, B, writhe=LOOP_WRITHE):
    """Excess free energy ``eps* = 2 pi sqrt(2 B gamma_l) - 2 pi M_p w`` (J) of the loop.

    ``eps*`` is the vertical offset of the coexistence line with the loop above the
    line without it [end-loop.md#2-loop].

    Raises
    ------
    ValidityError
        If ``eps* <= 0``: the loop would lower the coexisting state and buckling
        would not be a jump (happens when ``sqrt(2 B gamma_l) <= M_p w``).

    Notes
    -----
    Implements docs/theory/end-loop.md (EL1, EL2).
    """
    eps = _TWO_PI * (np.sqrt(2.0 * B * np.asarray(gamma_l, float))
                     - np.asarray(torque, float) * writhe)
    if np.any(~(eps > 0.0)):
        raise ValidityError(
            "end loop excess free energy 2 pi (sqrt(2 B gamma_l) - M_p w) is not positive "
            f"({np.min(eps):.6g} J): the loop would not delay buckling"
        )
    return eps


def buckling_shift(eps, stiffness, length):
    """Extra turns ``N* - N_b = (L / 2 pi) sqrt(2 eps / (c L))`` before the jump.

    ``stiffness`` is the stretched phase's twist rigidity c (N m^2) whose
    quadratic free energy ``(c/2) L (2 pi N/L)^2`` the coexistence line touches
    at ``N_b`` [end-loop.md#3-jump].

    Implements docs/theory/end-loop.md (EL4).
    """
    return length / _TWO_PI * np.sqrt(2.0 * np.asarray(eps, float) / (stiffness * length))


def torque_overshoot(eps, stiffness, length):
    """Torque overshoot ``dM = sqrt(2 eps c / L)`` (N m) just before the jump.

    Implements docs/theory/end-loop.md (EL5).
    """
    return np.sqrt(2.0 * np.asarray(eps, float) * stiffness / length)


def coiled_state(turns_in_plectoneme, length, B, K, C):
    """Fully coiled molecule with its end loop (no tail) [end-loop.md#4-fully-coiled].

    ``n = |N| - w`` turns are shared as twist between the loop (contour
    ``l = 2 pi R``, rigidity C) and the plectoneme (length ``L - l``, rigidity
    ``K = P kT``): ``G = pi B / R + (2 pi n)^2 / (2 D)`` with the compliance
    ``D = l / C + (L - l) / K`` and torque ``M = 2 pi n / D``. Minimising over R
    gives ``R = sqrt(B) L / (2 pi K s (n + sqrt(B) s))``, ``s = sqrt(1/K - 1/C)``.

    Returns
    -------
    (G [J], M [N m], R [m]), arrays of n's shape; needs ``n > 0`` and ``K < C``.

    Notes
    -----
    Implements docs/theory/end-loop.md (EL6).
    """
    n = np.asarray(turns_in_plectoneme, dtype=float)
    sB, s = np.sqrt(B), np.sqrt(1.0 / K - 1.0 / C)
    R = sB * length / (_TWO_PI * K * s * (n + sB * s))
    ell = _TWO_PI * R
    D = ell / C + (length - ell) / K
    M = _TWO_PI * n / D
    return loop_bending_energy(R, B) + 0.5 * (_TWO_PI * n) ** 2 / D, M, R


class LoopedCoexistence(NamedTuple):
    """End-loop constants of a coexistence with a general tail (SI arrays per force)."""

    radius: np.ndarray  # R* of the loop, m
    length: np.ndarray  # l = 2 pi R*, m
    linking: np.ndarray  # w + t: turns absorbed by the loop (writhe + twist)
    excess: np.ndarray  # eps*, J
    overshoot_torque: np.ndarray  # M_+ = M* + dM: stretched torque at the jump, N m
    jump_turns: np.ndarray  # N* (> N_b)
    plectoneme_length: np.ndarray  # S at N* (strand length, loop excluded), m
    extension_jump: np.ndarray  # z just below N* minus z just above, m


def looped_coexistence(co, length, B, C, tail, writhe=LOOP_WRITHE, upper_torque=None):
    """End loop on a coexistence whose tail has a general ``g(M)`` [end-loop.md#7-free-energy].

    Parameters
    ----------
    co : Coexistence-like
        Per-force arrays ``force``, ``torque`` (M*), ``free_energy_density``
        (``g* < 0``, J/m), ``tail_linking`` (``l_s*``, rad/m), ``linking_rate``
        (``D = l_p - l_s``, rad/m), ``long_tail_factor`` (``zeta*``).
    length, B, C : float
        Contour length (m), bending and bare twist rigidity (N m^2).
    tail : callable
        ``(force, torque) -> (g, zeta, l)`` of the tail per length at fixed torque
        (concave in the torque: ``l = -dg/dM`` increasing).
    upper_torque : array, optional
        Torque at which ``l`` diverges (the root is bracketed below it); ``None``:
        a quadratic tail ``g = g* - (M^2 - M*^2)/(2C)`` and the closed form
        ``dM = sqrt(2 eps C / L)``.

    Raises
    ------
    ValidityError
        If the loop tension ``-g* - M*^2/(2C)`` or the excess free energy is not
        positive, or the jump does not land in a coexistence with a plectoneme and a
        tail (the molecule is too short: a curl, not modelled, or full coiling).
    """
    M, L = co.torque, length
    gl = loop_tension(-co.free_energy_density, M, C)
    R = loop_radius(gl, B)
    ell = _TWO_PI * R
    link = writhe + loop_twist(M, ell, C)
    bad = ~(np.sqrt(2.0 * B * gl) > M * writhe)
    if np.any(bad):
        i = np.flatnonzero(bad)[0]
        raise ValidityError(
            f"end loop at force {np.ravel(co.force)[i] * 1e12:.6g} pN would not delay buckling: "
            f"its excess free energy 2 pi (sqrt(2 B gamma_l) - w M*) is not positive "
            f"(sqrt(2 B gamma_l) = {np.sqrt(2.0 * B * gl.flat[i]) * 1e21:.4g} pN nm <= w M* = "
            f"{writhe * M.flat[i] * 1e21:.4g} pN nm) [end-loop.md#7-free-energy]")
    eps = loop_excess_free_energy(gl, M, B, writhe)
    if upper_torque is None:
        Mp = M + torque_overshoot(eps, C, L)
    else:  # L [g(M) - g* + l(M) (M - M*)] = eps: increasing in M > M*, -eps at M*
        def excess(m, f, m0, g0, e):
            g, _, lk = tail(f, m)
            return L * (g - g0 + lk * (m - m0)) - e

        from scipy.optimize import elementwise

        res = elementwise.find_root(excess, (M, upper_torque),
                                    args=(co.force, M, co.free_energy_density, eps))
        if not np.all(res.success):  # pragma: no cover - a bracketed monotone root
            raise ValidityError("end loop: no torque overshoot found")
        Mp = res.x
    _, zeta, lk = tail(co.force, Mp)
    Nstar = L * lk / _TWO_PI
    S = (_TWO_PI * (Nstar - link) - (L - ell) * co.tail_linking) / co.linking_rate
    _check_fits(S, L - ell, co.force)
    jump = L * zeta - (L - ell - S) * co.long_tail_factor
    return LoopedCoexistence(R, ell, link, eps, Mp, Nstar, S, jump)


def _check_fits(S, room, force):
    for bad, what in ((~(S >= 0.0), "into a curl (a loop without plectoneme: the looped "
                       "coexistence at the jump would hold a plectoneme of length {:.4g} nm)"),
                      (~(S < room), "straight to full coiling (no tail left: plectoneme "
                       "{:.4g} nm)")):
        if np.any(bad):
            i = np.flatnonzero(bad)[0]
            raise ValidityError(
                f"end loop at force {np.ravel(force)[i] * 1e12:.6g} pN: the molecule is too "
                "short, the stretched state would jump " + what.format(S.flat[i] * 1e9)
                + ", which is not modelled; use a longer molecule [end-loop.md#7-free-energy]")
