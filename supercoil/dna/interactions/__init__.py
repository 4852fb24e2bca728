"""Inter-strand interactions of the DNA plectoneme (docs/theory/plectoneme.md).

``get_interaction("hard-core")`` (the paper's Marko-Siggia ``w``, the default),
``get_interaction("screened")`` (Debye-Hueckel electrostatics with salt,
docs/theory/screened-interaction.md). Every module of this package except ``base`` holds
one interaction and is registered by being here (as the models,
:mod:`supercoil.dna.models`); user code registers its own with
:func:`register_interaction`. The contract is the docstring of :class:`Interaction`.
"""

from supercoil.dna.interactions.base import Interaction
from supercoil.dna.registry import Registry

#: the interaction used when none is given (the paper's)
DEFAULT_INTERACTION = "hard-core"
_REGISTRY = Registry("interaction", Interaction, __name__)
globals().update(_REGISTRY.package_classes())

__all__ = ["DEFAULT_INTERACTION", "Interaction", "available_interactions",
           "get_interaction", "register_interaction", "unregister_interaction",
           *sorted(_REGISTRY.package_classes())]


def register_interaction(cls, replace=False):
    """Make an :class:`Interaction` subclass available by its ``name``."""
    return _REGISTRY.register(cls, replace=replace)


def unregister_interaction(name):
    """Remove a registered interaction by name (returns its class)."""
    return _REGISTRY.unregister(name)


def get_interaction(spec=DEFAULT_INTERACTION, **values):
    """An interaction instance from a name or an instance."""
    return _REGISTRY.get(spec, "interaction", **values)


def available_interactions():
    """Registered interaction names."""
    return _REGISTRY.names()
