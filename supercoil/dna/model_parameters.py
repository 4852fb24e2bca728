"""Declared parameters of DNA models and interactions (name, unit, default, bounds, source).

A :class:`ModelParameter` is the declaration a model or interaction makes of
one of its own parameters (beyond the :class:`~supercoil.DNA` material): the
display unit, the default and the plausible bounds (SI floats), a one-line
description and the source of the default. :class:`Parametrised` is the shared
base of :class:`~supercoil.dna.models.base.DNAModel` and
:class:`~supercoil.dna.interactions.base.Interaction`: immutable instances
holding ``values`` (SI floats by name), built from pint quantities or SI floats,
validated against the bounds, picklable and comparable by value.
"""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

from supercoil.units import magnitude, ureg

__all__ = ["ModelParameter", "Parametrised"]


@dataclasses.dataclass(frozen=True)
class ModelParameter:
    """One declared parameter of a model or interaction.

    Attributes
    ----------
    name : str
        Keyword of the parameter (unique across the DNA fields, the model and
        the interaction, so that fits can address it by name).
    unit : str
        Display unit (a pint unit string, "" for a dimensionless number).
    default, lower, upper : float
        Default and plausible bounds in SI (``lower <= default <= upper``);
        fits warn when a parameter ends at or beyond them.
    description : str
        One line.
    source : str
        Where the default comes from (a citation, or "choice").
    """

    name: str
    unit: str
    default: float
    lower: float
    upper: float
    description: str = ""
    source: str = ""

    @property
    def si_unit(self):
        """The SI base unit of :attr:`unit` (pint Unit)."""
        return ureg.Quantity(1.0, self.unit).to_base_units().units if self.unit else \
            ureg.dimensionless

    def to_si(self, value, owner: str) -> float:
        """SI float of ``value`` (a quantity, or a plain number already in SI)."""
        name = f"{owner}.{self.name}"
        if hasattr(value, "_units"):
            v = magnitude(value, self.si_unit, name)
        else:
            try:
                v = float(value)
            except (TypeError, ValueError):
                raise TypeError(f"{name} must be a number or a quantity in {self.unit or '1'}, "
                                f"got {type(value).__name__}") from None
        if not math.isfinite(v):
            raise ValueError(f"{name} must be finite, got {value!r}")
        if not (self.lower <= v <= self.upper):
            raise ValueError(f"{name} = {v:.6g} (SI) lies outside its allowed range "
                             f"[{self.lower:.6g}, {self.upper:.6g}]")
        return v

    def quantity(self, si_value: float):
        """``si_value`` as a quantity in the display unit."""
        q = ureg.Quantity(si_value, self.si_unit)
        return q.to(self.unit) if self.unit else q


class Parametrised:
    """Immutable holder of declared parameters: ``values`` (SI floats by name).

    Subclasses declare ``parameters: dict[str, ModelParameter]`` and ``name``.
    """

    name: ClassVar[str] = ""
    parameters: ClassVar[dict[str, ModelParameter]] = {}
    #: boolean options (not fitted parameters) and their defaults, e.g. {"end_loop": False}
    OPTIONS: ClassVar[dict[str, bool]] = {}

    def __init__(self, **values):
        from supercoil._checks import check_flag

        for key, default in self.OPTIONS.items():
            object.__setattr__(self, key, check_flag(values.pop(key, default), key))
        unknown = set(values) - set(self.parameters)
        if unknown:
            raise TypeError(f"{type(self).__name__} has no parameter(s) {sorted(unknown)}; "
                            f"its parameters are {sorted(self.parameters)}")
        si = {}
        for key, spec in self.parameters.items():
            si[key] = spec.to_si(values[key], self.name) if key in values else spec.default
        object.__setattr__(self, "values", si)

    def __setattr__(self, key, value):
        raise AttributeError(f"{type(self).__name__} is immutable; use replace()")

    def options(self) -> dict:
        """The boolean options of this instance (for provenance), e.g. ``{"end_loop": False}``."""
        return {k: getattr(self, k) for k in self.OPTIONS}

    @classmethod
    def option_defaults(cls) -> dict:
        """The boolean options of the class with their defaults (a copy of ``OPTIONS``)."""
        return dict(cls.OPTIONS)

    def replace(self, **values):
        """A copy with some parameters (quantities or SI floats) or options changed."""
        merged = {**dict(self.values), **self.options()}
        for key in self.OPTIONS:
            if key in values:
                merged[key] = values.pop(key)
        for key, v in values.items():
            if key not in self.parameters:
                raise TypeError(f"{type(self).__name__} has no parameter {key!r}; "
                                f"its parameters are {sorted(self.parameters)}")
            merged[key] = v
        return type(self)(**merged)

    def quantities(self) -> dict:
        """The parameter values as quantities in their display units."""
        return {k: self.parameters[k].quantity(v) for k, v in self.values.items()}

    def __reduce__(self):
        return (_rebuild, (type(self), {**self.values, **self.options()}))

    def __eq__(self, other):
        return (type(other) is type(self) and other.values == self.values
                and other.options() == self.options())

    def __hash__(self):
        return hash((type(self), tuple(sorted(self.values.items())),
                     tuple(sorted(self.options().items()))))

    def __repr__(self):
        body = ", ".join(f"{k}={q:.6g~P}" for k, q in self.quantities().items())
        return f"{type(self).__name__}({body})"


def _rebuild(cls, values):
    return cls(**values)
