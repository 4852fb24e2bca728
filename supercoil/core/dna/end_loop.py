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

Everything broadcasts; nothing here imports pint.
"""

from __future__ import annotations

import numpy as np

from supercoil.exceptions import ValidityError

__all__ = [
    "LOOP_WRITHE",
    "buckling_shift",
    "coiled_state",
    "loop_bending_energy",
    "loop_excess_free_energy",
    "loop_length",
    "loop_radius",
    "loop_tension",
    "loop_twist",
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
    """
    gl = np.asarray(gamma, float) - np.asarray(torque, float) ** 2 / (2.0 * C)
    if np.any(~(gl > 0.0)):
        raise ValidityError("end loop undefined: the loop tension gamma - M_p^2/(2 C) must be "
                            f"positive, got {np.min(gl):.6g} N")
    return gl


def loop_radius(gamma_l, B):
    """Radius ``R* = sqrt(B / (2 gamma_l))`` (m) of the end loop [end-loop.md#2-loop]."""
    gamma_l = np.asarray(gamma_l, dtype=float)
    if np.any(~(gamma_l > 0.0)):
        raise ValidityError("end loop undefined: the loop tension gamma_l must be positive, "
                            f"got {np.min(gamma_l):.6g} N")
    return np.sqrt(B / (2.0 * gamma_l))


def loop_length(gamma_l, B):
    """Contour length ``l = 2 pi R*`` (m) taken up by the end loop."""
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
    """
    return length / _TWO_PI * np.sqrt(2.0 * np.asarray(eps, float) / (stiffness * length))


def torque_overshoot(eps, stiffness, length):
    """Torque overshoot ``dM = sqrt(2 eps c / L)`` (N m) just before the jump."""
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
    """
    n = np.asarray(turns_in_plectoneme, dtype=float)
    sB, s = np.sqrt(B), np.sqrt(1.0 / K - 1.0 / C)
    R = sB * length / (_TWO_PI * K * s * (n + sB * s))
    ell = _TWO_PI * R
    D = ell / C + (length - ell) / K
    M = _TWO_PI * n / D
    return loop_bending_energy(R, B) + 0.5 * (_TWO_PI * n) ** 2 / D, M, R
