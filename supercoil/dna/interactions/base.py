"""The interaction interface: the energy w(alpha, R) between the two plectoneme strands.

An :class:`Interaction` gives the interaction energy per unit strand length of
a uniform double helix of tilt ``alpha`` and radius ``R`` and solves the
uniform plectoneme at a given tension (docs/theory/plectoneme.md): (GE1),
(GE2) and ``T = -(1/2) B kappa^2 + C omega tau - w``. The DNA models
(:mod:`supercoil.dna.models`) that have a plectoneme helix state call
:meth:`Interaction.equilibrium`; nothing else about the interaction is
assumed. Implementations: ``"hard-core"`` (the paper's Marko-Siggia ``w``,
:mod:`supercoil.dna.interactions.hard_core`, the default) and ``"screened"``
(Debye-Hueckel electrostatics with salt).

Adding an interaction: subclass :class:`Interaction`, declare ``name`` and
``parameters`` (:class:`~supercoil.dna.model_parameters.ModelParameter`), implement
:meth:`partials` and :meth:`equilibrium` on SI floats, and register it with
:func:`supercoil.dna.interactions.register_interaction`.
"""

from __future__ import annotations

from typing import ClassVar

from supercoil.dna.model_parameters import ModelParameter, Parametrised

__all__ = ["Interaction"]


class Interaction(Parametrised):
    """Base class of the inter-strand interactions (immutable, picklable).

    Attributes
    ----------
    name : str
        Registry name.
    parameters : dict[str, ModelParameter]
        Its own parameters (SI defaults and bounds).
    values : dict[str, float]
        This instance's parameter values (SI).
    """

    name: ClassVar[str] = ""
    summary: ClassVar[str] = ""
    parameters: ClassVar[dict[str, ModelParameter]] = {}

    def energy(self, alpha, radius, dna):
        """Interaction energy ``w`` per unit strand length (J/m) at tilt and radius (SI)."""
        return self.partials(alpha, radius, dna)[0]

    def partials(self, alpha, radius, dna):
        """``(w, dw/dalpha, dw/dR)`` in SI (J/m, J/m, J/m^2)."""
        raise NotImplementedError

    def equilibrium(self, tension, dna):
        """Uniform plectoneme at ``tension`` (N, 1-D array) for the molecule ``dna`` (DNASI).

        Returns
        -------
        supercoil.core.dna.plectoneme.PlectonemeState
            SI arrays of the tension's shape.

        Raises
        ------
        NoEquilibriumError
            Naming the tension where no plectoneme state exists.
        """
        raise NotImplementedError

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

    def check(self, dna):
        """Raise ParameterError if ``dna`` lacks something this interaction needs."""
