"""Moroz-Nelson thermal corrections of the stretched tail, with units.

docs/theory/li-zhao.md#moroz-nelson. Unit wrappers over
:mod:`supercoil.core.dna.moroz_nelson`: the effective twist rigidity
``C_eff`` and the extension factor ``zeta`` of the paper's construction.
"""

from __future__ import annotations

import warnings

import numpy as np

from supercoil import display
from supercoil._checks import broadcast_shape
from supercoil.core.dna import moroz_nelson as _mn
from supercoil.dna import validity as _v
from supercoil.exceptions import ValidityWarning
from supercoil.units import U, magnitude, quantity

__all__ = ["CONVERGED_BRACKET", "effective_twist_rigidity", "extension_factor",
           "long_tail_messages"]

_PN_NM2 = U.pN * U.nm**2

#: Below this Moroz-Nelson bracket Q the long-tail factor 1 - Q^(-1/2)/2 < 0.5: the
#: expansion in 1/sqrt(Q) has not converged and the thermal extension is qualitative.
CONVERGED_BRACKET = 1.0


def long_tail_messages(F, Q, where, at, label="", limits=("", "")):
    """Messages where the tail's long-tail factor ``1 - Q^(-1/2)/2`` is <= 0 or < 0.5.

    Shared by the models with a Moroz-Nelson tail (``li-zhao``, ``free-energy``). ``at(i)``
    names point i (force, turns); ``label`` prefixes the message; ``limits`` are the
    seed-set forces below which each failure happens, for the reader (text).
    """
    Q = np.asarray(Q)
    bad = where & (Q <= 0.25)
    if np.any(bad):
        i = np.flatnonzero(bad)[0]
        return [f"{label}Moroz-Nelson zeta is not valid at {at(i)}: its long-tail factor "
                f"1 - Q^(-1/2)/2 = {1 - 0.5 / np.sqrt(Q.flat[i]):.4g} <= 0 (the extension "
                f"would grow with turns{limits[0]})"]
    rough = where & (Q < CONVERGED_BRACKET)
    if np.any(rough):
        i = np.flatnonzero(rough)[0]
        return [f"{label}Moroz-Nelson expansion not converged at {at(i)}: the long-tail factor "
                f"1 - Q^(-1/2)/2 = {1 - 0.5 / np.sqrt(Q.flat[i]):.3g} < 0.5 (bracket Q < 1), "
                f"so the thermal extension, torque and post-buckling slope are qualitative "
                f"there{limits[1]}"]
    return []


def effective_twist_rigidity(dna, force):
    """Moroz-Nelson effective torsional rigidity of the fluctuating tail.

    ``1/C_eff = 1/C + kT / (4 B sqrt(B T))`` [docs/theory/li-zhao.md#moroz-nelson].

    Returns
    -------
    Quantity [pN nm^2]

    Raises
    ------
    ValueError
        If a force is not positive.
    """
    si = _v.check_dna(dna)
    f = _v.checked_forces(force, one_d=False)
    if not np.all(f > 0):
        raise ValueError(f"force must be positive for C_eff, got {force}")
    c = _mn.effective_twist_rigidity(f, si.bending_rigidity, si.torsional_rigidity, si.kT)
    return quantity(c, U.N * U.m**2).to(_PN_NM2)


def extension_factor(dna, force, torque, tail_length):
    """Moroz-Nelson extension factor zeta of a tail of length l carrying torque M_3.

    ``zeta = 1 - (1/2) Q^(-1/2) + B kT / (l (B T - M_3^2/4))`` with the bracket
    ``Q = B T/kT^2 - M_3^2/(4 kT^2) - 1/32`` [docs/theory/li-zhao.md#moroz-nelson]; the tail's
    end-to-end distance is ``zeta l``. Arguments broadcast.

    Raises
    ------
    ValidityError
        Naming force and torque where ``Q <= 0`` (zeta undefined). With the
        seed set, the plectoneme torque gives Q <= 0 below 0.0954 pN.
    ValueError
        For a non-positive force or tail length.

    Warns
    -----
    ValidityWarning
        Where zeta leaves (0, 1]: zeta <= 0 at low force (long-tail factor
        ``1 - Q^(-1/2)/2 <= 0`` once Q <= 1/4, below 0.122 pN at the seed
        set's plectoneme torque), zeta > 1 for tails of a few persistence
        lengths or less.
    """
    si = _v.check_dna(dna)
    f = _v.checked_forces(force, one_d=False)
    m = magnitude(torque, U.N_m, "torque")
    length = magnitude(tail_length, U.m, "tail_length")
    for name, x, given in (("torque", m, torque), ("tail_length", length, tail_length)):
        if not np.all(np.isfinite(x)):
            raise ValueError(f"{name} must be finite, got {given}")
    broadcast_shape(force=f, torque=m, tail_length=length)
    if not np.all(f > 0):
        raise ValueError(f"force must be positive, got {force}")
    if not np.all(np.asarray(length) > 0):
        raise ValueError(f"tail_length must be positive, got {tail_length}")
    z = _mn.extension_factor(f, m, length, si.bending_rigidity, si.kT)
    outside = ~((z > 0) & (z <= 1))
    if np.any(outside):
        i = np.flatnonzero(outside)[0]
        fb = np.broadcast_to(f, np.shape(z)).flat[i]
        warnings.warn(
            f"Moroz-Nelson zeta = {np.ravel(z)[i]:.4g} lies outside (0, 1] at force "
            f"{display.text(fb, 'force')}: the extension formula is not valid there",
            ValidityWarning,
            stacklevel=2,
        )
    return quantity(z, U.dimensionless)
