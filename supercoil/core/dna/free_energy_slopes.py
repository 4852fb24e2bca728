"""Slopes of the free-energy hat curve in the turns, from its own points. Float-only kernel.

``dz/dN`` and ``dM/dN`` at fixed force in each phase, in closed form from a call's
points (its torque and phase) and the per-force post-buckling slope: the fits' Jacobian
column in the turns offset, instead of a second kernel call at ``N -/+ h``.
Implements docs/theory/free-energy.md (FE10); re-used by
:meth:`supercoil.dna.models.free_energy.FreeEnergy.turn_slopes`.
"""

from __future__ import annotations

import numpy as np

from supercoil.core.dna.interface import PLECTONEME, STRETCHED

__all__ = ["turn_slopes"]

_TWO_PI = 2.0 * np.pi


def turn_slopes(turns, force, torque, phase, slope, length, B, C, kT, thermal=True):
    """``(dz/dN, dM/dN)`` of the free-energy hat points (m and N m per turn).

    Implements docs/theory/free-energy.md (FE10): in the stretched phase the tail's
    linking constraint ``l_s(F, M) = 2 pi |N| / L`` gives ``dM/d|N| = (2 pi / L) / l_M``
    and ``z = L zeta_inf(F, M)`` gives ``dz/d|N| = 2 pi zeta_M / l_M``, with
    ``zeta_M = -M / (8 kT^2 Q^(3/2))`` and
    ``l_M = 1/C + 1/(4 B sqrt Q) + M^2 / (16 B kT^2 Q^(3/2))`` (athermal: ``zeta_M = 0``,
    ``l_M = 1/C``); in the plectoneme phase the post-buckling slope and ``dM/dN = 0``;
    fully coiled ``dz/dN = 0`` and ``dM/dN`` NaN (the branch's slope is not among the
    points: the caller differentiates those numerically). With or without the end loop:
    its stretched points carry no loop, its plectoneme points the same slope.

    Parameters
    ----------
    turns, force, torque, phase : array
        The points' turns N (signed), force F (N), signed torque (N m) and phase codes.
    slope : array
        The post-buckling slope ``dz/dN`` past +N_b at each point's force (m per turn,
        ``Coexistence.slope``).
    length, B, C, kT : float
        Contour length (m), rigidities (N m^2), thermal energy (J).
    thermal : bool
        The Moroz-Nelson tail; False: the athermal one.

    Returns
    -------
    dz_dN, dM_dN : ndarray
        ``dz/dN`` is odd in N (z is even), ``dM/dN`` even (M is odd).
    """
    turns, force, phase = (np.asarray(a) for a in (turns, force, phase))
    M = np.abs(np.asarray(torque, float))
    dz = np.zeros(turns.shape)
    dM = np.full(turns.shape, np.nan)
    s = phase == STRETCHED
    if np.any(s):
        Ms = M[s]
        if thermal:
            f = force[s] if np.ndim(force) else force
            Q = B * f / (kT * kT) - Ms * Ms / (4.0 * kT * kT) - 1.0 / 32.0
            q32 = Q * np.sqrt(Q)
            l_M = 1.0 / C + 1.0 / (4.0 * B * np.sqrt(Q)) + Ms * Ms / (16.0 * B * kT * kT * q32)
            dz[s] = _TWO_PI * (-Ms / (8.0 * kT * kT * q32)) / l_M
            dM[s] = _TWO_PI / (length * l_M)
        else:
            dM[s] = _TWO_PI * C / length
    p = phase == PLECTONEME
    dz[p] = np.broadcast_to(slope, turns.shape)[p]
    dM[p] = 0.0
    return np.sign(turns) * dz, dM
