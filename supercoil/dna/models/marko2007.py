"""``model="marko2007"``: Marko's two-phase model (J. F. Marko, PRE 76, 021926, 2007).

A stretched worm-like chain coexisting with a plectoneme phase of effective
twist stiffness P; closed forms in :mod:`supercoil.core.dna.marko2007`,
derivation and sources in ``docs/theory/marko2007.md``. The optional end loop
(``end_loop=True``) makes buckling a jump in extension and torque
(``docs/theory/end-loop.md``).

``thermal=False`` is the athermal limit at fixed rigidities: ``g(F) = F``,
``c_s = C`` and a stretched extension equal to L; the plectoneme keeps its twist
rigidity ``P kT``.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from supercoil import display
from supercoil.core.dna import end_loop as _loop
from supercoil.core.dna import marko2007 as _mk
from supercoil.core.dna.interface import SHORT_TAIL_PERSISTENCE_LENGTHS
from supercoil.dna.model_parameters import ModelParameter
from supercoil.dna.models.base import Buckling, DNAModel, HatPoints

__all__ = ["LOW_FORCE_FACTOR", "Marko2007"]

#: below ``LOW_FORCE_FACTOR kT / A`` the high-force expansions are warned about
#: (at 4 kT/A, z/L of the expansion is 2.3 % above the Marko-Siggia
#: interpolation and c_s is 5 % below the Moroz-Nelson resummation for the seed
#: set; docs/theory/marko2007.md#6-validity)
LOW_FORCE_FACTOR = 4.0


class Marko2007(DNAModel):
    """Marko's (2007) stretched/plectoneme coexistence with an optional end loop.

    Parameters
    ----------
    plectoneme_twist_persistence : Quantity [length] or float (m)
        P, the plectoneme phase's effective twist stiffness (default 24 nm).
    end_loop_writhe : float
        Turns of linking absorbed by the end loop, a plain number (default 1);
        used only with ``end_loop=True``.
    end_loop : bool
        Option (not a fitted parameter): add the plectoneme end loop of
        ``docs/theory/end-loop.md`` (default False).
    """

    name: ClassVar[str] = "marko2007"
    summary: ClassVar[str] = ("Marko 2007 two-phase model: WLC tail + plectoneme of twist "
                              "stiffness P, closed form; optional end loop")
    uses_interaction: ClassVar[bool] = False
    parameters: ClassVar[dict[str, ModelParameter]] = {
        "plectoneme_twist_persistence": ModelParameter(
            "plectoneme_twist_persistence", "nm", 24e-9, 5e-9, 80e-9,
            "P: effective twist stiffness of the plectoneme phase",
            "P = 24 nm for bare DNA: comment of DNA_fiber_twisted.m in "
            "github.com/arturrsl/MT-chromatin-torsionally-constrained (A. Kaczmarczyk, "
            "2018; salt not stated there); Marko (2007) gives no single value in its "
            "abstract"),
        "end_loop_writhe": ModelParameter(
            "end_loop_writhe", "", _loop.LOOP_WRITHE, 0.5, 1.5,
            "turns of linking absorbed as writhe by the plectoneme end loop",
            "one closed loop, docs/theory/end-loop.md#2-loop (the package's estimate)"),
    }

    OPTIONS: ClassVar[dict] = {"end_loop": False}

    def __repr__(self):
        P = display.text(self.values["plectoneme_twist_persistence"], "length")
        w = self.values["end_loop_writhe"]
        return (f"Marko2007(plectoneme_twist_persistence={P}, end_loop_writhe={w:g}, "
                f"end_loop={self.end_loop})")

    def has_free_energy(self, thermal: bool) -> bool:
        """True for both settings: G(N, F) is closed form (athermal limit included)."""
        return True

    # ---- float level --------------------------------------------------------------
    def _args(self, dna, thermal):
        return (dna.length, dna.bending_persistence, dna.twist_persistence,
                self.values["plectoneme_twist_persistence"], dna.kT, bool(thermal),
                self.end_loop, self.values["end_loop_writhe"])

    def parameters_at(self, force, dna, thermal):
        """The kernel's :class:`~supercoil.core.dna.marko2007.MarkoParameters`."""
        L, A, Ct, P, kT, th, loop, w = self._args(dna, thermal)
        return _mk.marko_parameters(np.asarray(force, float), L, A, Ct, P, kT, th, loop, w)

    def _buckling(self, force, dna, thermal, interaction):
        """Turns at the (possibly jumping) buckling, plectoneme torque, slope."""
        par = self.parameters_at(force, dna, thermal)
        return Buckling(par.jump_turns, par.torque, par.slope)

    def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
        """Extension, torque, plectoneme length (with the loop), phase, free energy."""
        L, A, Ct, P, kT, th, loop, w = self._args(dna, thermal)
        pt = _mk.points(turns, force, L, A, Ct, P, kT, th, loop, w)
        if short_tail_length is None:
            short_tail_length = SHORT_TAIL_PERSISTENCE_LENGTHS * A
        return HatPoints(pt.extension, pt.torque, L - pt.tail_length, pt.phase,
                         pt.tail_length < short_tail_length, pt.zeta, pt.free_energy)

    def _free_energy(self, turns, force, dna, thermal, interaction):
        """G(N, F) in J (relative to the straight, untwisted, unstretched chain)."""
        L, A, Ct, P, kT, th, loop, w = self._args(dna, thermal)
        return _mk.free_energy(turns, force, L, A, Ct, P, kT, th, loop, w)

    def _validity(self, turns, force, points, dna, thermal):
        """Messages for forces where the high-force expansions are inaccurate."""
        if not thermal:
            return []
        limit = LOW_FORCE_FACTOR * dna.kT / dna.bending_persistence
        f = np.asarray(force, float)
        if np.any(f < limit):
            return [f"marko2007: force {display.text(np.min(f), 'force', '.4g')} is below "
                    f"{LOW_FORCE_FACTOR:g} kT/A = {display.text(limit, 'force', '.4g')}, where "
                    "the high-force "
                    "expansions g(F) and c_s(F) err by more than 2 % (z/L) and 5 % (c_s)"]
        return []

