"""The paper's construction of the hat curve, ``model="li-zhao"``.

Li, Zhao et al., Example III (docs/theory/li-zhao.md): the uniform plectoneme
at the full force F (any interaction), the Moroz-Nelson effective twist
rigidity ``C_eff`` of the fluctuating tail and its extension factor ``zeta``
with the paper's finite-length term; buckling where the tail torque
``C_eff 2 pi N / L`` reaches the plectoneme torque. Kernel:
:mod:`supercoil.core.dna.li_zhao`. ``thermal=False`` is the athermal construction
(``C_eff = C``, ``zeta = 1``). The thermal construction is not derived from
one free energy (its extension and torque violate the Maxwell relation,
docs/theory/free-energy.md#maxwell), so :meth:`free_energy` raises
:class:`~supercoil.exceptions.ModelError`; the athermal limit is
``model="free-energy", thermal=False``.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from supercoil import display as _d
from supercoil.core.dna import li_zhao as _hc
from supercoil.core.dna import moroz_nelson as _mn
from supercoil.core.dna.interface import FULLY_COILED
from supercoil.dna import validity as _v
from supercoil.dna.models.base import Buckling, DNAModel
from supercoil.dna.moroz_nelson import CONVERGED_BRACKET
from supercoil.dna.moroz_nelson import long_tail_messages as _tail_messages
from supercoil.exceptions import ModelError

__all__ = ["CONVERGED_BRACKET", "LiZhao"]



class LiZhao(DNAModel):
    """The paper's plectoneme + Moroz-Nelson tail construction (no parameters of its own)."""

    name = "li-zhao"
    summary = "the paper's construction: plectoneme at the full force, Moroz-Nelson tail"
    parameters: ClassVar[dict] = {}

    def _args(self, dna):
        return (dna.length, dna.bending_rigidity, dna.torsional_rigidity, dna.kT, dna.radius)

    def _buckling(self, force, dna, thermal, interaction):
        eq = interaction.equilibrium(force, dna)
        par = _hc.hat_parameters(force, *self._args(dna), thermal=thermal, check_zeta=False,
                                 equilibrium_state=eq)
        return Buckling(par.buckling_turns, par.torque, par.slope)

    def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
        """Hat-curve points; ``zeta`` and ``bracket`` are not kept (None).

        :meth:`_validity` reads the kernel's summary, and only in a failure region
        recomputes them (zeta as extension / tail, the bracket from the torque).
        """
        return _hc.hat_curve_points(
            turns, force, *self._args(dna), thermal=thermal, short_tail_length=short_tail_length,
            equilibrium_solver=lambda f: interaction.equilibrium(f, dna), diagnostics=False)

    def _free_energy(self, turns, force, dna, thermal, interaction):
        """Not available: raises :class:`~supercoil.exceptions.ModelError` (see the class docs)."""
        if thermal:
            raise ModelError("model 'li-zhao' with thermal=True is not derived from one free "
                             "energy (its extension and torque violate the Maxwell relation, "
                             "docs/theory/free-energy.md#maxwell), so it has none; use "
                             "model='free-energy'")
        raise ModelError("model 'li-zhao' with thermal=False gives no free energy: up to full "
                         "coiling it is exactly model='free-energy', thermal=False (use that), "
                         "and once fully coiled it holds the plateau torque, which no free "
                         "energy does")

    def _turns_at_tail_length(self, force, tail_length, dna, thermal, interaction):
        """Exact: ``N_b + (L - l) D / (2 pi)`` with the linking rate D of the plectoneme
        phase (docs/theory/li-zhao.md#hat-curve)."""
        par = _hc.hat_parameters(force, *self._args(dna), thermal=thermal,
                                 equilibrium_state=interaction.equilibrium(force, dna))
        return par.buckling_turns + (dna.length - tail_length) * par.linking_rate / (2 * np.pi)

    def _slope_validity(self, force, torque, dna, thermal):
        """Messages where the long-tail factor of zeta at the plectoneme torque fails."""
        if not thermal:
            return []
        Q = _mn.zeta_bracket(force, torque, dna.bending_rigidity, dna.kT)
        return long_tail_messages(force, Q, np.ones(np.shape(force), bool))

    def _validity(self, turns, force, points, dna, thermal):
        if not thermal:
            return []
        summary = _v.summary_of(points)
        Q = points.bracket
        if Q is None and (summary is None or not summary.bracket_min >= CONVERGED_BRACKET):
            Q = _mn.zeta_bracket(force, points.torque, dna.bending_rigidity, dna.kT)
        q_min = Q.min() if summary is None else summary.bracket_min  # NaN: the masks below
        if q_min > 0.25:
            # 1 - Q^(-1/2)/2 > 0 and the finite-length term is positive: zeta > 0 at
            # every point with a tail (fully coiled points hold 0), so only zeta > 1
            # at a long tail can fail (the kernel's summary says whether one does)
            if summary is not None and not summary.zeta_over_long_tail:
                zeta_bad = False
            else:
                zeta = _zeta(points, dna)
                zeta_bad = (zeta > 1.0) & ~points.short_tail
        else:
            zeta = _zeta(points, dna)
            zeta_bad = ~points.short_tail & ~((zeta > 0) & (zeta <= 1))
            zeta_bad &= points.phase != FULLY_COILED
        if np.any(zeta_bad):
            i = np.flatnonzero(zeta_bad)[0]
            return [f"Moroz-Nelson zeta = {zeta[i]:.4g} lies outside (0, 1] at force "
                    f"{_d.text(force[i], 'force')}, turns {turns[i]:.6g}: the extension is not "
                    "valid there"]
        if q_min >= CONVERGED_BRACKET:
            return []  # no long-tail message can fire
        return long_tail_messages(force, Q, points.phase != FULLY_COILED, turns)


def _zeta(points, dna):
    """The points' zeta: kept by the kernel, or extension / tail (0 where fully coiled)."""
    if points.zeta is not None:
        return points.zeta
    tail = dna.length - points.plectoneme_length
    return np.divide(points.extension, tail, out=np.zeros_like(tail), where=tail > 0)


def long_tail_messages(F, Q, where, N=None):
    """li-zhao's messages where zeta's long-tail factor fails (the shared check)."""
    def at(i):
        return f"force {_d.text(F[i], 'force')}" + (f", turns {N[i]:.6g}" if N is not None else "")

    return _tail_messages(F, Q, where, at, limits=(
        "", " (below 0.201 pN in the plectoneme phase for the seed set)"))
