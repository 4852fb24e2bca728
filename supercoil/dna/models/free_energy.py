"""``model="free-energy"``: the thermodynamically consistent hat curve.

One free energy ``G(N, F) = min_S max_M [(L - S) g_s(F, M) + S g_p(M) + 2 pi N M]``
of a Moroz-Nelson tail and a uniform plectoneme sharing the torque M; extension
``z = -dG/dF`` and torque ``M = (1/2 pi) dG/dN`` satisfy the Maxwell relation
``dz/dN|_F = -2 pi dM/dF|_N`` exactly. Derivation, limits and the validity
table: docs/theory/free-energy.md; kernel :mod:`supercoil.core.dna.free_energy`.
No own parameters; the plectoneme comes from the ``interaction`` (its
``equilibrium(T, dna)`` at the tail's effective pull). The optional end loop
(``end_loop=True``, off by default) makes buckling a jump in extension and
torque with G continuous (docs/theory/end-loop.md#7-free-energy).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from supercoil import display as _d
from supercoil.core.dna import free_energy as _fe
from supercoil.core.dna import free_energy_slopes as _slopes
from supercoil.core.dna.interface import FULLY_COILED
from supercoil.dna.models.base import Buckling, DNAModel, HatPoints
from supercoil.dna.moroz_nelson import CONVERGED_BRACKET
from supercoil.dna.moroz_nelson import long_tail_messages as _tail_messages
from supercoil.exceptions import SupercoilError, ValidityError

__all__ = ["CONVERGED_BRACKET", "FreeEnergy"]



def _args(dna):
    return dna.length, dna.bending_rigidity, dna.torsional_rigidity, dna.kT


def _equilibrium(interaction, dna):
    def eq(T):
        return interaction.equilibrium(T, dna)

    return eq


class FreeEnergy(DNAModel):
    """Hat curve from one free energy: Maxwell-consistent extension and torque.

    Differs from ``li-zhao`` (the paper's construction) in three places, each
    forced by the free energy (docs/theory/free-energy.md#maxwell): the tail twists
    with the Moroz-Nelson compliance at its own torque,
    ``1/C_eff = 1/C + 1/(4 B sqrt(Q))``; the plectoneme coexists with a tail
    that pulls with ``T_eff = F - (kT^2/B) sqrt(Q)`` instead of F; and there is
    no finite-length term (short tails are flagged). ``thermal=False`` is the
    athermal li-zhao construction exactly.

    Parameters
    ----------
    end_loop : bool
        Option (not a fitted parameter): the plectoneme carries one circular end
        loop (writhe 1, twist at the common torque), docs/theory/end-loop.md#7-free-energy
        (default False: the model without the loop, unchanged).
    """

    name = "free-energy"
    summary = ("Moroz-Nelson tail and plectoneme from one free energy: "
               "Maxwell-consistent extension and torque")
    parameters: ClassVar[dict] = {}
    OPTIONS: ClassVar[dict] = {"end_loop": False}

    def __repr__(self):
        return f"FreeEnergy(end_loop={self.end_loop})"

    def loop_constants(self, force, dna, thermal, interaction):
        """End-loop constants at each force (SI): loop size, eps*, N*, jump, overshoot.

        Returns ``(Coexistence, LoopedCoexistence)`` whatever ``end_loop``
        (docs/theory/end-loop.md#7-free-energy).
        """
        co = _fe.coexistence(np.asarray(force, float), *_args(dna),
                             _equilibrium(interaction, dna), thermal)
        return co, _fe.loop_constants(co, *_args(dna), thermal)

    def has_free_energy(self, thermal: bool) -> bool:
        """True for both ``thermal=True`` and ``thermal=False``."""
        return True

    def _plectoneme_tension(self, force, dna, thermal, interaction):
        """The tail's effective pull ``T_eff = F - (kT^2/B) sqrt(Q*)`` at the coexistence
        (docs/theory/free-energy.md#coexistence).

        Raises
        ------
        ValidityError
            Naming the force where the model has no tail-plectoneme coexistence.
        """
        try:
            co = _fe.coexistence(force, *_args(dna), _equilibrium(interaction, dna), thermal)
        except SupercoilError as exc:
            raise ValidityError(f"free-energy model: no tail-plectoneme coexistence at "
                                f"{_d.text(force[0], 'force', 'g')} "
                                f"({type(exc).__name__}: {exc})") from exc
        return co.pull

    def _buckling(self, force, dna, thermal, interaction):
        """Buckling turns ``N_b = L l_s(F, M*)/(2 pi)``, torque M*, slope ``-2 pi zeta_inf / D``.

        With the end loop the turns are those of the jump, ``N* > N_b``.

        Raises
        ------
        ValidityError
            (thermal) naming the force where no coexistence exists (below
            0.0946 pN and above 44.04 pN for the seed set) or ``D <= 0``.
        NoEquilibriumError
            From the interaction, where no plectoneme exists.
        """
        co = _fe.coexistence(force, *_args(dna), _equilibrium(interaction, dna), thermal)
        if self.end_loop:
            return Buckling(_fe.loop_constants(co, *_args(dna), thermal).jump_turns,
                            co.torque, co.slope)
        return Buckling(co.buckling_turns, co.torque, co.slope)

    def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
        """Hat-curve points with the ``free_energy`` column (J).

        The secant's trial tensions of fully coiled points go to
        ``interaction.unrecorded()`` (the public layer records only the final states for
        its shared checks). The interaction's :meth:`kernel_memo` (a fit's) keeps the
        C-free pull and fully coiled branch across calls.
        """
        bare = interaction.unrecorded()
        trial = None if bare is interaction else _equilibrium(bare, dna)
        p = _fe.hat_points(turns, force, *_args(dna), _equilibrium(interaction, dna), thermal,
                           short_tail_length, trial_equilibrium=trial, end_loop=self.end_loop,
                           memo=interaction.kernel_memo(dna))
        return HatPoints(p.extension, p.torque, p.plectoneme_length, p.phase, p.short_tail,
                         p.zeta, p.free_energy)

    def _turn_slopes(self, turns, force, dna, thermal, interaction, points):
        """Closed forms per phase (docs/theory/free-energy.md, FE10;
        :func:`supercoil.core.dna.free_energy_slopes.turn_slopes`); ``dM/dN`` is NaN at
        fully coiled points."""
        uf, inv = np.unique(force, return_inverse=True)
        co = _fe.coexistence(uf, *_args(dna), _equilibrium(interaction, dna), thermal,
                             interaction.kernel_memo(dna))
        return _slopes.turn_slopes(turns, force, points.torque, points.phase,
                                   co.slope[inv], *_args(dna), thermal)

    def _free_energy(self, turns, force, dna, thermal, interaction):
        """``G(N, F)`` (J), docs/theory/free-energy.md#coexistence (up to a constant)."""
        return self._points(turns, force, dna, thermal, interaction, None).free_energy

    def _slope_validity(self, force, torque, dna, thermal):
        """Messages where the tail's expansion fails at the coexistence torque."""
        if not thermal:
            return []
        return _messages(force, _fe.tail_bracket(force, torque, dna.bending_rigidity, dna.kT),
                         np.ones(force.shape, bool),
                         lambda i: f"force {_d.text(force[i], 'force')}")

    def _validity(self, turns, force, points, dna, thermal):
        """Messages where the tail's expansion fails (zeta_inf <= 0, or bracket Q < 1)."""
        if not thermal:
            return []
        force = np.asarray(force, float)
        turns = np.asarray(turns, float)
        torque, phase = np.asarray(points.torque, float), np.asarray(points.phase)
        if _converged_everywhere(force, torque, phase, dna):
            return []
        where = phase != FULLY_COILED
        Q = _fe.tail_bracket(force, torque, dna.bending_rigidity, dna.kT)

        def at(i):
            return f"force {_d.text(force.flat[i], 'force')}, turns {turns.flat[i]:.6g}"

        return _messages(force, Q, where, at)


def _converged_everywhere(force, torque, phase, dna, block=1 << 15):
    """The tail's bracket Q >= 1 at every point that is not fully coiled (then no message).

    Block by block, a reduction each (no array of the points' size: the
    messages below need Q's masks only where this fails; NaN fails it).
    """
    for start in range(0, force.size, block):
        sl = slice(start, start + block)
        where = phase[sl] != FULLY_COILED
        if not where.any():
            continue
        Q = _fe.tail_bracket(force[sl][where], torque[sl][where], dna.bending_rigidity, dna.kT)
        if not Q.min() >= CONVERGED_BRACKET:
            return False
    return True


def _messages(force, Q, where, at):
    """The shared Moroz-Nelson tail check, with the free-energy model's seed-set limits."""
    return _tail_messages(force, Q, where, at, "free-energy model: ", (
        "; below 0.1123 pN for the seed set", " (below 0.1817 pN for the seed set)"))

