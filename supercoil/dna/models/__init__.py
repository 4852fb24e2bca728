"""DNA models on one interface (docs/theory/models.md).

``get_model("li-zhao")`` (the paper's construction, the default); further
models register themselves with :func:`register_model`. The contract is in
:mod:`supercoil.dna.models.base`.
"""

from supercoil.dna.models.base import Buckling, DNAModel, HatPoints, unique_forces
from supercoil.dna.models.ensemble import Ensemble
from supercoil.dna.models.free_energy import FreeEnergy
from supercoil.dna.models.li_zhao import LiZhao
from supercoil.dna.models.marko2007 import Marko2007
from supercoil.dna.registry import Registry

__all__ = ["DEFAULT_MODEL", "Buckling", "DNAModel", "Ensemble", "FreeEnergy", "HatPoints",
           "LiZhao", "Marko2007", "available_models", "get_model", "register_model",
           "unique_forces", "unregister_model"]

#: the model used when none is given (the paper's)
DEFAULT_MODEL = "li-zhao"
_REGISTRY = Registry("model", DNAModel)


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


register_model(LiZhao)
register_model(FreeEnergy)
register_model(Marko2007)
register_model(Ensemble)
