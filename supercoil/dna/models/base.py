"""STAND-IN (branch ``freeenergy`` only) for the lead's DNA model interface.

Written to the interface announced for ``supercoil/dna/models/base.py`` so that
the free-energy model can be coded against it before the layout lands; on
merge the lead's version replaces this file.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar, NamedTuple

import numpy as np

try:  # the lead adds ModelError to supercoil.exceptions with the layout
    from ...exceptions import ModelError
except ImportError:  # pragma: no cover - stand-in only
    from ...exceptions import SupercoilError

    class ModelError(SupercoilError):
        """A model cannot do what was asked (stand-in)."""


@dataclass(frozen=True)
class ModelParameter:
    """A model's own parameter (beyond the DNA material); numbers in SI."""

    name: str
    unit: str
    default: float
    lower: float
    upper: float
    description: str
    source: str


class Buckling(NamedTuple):
    turns: np.ndarray  # turns
    torque: np.ndarray  # N m
    slope: np.ndarray  # m per turn, negative


class HatPoints(NamedTuple):
    extension: np.ndarray
    torque: np.ndarray
    plectoneme_length: np.ndarray
    phase: np.ndarray
    short_tail: np.ndarray
    zeta: np.ndarray
    free_energy: np.ndarray | None


class DNAModel:
    """Base of the DNA models (stand-in)."""

    name: ClassVar[str]
    summary: ClassVar[str]
    parameters: ClassVar[dict[str, ModelParameter]] = {}
    uses_interaction: ClassVar[bool] = True

    def __init__(self, **values):
        unknown = set(values) - set(self.parameters)
        if unknown:
            raise ModelError(f"model {self.name!r} has no parameter(s) {sorted(unknown)}")
        object.__setattr__(self, "values", {})

    def replace(self, **values):
        return type(self)(**{**self.values, **values})

    def has_free_energy(self, thermal: bool) -> bool:
        return False

    def buckling(self, force, dna, thermal, interaction):
        raise NotImplementedError

    def points(self, turns, force, dna, thermal, interaction, short_tail_length):
        raise NotImplementedError

    def free_energy(self, turns, force, dna, thermal, interaction):
        raise ModelError(f"model {self.name!r} has no free energy")

    def validity(self, turns, force, points, dna, thermal):
        return []
