"""Stand-in for the lead's interaction interface (replaced by the lead's file at merge)."""

from __future__ import annotations

from typing import ClassVar

from ...units import ureg
from ..models.base import ModelParameter

__all__ = ["Interaction", "ModelParameter"]


class Interaction:
    """Inter-strand interaction of a plectoneme: immutable, picklable, SI values."""

    name: ClassVar[str]
    parameters: ClassVar[dict[str, ModelParameter]] = {}

    def __init__(self, **values):
        unknown = set(values) - set(self.parameters)
        if unknown:
            raise TypeError(f"{self.name}: unknown parameter(s) {sorted(unknown)}; "
                            f"takes {sorted(self.parameters)}")
        si = {k: p.default for k, p in self.parameters.items()}
        for key, v in values.items():
            if hasattr(v, "units"):
                unit = ureg.Quantity(1.0, self.parameters[key].unit).to_base_units().units
                v = float(v.m_as(unit))
            si[key] = float(v)
        object.__setattr__(self, "values", si)

    def __setattr__(self, key, value):
        raise AttributeError(f"{type(self).__name__} is immutable; use replace()")

    def __reduce__(self):
        return (_rebuild, (type(self), dict(self.values)))

    def __eq__(self, other):
        return type(other) is type(self) and other.values == self.values

    def __hash__(self):
        return hash((type(self), tuple(sorted(self.values.items()))))

    def __repr__(self):
        args = ", ".join(f"{k}={v:.6g}" for k, v in self.values.items())
        return f"{type(self).__name__}({args})"

    def replace(self, **values):
        """A copy with some parameters changed."""
        return type(self)(**{**self.values, **values})

    def energy(self, alpha, radius, dna):  # pragma: no cover - interface
        raise NotImplementedError

    def partials(self, alpha, radius, dna):  # pragma: no cover - interface
        raise NotImplementedError

    def equilibrium(self, tension, dna):  # pragma: no cover - interface
        raise NotImplementedError


def _rebuild(cls, values):
    return cls(**values)
