"""Inter-strand interactions of the DNA plectoneme (docs/theory/plectoneme.md).

``get_interaction("hard-core")`` (the paper's Marko-Siggia ``w``, the default),
``get_interaction("screened")`` (Debye-Hueckel electrostatics with salt,
docs/theory/screened-interaction.md);
further interactions register themselves with :func:`register_interaction`.
"""

from supercoil.dna.interactions.base import Interaction
from supercoil.dna.interactions.hard_core import HardCore
from supercoil.dna.interactions.screened import Screened
from supercoil.dna.registry import Registry

__all__ = ["DEFAULT_INTERACTION", "HardCore", "Interaction", "Screened",
           "available_interactions", "get_interaction", "register_interaction",
           "unregister_interaction"]

#: the interaction used when none is given (the paper's)
DEFAULT_INTERACTION = "hard-core"
_REGISTRY = Registry("interaction", Interaction)


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


register_interaction(HardCore)
register_interaction(Screened)
