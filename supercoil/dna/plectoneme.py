"""DNA plectonemes at fixed force: Marko-Siggia equilibrium and Moroz-Nelson corrections.

docs/theory/plectoneme.md (paper Example III). Unit wrappers over the float kernels
:mod:`supercoil.core.dna.plectoneme` (equilibrium of (GE1), (GE2) and the tension
equation with the Marko-Siggia interaction) and :mod:`supercoil.core.dna.moroz_nelson`.
Every function takes a :class:`~supercoil.dna.material.DNA` and pint quantities of
:data:`supercoil.ureg`, and is vectorised over the force.
"""

from __future__ import annotations

import numpy as np

from supercoil.dna import validity as _v
from supercoil.dna.interactions import DEFAULT_INTERACTION, get_interaction
from supercoil.records import Record

__all__ = ["PlectonemeEquilibrium", "plectoneme_equilibrium"]


class PlectonemeEquilibrium(Record):
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
    DOMAIN = "dna"
    FIELDS = ("force", "alpha", "radius", "pitch", "omega", "torque", "curvature", "torsion",
              "bending_energy", "twist_energy", "interaction_energy")


def plectoneme_equilibrium(dna, force, interaction=DEFAULT_INTERACTION):
    """Plectoneme equilibrium of ``dna`` at fixed ``force`` (docs/theory/plectoneme.md#equations).

    Solves (GE1) ``C omega = (B kappa kappa_alpha + w_alpha)/tau_alpha``, (GE2)
    and the tension equation ``T = -(1/2) B kappa^2 + C omega tau - w``
    [Example III] with the Marko-Siggia ``w``. The physical (stable) branch
    and the method are described in :mod:`supercoil.core.dna.plectoneme`:
    residuals are ~1e-15 relative, no starting guess is needed.

    Parameters
    ----------
    dna : DNA
        The molecule (B, C, r0, t).
    force : Quantity [force]
        Tension T, scalar or array.
    interaction : str or Interaction
        The inter-strand interaction (default ``"hard-core"``, the paper's
        Marko-Siggia ``w``); see :mod:`supercoil.dna.interactions`.

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
    si = _v.check_dna(dna)
    f = _v.checked_forces(force, one_d=False)
    inter = _v.StateRecorder(get_interaction(interaction))
    inter.check(si)
    st = inter.equilibrium(np.atleast_1d(f).ravel(), si)
    _v.warn(_v.force_messages(f) + inter.messages(si), stacklevel=2)
    shape = np.shape(f)
    return PlectonemeEquilibrium(**{k: np.asarray(v).reshape(shape) if shape else float(v[0])
                                    for k, v in zip(st._fields, st, strict=True)})
