"""The DNA model interface: one contract for every construction of the hat curve.

A DNA model turns a molecule (:class:`~supercoil.DNA`), a force and the
applied turns into extension, torque and phase (docs/theory/models.md). Every
public DNA function (:func:`~supercoil.hat_curve`,
:func:`~supercoil.buckling_turns`, :func:`~supercoil.post_buckling_slope`,
:func:`~supercoil.free_energy`, :func:`~supercoil.simulate_rotation_curves`,
the fits and ``supercoil hat --model``) takes ``model=`` (a registered name
or an instance) and calls only the methods below, so a new model is one
subclass plus its tests.

Contract (float level, SI; modelled on scipy's ``OdeSolver`` rules)
------------------------------------------------------------------
1. ``name`` (registry key), ``summary`` (one line) and ``parameters`` (its own
   :class:`~supercoil.dna.model_parameters.ModelParameter` declarations) are class
   attributes; instances are immutable, picklable and hold ``values`` (SI).
2. Capabilities, declared once as class attributes (an instance may override them
   through a property when an option decides): ``uses_interaction`` (a plectoneme
   helix state, so it takes an :class:`~supercoil.dna.interactions.base.Interaction`),
   ``symmetric_in_turns`` (even extension, odd torque), ``describes_denaturation``
   (a melted phase: the shared denaturation warning is not issued) and
   :meth:`has_free_energy`.
3. ``buckling(force, dna, thermal, interaction)`` -> :class:`Buckling` per
   force (1-D array of distinct forces, N).
4. ``points(turns, force, dna, thermal, interaction, short_tail_length)`` ->
   :class:`~supercoil.core.dna.interface.HatPoints`; ``turns`` and ``force`` are 1-D
   arrays of the same shape (force repeated per point; read-only: for one
   force it is a broadcast view).
5. ``has_free_energy(thermal)`` and ``free_energy(turns, force, ...)`` (J): the
   total free energy G(N, F) at fixed force, whose derivatives give
   ``z = -dG/dF`` and ``M = (1/2 pi) dG/dN``; the default raises
   :class:`~supercoil.exceptions.ModelError`.
6. ``validity(turns, force, points, dna, thermal)`` -> list of messages the
   public layer issues as :class:`~supercoil.exceptions.ValidityWarning`
   (model-specific checks only; the shared ones live in
   :mod:`supercoil.dna.validity`).
7. Errors are named: :class:`~supercoil.exceptions.NoEquilibriumError` (no
   plectoneme at a force), :class:`~supercoil.exceptions.ValidityError`
   (formula undefined), each naming the force.
``dna`` is a :class:`~supercoil.dna.material.DNASI` (SI floats).
"""

from __future__ import annotations

from typing import ClassVar, NamedTuple

import numpy as np

from supercoil.core.dna.interface import HatPoints
from supercoil.dna.model_parameters import ModelParameter, Parametrised
from supercoil.exceptions import ModelError

__all__ = ["Buckling", "DNAModel", "HatPoints", "unique_forces"]


class Buckling(NamedTuple):
    """Per-force buckling constants of a model (SI arrays of the force's shape)."""

    turns: np.ndarray  # N_b, turns
    torque: np.ndarray  # torque at buckling (plectoneme torque), N m
    slope: np.ndarray  # dz/dN just past +N_b, m per turn (negative)


class DNAModel(Parametrised):
    """Base class of the DNA models (see the module docstring for the contract)."""

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    parameters: ClassVar[dict[str, ModelParameter]] = {}
    uses_interaction: ClassVar[bool] = True
    #: capability: extension, plectoneme length and phase even in N, torque odd (a model
    #: with a melted phase for negative turns is not); checked by the contract test
    symmetric_in_turns: ClassVar[bool] = True
    #: capability: the model describes the denaturation of negatively twisted DNA, so the
    #: shared "the model ignores denaturation" warning (above 0.8 pN) is not issued
    describes_denaturation: ClassVar[bool] = False

    def has_free_energy(self, thermal: bool) -> bool:
        """Whether :meth:`free_energy` is defined for this construction."""
        return False

    def buckling(self, force, dna, thermal, interaction) -> Buckling:
        raise NotImplementedError

    def points(self, turns, force, dna, thermal, interaction, short_tail_length) -> HatPoints:
        raise NotImplementedError

    def free_energy(self, turns, force, dna, thermal, interaction):
        raise ModelError(f"model {self.name!r} (thermal={thermal}) is not derived from one "
                         "free energy, so it has none; use model='free-energy'")

    def validity(self, turns, force, points, dna, thermal) -> list[str]:
        return []


def unique_forces(force):
    """``(distinct forces, index of each point's force)`` for per-force constants."""
    force = np.asarray(force, dtype=float)
    if force.size and force.min() == force.max():
        return force[:1].copy(), np.zeros(force.shape, dtype=np.intp)
    uf, inv = np.unique(force, return_inverse=True)
    return uf, inv.reshape(force.shape)
