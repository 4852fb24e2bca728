"""The interface of the DNA kernels: the points every model returns, phase codes, force limits.

Every DNA model's kernel (``li_zhao``'s :mod:`supercoil.core.dna.li_zhao`,
:mod:`supercoil.core.dna.free_energy`, :mod:`supercoil.core.dna.marko2007`, and any
plug-in) returns :class:`HatPoints` with the phase codes below; the public layer
(:mod:`supercoil.dna.validity`) applies the shared force limits. Defined once here, so that no
model's kernel holds another model's types (docs/theory/models.md#the-interface).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = [
    "DENATURATION_FORCE",
    "FULLY_COILED",
    "OVERSTRETCHING_FORCE",
    "PHASE_CODES",
    "PLECTONEME",
    "SHORT_TAIL_PERSISTENCE_LENGTHS",
    "STRETCHED",
    "HatPoints",
    "PointSummary",
]

#: phase codes of :attr:`HatPoints.phase` (int8)
STRETCHED, PLECTONEME, FULLY_COILED = 0, 1, 2
#: every phase code, in the order of the public ``phase`` labels
PHASE_CODES = (STRETCHED, PLECTONEME, FULLY_COILED)
#: above this force (N) negative supercoiling denatures real DNA [Salerno 2012]
DENATURATION_FORCE = 0.8e-12
#: above this force (N) B-DNA overstretches (Smith, Cui & Bustamante, Science 271,
#: 795 (1996); Cluzel et al., Science 271, 792 (1996)); the model is inextensible
OVERSTRETCHING_FORCE = 65e-12
#: default short-tail threshold of :attr:`HatPoints.short_tail`, in bending persistence
#: lengths A = B/kT (the Moroz-Nelson expansion needs a tail long compared with A)
SHORT_TAIL_PERSISTENCE_LENGTHS = 3.0


class HatPoints(NamedTuple):
    """Hat-curve points, same-shape SI arrays."""

    extension: np.ndarray  # m
    torque: np.ndarray  # N m, sign of N
    plectoneme_length: np.ndarray  # S, m (L when fully coiled)
    phase: np.ndarray  # int8: 0 stretched, 1 plectoneme, 2 fully coiled
    short_tail: np.ndarray  # bool: tail L - S shorter than short_tail_length
    zeta: np.ndarray  # Moroz-Nelson extension factor (1 athermal, 0 fully coiled)
    free_energy: np.ndarray | None = None  # G(N, F) in J, for models that have one
    bracket: np.ndarray | None = None  # li-zhao thermal: Moroz-Nelson bracket Q per point
    summary: PointSummary | None = None  # reductions the kernel computed block by block


class PointSummary(NamedTuple):
    """Reductions over all points of a kernel's call, taken block by block (optional).

    Computed while each block is in the CPU cache, so that the public layer's
    checks (docs/theory/limits.md) reuse them instead of passing over the
    arrays again (about a dozen passes). The ranges hold only if ``finite``.
    """

    finite: bool  # extension and torque finite everywhere
    extension_min: float  # m
    extension_max: float  # m
    torque_min: float  # N m, signed
    torque_max: float  # N m, signed
    bracket_min: float  # thermal: min of Q over all points (NaN athermal)
    zeta_over_long_tail: bool  # zeta > 1 at a point not flagged short_tail
    turns_min: float = float("nan")  # the turns of the call (NaN: not kept)
    turns_max: float = float("nan")
