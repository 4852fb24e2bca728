"""Moroz-Nelson thermal corrections of a fluctuating DNA tail. Float-only.

docs/theory/li-zhao.md#moroz-nelson.

* Effective torsional rigidity of the tail under tension T:
  ``1/C_eff = 1/C + kT / (4 B sqrt(B T))``.
* Extension factor of a tail of length l carrying torque M_3:
  ``zeta = 1 - (1/2) Q^(-1/2) + B kT / (l (B T - M_3^2/4))`` with the bracket
  ``Q = B T/(kT)^2 - M_3^2/(4 (kT)^2) - 1/32``.

zeta is defined only while ``Q > 0``. The first two terms,
``zeta_inf = 1 - Q^(-1/2)/2``, are the long-tail limit; the last term makes the
end-to-end distance ``zeta l`` tend to ``B kT / (B T - M_3^2/4)`` (not 0) as
l -> 0, so the formula is meaningless once the tail is shorter than a few
bending persistence lengths. ``zeta_inf <= 0`` once ``Q <= 1/4``.
Everything broadcasts; SI floats.
"""

from __future__ import annotations

import numpy as np

from supercoil.exceptions import ValidityError

__all__ = [
    "check_bracket",
    "effective_twist_rigidity",
    "extension_factor",
    "long_tail_factor",
    "twist_rigidity_ratio",
    "zeta_bracket",
]


def twist_rigidity_ratio(force, B, C, kT):
    """``C / C_eff = 1 + C kT / (4 B sqrt(B T))`` (> 1).

    Implements docs/theory/li-zhao.md (LZ1).
    """
    f = np.asarray(force, float)
    with np.errstate(divide="ignore", over="ignore", under="ignore"):
        bt = B * f
        ratio = 1.0 + C * kT / (4.0 * B * np.sqrt(bt))
        # T below ~1e-280 N: B T underflows; sqrt(B) sqrt(T) stays exact there
        tiny = bt < np.finfo(float).tiny
        if np.any(tiny):
            ratio = np.where(tiny, 1.0 + C * kT / (4.0 * B * np.sqrt(B) * np.sqrt(f)), ratio)
    return ratio


def effective_twist_rigidity(force, B, C, kT):
    """Moroz-Nelson ``C_eff`` (N m^2): ``1/C_eff = 1/C + kT / (4 B sqrt(B T))``.

    Implements docs/theory/li-zhao.md (LZ1).
    """
    return C / twist_rigidity_ratio(force, B, C, kT)


def zeta_bracket(force, torque, B, kT):
    """``Q = B T/kT^2 - M_3^2/(4 kT^2) - 1/32`` (dimensionless).

    Implements docs/theory/li-zhao.md (LZ2).
    """
    m = np.asarray(torque, float) / kT
    return B * np.asarray(force, float) / (kT * kT) - 0.25 * m * m - 1.0 / 32.0


def check_bracket(Q, force, torque, what="Moroz-Nelson extension factor"):
    """Raise :class:`ValidityError` naming ``what``, force and torque where ``Q <= 0``."""
    Q, force, torque = np.broadcast_arrays(Q, force, torque)
    bad = ~(Q > 0.0)
    if np.any(bad):
        i = np.flatnonzero(bad)[0]
        raise ValidityError(
            f"{what} undefined at force "
            f"{force.flat[i] * 1e12:.6g} pN, torque {torque.flat[i] * 1e21:.6g} pN nm: "
            f"its bracket B T/kT^2 - M^2/(4 kT^2) - 1/32 = {Q.flat[i]:.4g} is not positive"
        )


def long_tail_factor(force, torque, B, kT, check=True):
    """``zeta_inf = 1 - Q^(-1/2) / 2``, the l -> infinity limit of zeta (= dz/dl)."""
    Q = zeta_bracket(force, torque, B, kT)
    if check:
        check_bracket(Q, force, torque)
    return 1.0 - 0.5 / np.sqrt(Q)


def extension_factor(force, torque, tail_length, B, kT, check=True):
    """Moroz-Nelson ``zeta(M_3, l)``: end-to-end distance over contour length of the tail.

    Implements docs/theory/li-zhao.md (LZ2).

    Parameters
    ----------
    force : float or array
        Tension T (N).
    torque : float or array
        Tail torque M_3 (N m); only M_3^2 enters.
    tail_length : float or array
        Tail length l = L - S (m), positive.
    B, kT : float
        Bending rigidity (N m^2), thermal energy (J).
    check : bool
        Raise :class:`ValidityError` where the bracket is not positive.
    """
    force = np.asarray(force, float)
    torque = np.asarray(torque, float)
    Q = zeta_bracket(force, torque, B, kT)
    if check:
        check_bracket(Q, force, torque)
    return (1.0 - 0.5 / np.sqrt(Q)
            + B * kT / (np.asarray(tail_length, float) * (B * force - 0.25 * torque * torque)))
