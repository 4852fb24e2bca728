"""The DNA model interface: one contract for every construction of the hat curve.

The contract is the docstring of :class:`DNAModel` (docs/theory/models.md explains it);
this module also holds the per-force :class:`Buckling` constants and
:func:`unique_forces`. Every public DNA function (:func:`~supercoil.hat_curve`,
:func:`~supercoil.buckling_turns`, :func:`~supercoil.post_buckling_slope`,
:func:`~supercoil.free_energy`, :func:`~supercoil.simulate_rotation_curves`, the fits and
``supercoil hat --model``) takes ``model=`` and calls only the public methods of
:class:`DNAModel`, so a new model is one subclass plus its tests.
"""

from __future__ import annotations

import abc
from typing import ClassVar, NamedTuple

import numpy as np

from supercoil._checks import check_flag
from supercoil.core.dna.interface import HatPoints
from supercoil.dna import validity as _v
from supercoil.dna.material import DNASI
from supercoil.dna.model_parameters import ModelParameter, Parametrised
from supercoil.exceptions import ModelError

__all__ = ["Buckling", "DNAModel", "HatPoints", "unique_forces"]


class Buckling(NamedTuple):
    """Per-force buckling constants of a model (SI arrays of the force's shape)."""

    turns: np.ndarray  # N_b, turns
    torque: np.ndarray  # torque at buckling (plectoneme torque), N m
    slope: np.ndarray  # dz/dN just past +N_b, m per turn (negative)


#: the public template methods and the step each one calls (a subclass implements the step)
TEMPLATE_METHODS = {"buckling": "_buckling", "points": "_points",
                    "free_energy": "_free_energy", "validity": "_validity",
                    "slope_validity": "_slope_validity",
                    "turns_at_tail_length": "_turns_at_tail_length",
                    "plectoneme_tension": "_plectoneme_tension"}


