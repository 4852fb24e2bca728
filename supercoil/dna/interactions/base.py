"""The interaction interface: the energy w(alpha, R) between the two plectoneme strands.

The contract is the docstring of :class:`Interaction` (docs/theory/models.md#the-interface):
the energy per unit strand length of a uniform double helix of tilt ``alpha`` and radius
``R``, and the uniform plectoneme at a given tension (docs/theory/plectoneme.md): (GE1),
(GE2) and ``T = -(1/2) B kappa^2 + C omega tau - w``. The DNA models that have a
plectoneme helix state (:mod:`supercoil.dna.models`) call :meth:`Interaction.equilibrium`;
nothing else about the interaction is assumed. Every module of
:mod:`supercoil.dna.interactions` holds one interaction (``"hard-core"``, the paper's
Marko-Siggia ``w``, the default; ``"screened"``, Debye-Hueckel electrostatics with salt).
"""

from __future__ import annotations

import abc
from typing import ClassVar

import numpy as np

from supercoil.dna.model_parameters import ModelParameter, Parametrised

__all__ = ["Interaction"]

#: the public template methods and the step each one calls (a subclass implements the step)
TEMPLATE_METHODS = {"partials": "_partials", "equilibrium": "_equilibrium", "check": "_check",
                    "energy": "_partials"}


class Interaction(Parametrised, abc.ABC):
    """Base class of the inter-strand interactions: the plug-in contract.

    As :class:`~supercoil.dna.models.base.DNAModel`, the public methods are template
    methods that check their inputs once and call a private step each interaction
    implements; overriding a public method is a TypeError at class definition.

    Declarations (class attributes): ``name`` (registry key), ``summary`` (one line),
    ``parameters`` (its own :class:`~supercoil.dna.model_parameters.ModelParameter`
    declarations); instances are immutable, picklable and hold ``values`` (SI).

    Steps (float level, SI; ``dna`` a :class:`~supercoil.dna.material.DNASI`)

    * ``_partials(alpha, radius, dna)`` (abstract) -> ``(w, dw/dalpha, dw/dR)`` in
      (J/m, J/m, J/m^2), arrays of the broadcast shape of ``alpha`` and ``radius``.
    * ``_equilibrium(tension, dna)`` (abstract) -> the uniform plectoneme
      (:class:`~supercoil.core.dna.plectoneme.PlectonemeState`, arrays of the tension's
      shape) at each tension (1-D, finite, positive, N); raises
      :class:`~supercoil.exceptions.NoEquilibriumError` naming the tension where none
      exists.
    * ``_check(dna)`` -> raise :class:`~supercoil.exceptions.ParameterError` if ``dna``
      lacks something the interaction needs (default: nothing needed).
    * :meth:`cache_key` (override only if the equilibrium reads more than the DNA fields
      and the interaction's own parameters).
    """

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    parameters: ClassVar[dict[str, ModelParameter]] = {}

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        for public, step in TEMPLATE_METHODS.items():
            if public in cls.__dict__:
                raise TypeError(f"{cls.__name__} overrides Interaction.{public}, a template "
                                f"method of the interaction contract; implement {step} "
                                "instead (supercoil.dna.interactions.base.Interaction)")

    def energy(self, alpha, radius, dna):
        """Interaction energy ``w`` per unit strand length (J/m) at tilt and radius (SI)."""
        return self.partials(alpha, radius, dna)[0]

    def partials(self, alpha, radius, dna):
        """``(w, dw/dalpha, dw/dR)`` in SI (J/m, J/m, J/m^2)."""
        return self._partials(np.asarray(alpha, float), np.asarray(radius, float), dna)

    def equilibrium(self, tension, dna):
        """Uniform plectoneme at ``tension`` (N, 1-D array) for the molecule ``dna`` (DNASI).

        Returns
        -------
        supercoil.core.dna.plectoneme.PlectonemeState
            SI arrays of the tension's shape.

        Raises
        ------
        ValueError
            The tension not 1-D or not finite.
        NoEquilibriumError
            Naming the tension where no plectoneme state exists (a tension <= 0 too).
        """
        from supercoil.dna.validity import check_positive_forces

        t = np.asarray(tension, dtype=float)
        if t.ndim != 1:
            raise ValueError(f"interaction {self.name!r}: tension must be a 1-D array (N), "
                             f"got shape {t.shape}")
        check_positive_forces(t)
        return self._equilibrium(t, dna)

    def check(self, dna):
        """Raise ParameterError if ``dna`` lacks something this interaction needs."""
        self._check(dna)
        self._check(dna)

    def unrecorded(self):
        """This interaction without the public layer's recording of the states it solves.

        The public layer hands the models a recorder of the plectoneme states, which the
        shared checks read; a model that solves trial states it does not keep asks them
        from ``interaction.unrecorded()`` (the interaction itself; the recorder returns
        the interaction it wraps).
        """
        return self

    def kernel_memo(self, dna):
        """A dict where a model may keep C-free results for ``dna`` across calls, or None.

        None here (each call solves afresh); a fit's memoised interaction returns one
        dict per :meth:`cache_key` (the models keep the pull and the fully coiled branch
        there: :mod:`supercoil.core.dna.branch_memo`).
        """
        return None

    @abc.abstractmethod
    def _partials(self, alpha, radius, dna):
        """``(w, dw/dalpha, dw/dR)`` (see the class docstring)."""

    @abc.abstractmethod
    def _equilibrium(self, tension, dna):
        """The uniform plectoneme at each tension (see the class docstring)."""

    def _check(self, dna):
        """Nothing needed beyond the DNA fields (default)."""

    #: DNASI fields the plectoneme equilibrium never reads: the molecule's length, and its
    #: twist rigidity C, because (GE2) contains no C, so the tilt, the radius and the
    #: torque M = C omega at a tension are independent of it (only ``omega = M / C`` and
    #: the twist energy ``M omega / 2`` scale with 1/C; docs/theory/plectoneme.md)
    C_FREE_FIELDS = ("length", "twist_persistence", "torsional_rigidity")

    def cache_key(self, dna):
        """Hashable key of everything :meth:`equilibrium` depends on, C excluded.

        Two molecules with the same key have the same plectoneme tilt, radius and torque
        at every tension; a cache rescales ``omega`` and ``twist_energy`` to the new C.
        An interaction that reads more than the DNA fields and its own parameters
        overrides this.
        """
        fields = tuple(v for k, v in dna._asdict().items() if k not in self.C_FREE_FIELDS)
        return (type(self).__qualname__, tuple(sorted(self.values.items())), fields)
