"""The paper's interaction: Marko-Siggia hard core plus entropic confinement.

``w = [1 + x^-12] kT/r0 (R/r0)^-12 + B^(-1/3) [1 + x^(-2/3)] (kT)^(4/3) / R^(2/3)``
with ``x = pi cot(alpha)`` (docs/theory/plectoneme.md#interaction). The hard-core
radius is the DNA's ``radius`` (r0); there is no salt. Kernels:
:mod:`supercoil.core.dna.marko_siggia` (w and partials) and
:mod:`supercoil.core.dna.plectoneme` (the equilibrium solver).
"""

from __future__ import annotations

from typing import ClassVar

from supercoil.core.dna import marko_siggia as _ms
from supercoil.core.dna import plectoneme as _pl
from supercoil.dna.interactions.base import Interaction

__all__ = ["HardCore"]


class HardCore(Interaction):
    """Marko-Siggia interaction of the paper (Example III): no parameters of its own."""

    name = "hard-core"
    summary = "Marko-Siggia (R/r0)^-12 hard core + entropic confinement (the paper's w)"
    parameters: ClassVar[dict] = {}

    def _partials(self, alpha, radius, dna):
        B, kT, r0 = dna.bending_rigidity, dna.kT, dna.radius
        w = _ms.interaction(alpha, radius, B, kT, r0)
        return (w, *_ms.interaction_partials(alpha, radius, B, kT, r0))

    def _equilibrium(self, tension, dna):
        return _pl.equilibrium(tension, dna.bending_rigidity, dna.torsional_rigidity, dna.kT,
                               dna.radius)