class DNAModel(Parametrised, abc.ABC):
    """Base class of the DNA models: the plug-in contract.

    A model turns a molecule, a force and the applied turns into extension, torque and
    phase (docs/theory/models.md). As scipy's ``OdeSolver``, the public methods are
    template methods: each checks its inputs once (1-D float arrays of one shape, finite
    and positive forces, ``dna`` a :class:`~supercoil.dna.material.DNASI`, ``thermal`` a
    bool, an interaction where the model takes one), handles empty inputs, applies the
    shared rules and the net under every model (a named error instead of a NaN), and
    calls a private step that each model implements. A subclass overrides the steps,
    never the public methods (overriding one is a TypeError at class definition).

    Declarations (class attributes; instances are immutable, picklable, hold ``values``
    in SI and are built with keywords, :class:`~supercoil.dna.model_parameters.Parametrised`)

    * ``name`` (registry key), ``summary`` (one line), ``parameters`` (its own
      :class:`~supercoil.dna.model_parameters.ModelParameter` declarations) and ``OPTIONS``
      (boolean options and their defaults, e.g. ``{"end_loop": False}``; read them with
      :meth:`options` and :meth:`option_defaults`).
    * Capabilities, declared here once (a model sets the class attribute, or a property
      where an option decides): :attr:`uses_interaction`, :attr:`symmetric_in_turns`,
      :attr:`describes_denaturation`, and :meth:`has_free_energy`. Callers read these;
      they never test a model's class, name or attributes.

    Steps (float level, SI: m, N, J, N m; ``dna`` a DNASI; ``turns`` and ``force`` 1-D of
    one shape, not empty, ``force`` read-only: for one force a broadcast view)

    * ``_buckling(force, dna, thermal, interaction)`` (abstract) -> :class:`Buckling` per
      distinct force (``turns`` may be +inf: the model never buckles).
    * ``_points(turns, force, dna, thermal, interaction, short_tail_length)`` (abstract)
      -> :class:`~supercoil.core.dna.interface.HatPoints` of the turns' shape (phase codes
      of :mod:`supercoil.core.dna.interface`; ``free_energy`` filled where the model has
      one; ``short_tail_length`` None: the model's default).
    * ``_free_energy(turns, force, dna, thermal, interaction)`` -> G(N, F) in J, with
      ``z = -dG/dF`` and ``M = (1/2 pi) dG/dN``; the default raises
      :class:`~supercoil.exceptions.ModelError` (a model without one may override it to
      say why). It must agree with :meth:`has_free_energy`.
    * ``_validity(turns, force, points, dna, thermal)`` -> the model's own messages
      (default none); the shared limits (:func:`supercoil.dna.validity.point_messages`)
      come first, from :meth:`validity`.
    * ``_slope_validity(force, torque, dna, thermal)`` -> messages where the model's
      post-buckling slope is not valid (default none).
    * ``_turns_at_tail_length(force, tail_length, dna, thermal, interaction)`` -> turns
      where the tail reaches a length (default: from the buckling constants, the
      plectoneme phase taken as linear; +inf where the model never buckles).
    * ``_plectoneme_tension(force, dna, thermal, interaction)`` -> the tension (N) on the
      model's plectoneme (default the force itself).

    Errors are named: :class:`~supercoil.exceptions.NoEquilibriumError` (no plectoneme
    at a force), :class:`~supercoil.exceptions.ValidityError` (a formula undefined), each
    naming the force. ``tests/dna/test_model_contract.py`` runs every registered model,
    and a plug-in, through the same checks.
    """

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    parameters: ClassVar[dict[str, ModelParameter]] = {}
    #: capability: a plectoneme helix state, so the model takes an
    #: :class:`~supercoil.dna.interactions.base.Interaction` (its ``equilibrium``)
    uses_interaction: ClassVar[bool] = True
    #: capability: extension, plectoneme length and phase even in N, torque odd (a model
    #: with a melted phase for negative turns is not); checked by the contract test
    symmetric_in_turns: ClassVar[bool] = True
    #: capability: the model describes the denaturation of negatively twisted DNA, so the
    #: shared "the model ignores denaturation" warning (above 0.8 pN) is not issued
    describes_denaturation: ClassVar[bool] = False

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        for public, step in TEMPLATE_METHODS.items():
            if public in cls.__dict__:
                raise TypeError(f"{cls.__name__} overrides DNAModel.{public}, a template "
                                f"method of the model contract; implement {step} instead "
                                "(supercoil.dna.models.base.DNAModel)")

    def has_free_energy(self, thermal: bool) -> bool:
        """Capability: whether :meth:`free_energy` is defined for this construction."""
        return False

    # ---- the public template methods ---------------------------------------------------
    def buckling(self, force, dna, thermal, interaction=None) -> Buckling:
        """Buckling turns, torque there and slope ``dz/dN`` past ``+N_b`` at each force.

        ``force`` (N) is a 1-D array of distinct forces; an empty one gives empty arrays.
        """
        force, dna, thermal, interaction = self._inputs(force, dna, thermal, interaction)
        if force.size == 0:
            return Buckling(np.empty(0), np.empty(0), np.empty(0))
        b = self._buckling(force, dna, thermal, interaction)
        if not isinstance(b, Buckling):
            raise TypeError(f"model {self.name!r}: _buckling must return a Buckling, got "
                            f"{type(b).__name__}")
        _v.check_finite_output(self, force, {"buckling turns": b.turns}, allow_inf=True)
        return b

    def points(self, turns, force, dna, thermal, interaction=None,
               short_tail_length=None) -> HatPoints:
        """Hat-curve points (:class:`~supercoil.core.dna.interface.HatPoints`, SI).

        ``turns`` and ``force`` (N) are 1-D arrays of one shape (the force of each point).

        Raises
        ------
        ValidityError
            Naming the model, force and turns where its extension or torque is not finite.
        """
        turns, force, dna, thermal, interaction = self._point_inputs(turns, force, dna,
                                                                     thermal, interaction)
        if turns.size == 0:  # the models reduce over their inputs: no call
            e = np.empty(0)
            return HatPoints(e, e.copy(), e.copy(), np.empty(0, np.int8), np.empty(0, bool),
                             e.copy(), np.empty(0) if self.has_free_energy(thermal) else None)
        hp = self._points(turns, force, dna, thermal, interaction, short_tail_length)
        if not isinstance(hp, HatPoints):
            raise TypeError(f"model {self.name!r}: _points must return HatPoints, got "
                            f"{type(hp).__name__}")
        if np.shape(hp.extension) != turns.shape or np.shape(hp.torque) != turns.shape:
            raise ValueError(f"model {self.name!r}: _points returned extension of shape "
                             f"{np.shape(hp.extension)} for turns of shape {turns.shape}")
        if _v.summary_of(hp) is None:  # the kernel's summary says finite: no second pass
            _v.check_finite_output(self, force, {"extension": hp.extension,
                                                 "torque": hp.torque}, turns)
        return hp

    def free_energy(self, turns, force, dna, thermal, interaction=None):
        """Total free energy ``G(N, F)`` at fixed force (J), one per point.

        Raises
        ------
        ModelError
            If the model is not derived from one free energy (:meth:`has_free_energy`).
        """
        turns, force, dna, thermal, interaction = self._point_inputs(turns, force, dna,
                                                                     thermal, interaction)
        if turns.size == 0 and self.has_free_energy(thermal):
            return np.empty(0)
        g = self._free_energy(turns, force, dna, thermal, interaction)
        _v.check_finite_output(self, force, {"free energy": g}, turns)
        return g

    def turn_slopes(self, turns, force, dna, thermal, interaction, points):
        """``(dz/dN, dM/dN)`` (SI, per turn) at ``points``, the model's own points at
        ``(turns, force)``, in closed form; None where the model has none (the default:
        callers then differentiate :meth:`points`). A fit's Jacobian column in the turns
        offset uses them instead of a kernel call at ``N -/+ h``; ``dM/dN`` may be NaN at
        points where only ``dz/dN`` is known."""
        turns, force, dna, thermal, interaction = self._point_inputs(turns, force, dna,
                                                                     thermal, interaction)
        return self._turn_slopes(turns, force, dna, thermal, interaction, points)

    def _turn_slopes(self, turns, force, dna, thermal, interaction, points):
        return None

    def validity(self, turns, force, points, dna, thermal) -> list[str]:
        """Messages the public layer issues as ValidityWarning: the shared limits, then
        the model's own (docs/theory/limits.md#dna)."""
        turns, force = _same_shape(turns, force)
        return (_v.point_messages(turns, force, points, dna, self.describes_denaturation)
                + list(self._validity(turns, force, points, dna, check_flag(thermal,
                                                                            "thermal"))))

    def slope_validity(self, force, buckling, dna, thermal) -> list[str]:
        """Messages where the post-buckling slope is not valid: the shared force limit,
        then the model's own (from the buckling torque)."""
        force = np.asarray(force, dtype=float)
        return _v.force_messages(force) + list(self._slope_validity(
            force, np.asarray(buckling.torque, float), dna, check_flag(thermal, "thermal")))

    def turns_at_tail_length(self, force, tail_length, dna, thermal, interaction=None):
        """Turns (per force, > N_b) where the tail shortens to ``tail_length`` (m).

        +inf where the model never buckles; NaN where it gives no such turns (the caller
        names the force).
        """
        force, dna, thermal, interaction = self._inputs(force, dna, thermal, interaction)
        tail = float(tail_length)
        if not (np.isfinite(tail) and 0 <= tail <= dna.length):
            raise ValueError(f"tail_length must lie in [0, L = {dna.length:.6g} m], got "
                             f"{tail_length!r}")
        if force.size == 0:
            return np.empty(0)
        return self._turns_at_tail_length(force, tail, dna, thermal, interaction)

    def plectoneme_tension(self, force, dna, thermal, interaction=None):
        """The tension (N) on the model's plectoneme at each force (the force by default)."""
        force, dna, thermal, interaction = self._inputs(force, dna, thermal, interaction)
        return self._plectoneme_tension(force, dna, thermal, interaction)

    # ---- the steps ---------------------------------------------------------------------
    @abc.abstractmethod
    def _buckling(self, force, dna, thermal, interaction) -> Buckling:
        """Buckling constants per distinct force (see the class docstring)."""

    @abc.abstractmethod
    def _points(self, turns, force, dna, thermal, interaction, short_tail_length) -> HatPoints:
        """Hat-curve points (see the class docstring)."""

    def _free_energy(self, turns, force, dna, thermal, interaction):
        """G(N, F) in J; the default: the model has none (ModelError)."""
        raise ModelError(f"model {self.name!r} (thermal={thermal}) is not derived from one "
                         "free energy, so it has none; use model='free-energy'")

    def _validity(self, turns, force, points, dna, thermal) -> list[str]:
        """The model's own validity messages (default: none)."""
        return []

    def _slope_validity(self, force, torque, dna, thermal) -> list[str]:
        """Messages where the model's post-buckling slope is not valid (default: none)."""
        return []

    def _turns_at_tail_length(self, force, tail_length, dna, thermal, interaction):
        """``N_b + z_b (1 - l / L) / |dz/dN|``: the plectoneme phase taken as linear."""
        b = self.buckling(force, dna, thermal, interaction)
        out = np.full(force.shape, np.inf)
        finite = np.isfinite(b.turns)
        if not finite.any():
            return out
        zb = np.asarray(self.points(b.turns[finite], force[finite], dna, thermal,
                                    interaction).extension, dtype=float)
        slope = b.slope[finite]
        with np.errstate(divide="ignore", invalid="ignore"):
            n = b.turns[finite] + zb * (1 - tail_length / dna.length) / np.abs(slope)
        out[finite] = np.where(np.isfinite(slope) & (slope < 0), n, np.nan)
        return out

    def _plectoneme_tension(self, force, dna, thermal, interaction):
        """The model holds its plectoneme at the full force (default)."""
        return force

    # ---- input checks (one place for every model) ---------------------------------------
    def _inputs(self, force, dna, thermal, interaction):
        force = np.asarray(force, dtype=float)
        if force.ndim != 1:
            raise ValueError(f"model {self.name!r}: force must be a 1-D array (N), got shape "
                             f"{force.shape}")
        _v.check_positive_forces(force)
        if not isinstance(dna, DNASI):
            raise TypeError(f"model {self.name!r}: dna must be the SI view DNA.si (a DNASI), "
                            f"got {type(dna).__name__}")
        if self.uses_interaction and interaction is None:
            raise ModelError(f"model {self.name!r} has a plectoneme helix state and needs an "
                             "interaction (e.g. get_interaction('hard-core'))")
        return force, dna, check_flag(thermal, "thermal"), interaction

    def _point_inputs(self, turns, force, dna, thermal, interaction):
        turns, force = _same_shape(turns, force)
        if turns.size and not _all_finite(turns):
            raise ValueError(f"model {self.name!r}: turns must be finite, got "
                             f"{turns[~np.isfinite(turns)][0]!r}")
        force, dna, thermal, interaction = self._inputs(force, dna, thermal, interaction)
        return turns, force, dna, thermal, interaction


def _all_finite(x):
    """Whether every element of the float array ``x`` is finite: one pass (its sum).

    A NaN or an infinity makes the sum NaN or infinite; a sum that overflows from
    finite values (|x| near 1e308) is told apart by the exact elementwise test.
    """
    with np.errstate(over="ignore", invalid="ignore"):
        total = np.add.reduce(x)
    return bool(np.isfinite(total)) or bool(np.isfinite(x).all())


def _same_shape(turns, force):
    """``turns`` and ``force`` as 1-D float arrays of one shape (ValueError naming both)."""
    turns = np.asarray(turns, dtype=float)
    force = np.asarray(force, dtype=float)
    if turns.ndim != 1 or turns.shape != force.shape:
        raise ValueError(f"turns and force must be 1-D arrays of one shape (the force of "
                         f"each point), got shapes {turns.shape} and {force.shape}")
    return turns, force


def unique_forces(force):
    """``(distinct forces, index of each point's force)`` for per-force constants."""
    force = np.asarray(force, dtype=float)
    if force.size and force.min() == force.max():
        return force[:1].copy(), np.zeros(force.shape, dtype=np.intp)
    uf, inv = np.unique(force, return_inverse=True)
    return uf, inv.reshape(force.shape)
