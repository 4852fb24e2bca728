"""DNA models on one interface (docs/theory/models.md).

``get_model("li-zhao")`` (the paper's construction, the default). Every module of this
package except ``base`` holds one model and is registered by being here: the registry
imports each module and registers the :class:`DNAModel` subclasses defined there
(:class:`supercoil.dna.registry.Registry`); their classes are attributes of this package
(``from supercoil.dna.models import Marko2007``). User code registers its own models with
:func:`register_model`. The contract is the docstring of :class:`DNAModel`.
"""

from supercoil.dna.models.base import Buckling, DNAModel, HatPoints, unique_forces
from supercoil.dna.registry import Registry

#: the model used when none is given (the paper's)
DEFAULT_MODEL = "li-zhao"
_REGISTRY = Registry("model", DNAModel, __name__)
globals().update(_REGISTRY.package_classes())

__all__ = ["DEFAULT_MODEL", "Buckling", "DNAModel", "HatPoints", "available_models",
           "get_model", "register_model", "unique_forces", "unregister_model",
           *sorted(_REGISTRY.package_classes())]


def register_model(cls, replace=False):
    """Make a :class:`DNAModel` subclass available by its ``name`` (returns the class)."""
    return _REGISTRY.register(cls, replace=replace)


def unregister_model(name):
    """Remove a registered model by name (returns its class); the package's own stay
    registered unless removed explicitly (tests re-register them)."""
    return _REGISTRY.unregister(name)


def get_model(spec=DEFAULT_MODEL, **values):
    """A model instance from a registered name, a class or an instance."""
    return _REGISTRY.get(spec, "model", **values)


def available_models():
    """Registered model names."""
    return _REGISTRY.names()
