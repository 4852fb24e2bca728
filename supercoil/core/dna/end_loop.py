"""End loop of a plectoneme: free energy, size and the first-order buckling it causes.

Float-only kernel (SI units). The derivation is in ``docs/theory/end-loop.md``;
it is the package's own estimate, not a formula copied from a paper: the end
loop is a circle of radius R closing the plectoneme, in a two-phase model whose
coexistence free energy is a straight line in the turns N,
``G_line(N) = -gamma L + 2 pi M_p |N|`` (docs/theory/end-loop.md#1-setting).

* The loop has contour ``l = 2 pi R``, bending energy ``E_b = pi B / R``, and
  absorbs ``w`` turns of linking as writhe (``w = 1`` for one closed loop).
* Moving ``l`` of contour out of the coexisting phases into the loop costs
  ``gamma l`` (gamma is the free energy per length of the coexisting state at
  N = 0); the ``w`` turns it absorbs save ``2 pi M_p w``. The loop's excess free
  energy is therefore ``eps(R) = pi B / R + 2 pi R gamma - 2 pi M_p w``, minimal
  at ``R* = sqrt(B / (2 gamma))`` with
  ``eps* = 2 pi sqrt(2 B gamma) - 2 pi M_p w`` (docs/theory/end-loop.md#2-loop).
* With a stretched phase of free energy ``G_s = -L g + (c/2) L (2 pi N / L)^2``
  tangent to the line at ``N_b``, the loop shifts buckling to the crossing
  ``N* = N_b + (L / 2 pi) sqrt(2 eps / (c L))``; the torque overshoots the
  plectoneme torque by ``dM = sqrt(2 eps c / L)`` just before buckling
  (docs/theory/end-loop.md#3-jump). ``c`` is the stretched twist rigidity (N m^2).

Everything broadcasts; nothing here imports pint.
"""

from __future__ import annotations

import numpy as np

from ...exceptions import ValidityError

__all__ = [
    "LOOP_WRITHE",
    "buckling_shift",
    "coiled_loop_radius",
    "loop_bending_energy",
    "loop_excess_free_energy",
    "loop_length",
    "loop_radius",
    "torque_overshoot",
]

#: writhe (turns of linking) absorbed by one closed end loop
LOOP_WRITHE = 1.0
_TWO_PI = 2.0 * np.pi


def loop_radius(gamma, B):
    """Radius ``R* = sqrt(B / (2 gamma))`` (m) of the end loop [end-loop.md#2-loop].

    Parameters
    ----------
    gamma : float or array
        Free energy per length of the coexisting state at zero turns, taken
        positive (N); for Marko's model ``g / (1 - P / c_s)``.
    B : float
        Bending rigidity (N m^2).
    """
    gamma = np.asarray(gamma, dtype=float)
    if np.any(~(gamma > 0.0)):
        raise ValidityError("end loop undefined: the coexisting state's free energy per "
                            f"length gamma must be positive, got {np.min(gamma):.6g} N")
    return np.sqrt(B / (2.0 * gamma))


def loop_length(gamma, B):
    """Contour length ``l = 2 pi R*`` (m) taken up by the end loop."""
    return _TWO_PI * loop_radius(gamma, B)


def loop_bending_energy(radius, B):
    """Bending energy ``pi B / R`` (J) of a circular loop of radius R (contour 2 pi R)."""
    return np.pi * B / np.asarray(radius, dtype=float)


def loop_excess_free_energy(gamma, torque, B, writhe=LOOP_WRITHE):
    """Excess free energy ``eps* = 2 pi sqrt(2 B gamma) - 2 pi M_p w`` (J) of the loop.

    ``eps*`` is the vertical offset of the coexistence line with the loop above the
    line without it [end-loop.md#2-loop]. It is the bending energy plus
    ``gamma l`` minus the work ``2 pi M_p w`` the loop's writhe saves.

    Raises
    ------
    ValidityError
        If ``eps* <= 0``: the loop would lower the coexisting state and buckling
        would not be a jump (happens when ``sqrt(2 B gamma) <= M_p w``).
    """
    eps = _TWO_PI * (np.sqrt(2.0 * B * np.asarray(gamma, float)) - np.asarray(torque) * writhe)
    if np.any(~(eps > 0.0)):
        raise ValidityError(
            "end loop excess free energy 2 pi (sqrt(2 B gamma) - M_p w) is not positive "
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


def coiled_loop_radius(turns_in_plectoneme, length, B, plectoneme_rigidity):
    """Loop radius of a fully coiled molecule (no tail) [end-loop.md#4-fully-coiled].

    Minimising ``pi B / R + (K/2) (2 pi n)^2 / (L - 2 pi R)`` over R, with
    ``n = |N| - w`` the turns held by the plectoneme and ``K = P kT`` its twist
    rigidity, gives ``R = sqrt(B) L / (2 pi (sqrt(B) + n sqrt(K)))``.
    """
    n = np.asarray(turns_in_plectoneme, dtype=float)
    sB = np.sqrt(B)
    return sB * length / (_TWO_PI * (sB + n * np.sqrt(plectoneme_rigidity)))
