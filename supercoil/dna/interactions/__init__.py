"""Inter-strand interactions of a plectoneme (stand-in registry until the lead's lands)."""

from .base import Interaction
from .screened import Screened

_REGISTRY = {Screened.name: Screened}


def get_interaction(name_or_instance, **values):
    """An interaction by registry name, or the instance itself."""
    if isinstance(name_or_instance, Interaction):
        return name_or_instance.replace(**values) if values else name_or_instance
    try:
        return _REGISTRY[name_or_instance](**values)
    except KeyError:
        raise ValueError(f"unknown interaction {name_or_instance!r}; available: "
                         f"{sorted(_REGISTRY)}") from None


__all__ = ["Interaction", "Screened", "get_interaction"]
