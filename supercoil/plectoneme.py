"""DNA plectonemes at fixed force: Marko-Siggia equilibrium and Moroz-Nelson corrections.

MODEL.md section 6 (paper Example III). Unit wrappers over the float kernels
:mod:`supercoil.core.plectoneme` (equilibrium of (GE1), (GE2) and the tension
equation with the Marko-Siggia interaction) and :mod:`supercoil.core.moroz_nelson`.
Every function takes a :class:`~supercoil.materials.DNA` and pint quantities of
:data:`supercoil.ureg`, and is vectorised over the force.
"""

from __future__ import annotations

import warnings
from typing import ClassVar

import numpy as np

from .core import moroz_nelson as _mn
from .core import plectoneme as _pl
from .core.hat_curve import OVERSTRETCHING_FORCE
from .exceptions import ValidityWarning
from .materials import DNA
from .units import QuantityRecord, U, magnitude, quantity

__all__ = [
    "PlectonemeEquilibrium",
    "effective_twist_rigidity",
    "extension_factor",
    "plectoneme_equilibrium",
]

_PN_NM2 = U.pN * U.nm**2


class PlectonemeEquilibrium(QuantityRecord):
    """Plectoneme equilibrium at fixed force (quantities of the force's shape).

    Fields (built on first access from the kernel's SI arrays): ``force`` (pN),
    ``alpha`` (rad, tilt angle arctan(2 pi R / P)), ``radius`` (nm,
    superhelix radius R), ``pitch`` (nm), ``omega`` (1/nm, twist density in
    the helix), ``torque`` (pN nm, M_3 = C omega), ``curvature`` and
    ``torsion`` (1/nm), and the energies per unit strand length (pN = pN nm/nm)
    ``bending_energy`` (B kappa^2 / 2), ``twist_energy`` (C omega^2 / 2) and
    ``interaction_energy`` (Marko-Siggia w). Iterates like a named tuple.
    """

    __slots__ = ()
    FIELDS: ClassVar[dict] = {
        "force": (U.pN, 1e12),
        "alpha": (U.rad, 1.0),
        "radius": (U.nm, 1e9),
        "pitch": (U.nm, 1e9),
        "omega": (U.per_nm, 1e-9),
        "torque": (U.pN_nm, 1e21),
        "curvature": (U.per_nm, 1e-9),
        "torsion": (U.per_nm, 1e-9),
        "bending_energy": (U.pN, 1e12),
        "twist_energy": (U.pN, 1e12),
        "interaction_energy": (U.pN, 1e12),
    }


def _check_dna(dna):
    if not isinstance(dna, DNA):
        raise TypeError(f"dna must be a supercoil.DNA, got {type(dna).__name__}")
    return dna.si


def _force(force):
    f = magnitude(force, U.N, "force")
    if not np.all(np.isfinite(f)):
        raise ValueError(f"force must be finite, got {force}")
    return f


def plectoneme_equilibrium(dna, force):
    """Plectoneme equilibrium of ``dna`` at fixed ``force`` (MODEL.md s.6, s.2).

    Solves (GE1) ``C omega = (B kappa kappa_alpha + w_alpha)/tau_alpha``, (GE2)
    and the tension equation ``T = -(1/2) B kappa^2 + C omega tau - w``
    [Example III] with the Marko-Siggia ``w``. The physical (stable) branch
    and the method are described in :mod:`supercoil.core.plectoneme`:
    residuals are ~1e-15 relative, no starting guess is needed.

    Parameters
    ----------
    dna : DNA
        The molecule (B, C, r0, t).
    force : Quantity [force]
        Tension T, scalar or array.

    Returns
    -------
    PlectonemeEquilibrium
        alpha (rad), radius and pitch (nm), omega (1/nm), torque (pN nm),
        curvature and torsion (1/nm), energy densities (pN).

    Raises
    ------
    NoEquilibriumError
        Naming the force, for a non-positive force or one so large that
        R < r0/2.
    pint.DimensionalityError
        If ``force`` is not a force.
    """
    si = _check_dna(dna)
    f = _force(force)
    st = _pl.equilibrium(f, si.bending_rigidity, si.torsional_rigidity, si.kT, si.radius)
    warn_force_range(f)
    tight = st.radius < si.radius
    if np.any(tight):
        warnings.warn(
            f"at {np.max(np.atleast_1d(f)[np.atleast_1d(tight)]) * 1e12:.6g} pN the superhelix "
            f"radius R < r0 = {si.radius * 1e9:.6g} nm: the strands are pressed inside the "
            "Marko-Siggia hard-core radius (above ~30 pN for the seed set), where the "
            "interaction is extrapolated", ValidityWarning, stacklevel=2)
    return PlectonemeEquilibrium(**st._asdict())


def warn_force_range(force):
    """ValidityWarning for forces above the B-DNA overstretching plateau (~65 pN)."""
    over = np.asarray(force) > OVERSTRETCHING_FORCE
    if np.any(over):
        warnings.warn(
            f"force {np.max(np.asarray(force)[over]) * 1e12:.6g} pN is above "
            f"{OVERSTRETCHING_FORCE * 1e12:g} pN, where B-DNA overstretches; the model "
            "(inextensible DNA) ignores it", ValidityWarning, stacklevel=3)


def effective_twist_rigidity(dna, force):
    """Moroz-Nelson effective torsional rigidity of the fluctuating tail.

    ``1/C_eff = 1/C + kT / (4 B sqrt(B T))`` [MODEL.md s.6].

    Returns
    -------
    Quantity [pN nm^2]

    Raises
    ------
    ValueError
        If a force is not positive.
    """
    si = _check_dna(dna)
    f = _force(force)
    if not np.all(f > 0):
        raise ValueError(f"force must be positive for C_eff, got {force}")
    c = _mn.effective_twist_rigidity(f, si.bending_rigidity, si.torsional_rigidity, si.kT)
    return quantity(c * 1e30, _PN_NM2)


def extension_factor(dna, force, torque, tail_length):
    """Moroz-Nelson extension factor zeta of a tail of length l carrying torque M_3.

    ``zeta = 1 - (1/2) Q^(-1/2) + B kT / (l (B T - M_3^2/4))`` with the bracket
    ``Q = B T/kT^2 - M_3^2/(4 kT^2) - 1/32`` [MODEL.md s.6]; the tail's
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
    si = _check_dna(dna)
    f = _force(force)
    m = magnitude(torque, U.N_m, "torque")
    length = magnitude(tail_length, U.m, "tail_length")
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
            f"{fb * 1e12:.6g} pN: the extension formula is not valid there",
            ValidityWarning,
            stacklevel=2,
        )
    return quantity(z, U.dimensionless)
