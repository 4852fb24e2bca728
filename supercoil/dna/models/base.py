"""Stand-in for the lead's model interface: only :class:`ModelParameter` (replaced at merge)."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class ModelParameter:
    """A model's or an interaction's own parameter (SI default and bounds)."""

    name: str
    unit: str
    default: float
    lower: float
    upper: float
    description: str
    source: str
