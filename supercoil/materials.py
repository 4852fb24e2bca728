"""Shared base of the materials (:class:`supercoil.ElasticRod`, :class:`supercoil.DNA`).

Both are immutable, validated at construction (dimension, finite, positive)
and carry an ``si`` view: a named tuple of plain SI floats that the kernels in
:mod:`supercoil.core` use, so the unit boundary is crossed once per object and
not once per call. The rod lives in :mod:`supercoil.rod.material`, the
molecule in :mod:`supercoil.dna.material`; see docs/theory/conventions.md.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from supercoil.units import U, magnitude, quantity

__all__ = ["Material", "derived_positive", "format_optional", "format_quantity",
           "positive_scalar"]


def positive_scalar(value, unit, name, owner):
    mag = magnitude(value, unit, f"{owner}.{name}")
    if np.ndim(mag) != 0:
        raise ValueError(f"{owner}.{name} must be a scalar, got shape {np.shape(mag)}")
    mag = float(mag)
    if not np.isfinite(mag):
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}")
    if mag <= 0:
        raise ValueError(f"{owner}.{name} must be positive, got {value!r}")
    return mag


def derived_positive(value, what, owner, inputs):
    """A derived SI number (a rigidity, kT) as float, if it is a normal positive float.

    ValueError naming the inputs when the product leaves the float range:
    ``ElasticRod(radius=1e300 m)`` overflows ``r^4`` to inf, and
    ``DNA(temperature=1e-300 K)`` underflows ``kT`` to a subnormal number,
    whose reciprocal overflows later in the kernels.
    """
    with np.errstate(over="ignore", under="ignore"):
        v = float(value)
    if not (np.isfinite(v) and v >= np.finfo(float).tiny):
        raise ValueError(f"{owner}: the {what} is {v!r} (outside the normal float range "
                         f"{np.finfo(float).tiny:.3g} to {np.finfo(float).max:.3g} in SI "
                         f"units); check {inputs}")
    return v


def format_quantity(q):
    return f"{q.magnitude:.6g} {q.units:~P}"


def format_optional(q):
    if q is None:
        return "None"
    if hasattr(q, "units"):
        return format_quantity(q)
    return f"{q:g}"


def _as_dict(obj, kind):
    out = {"kind": kind}
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if v is None:
            continue
        out[f.name] = f"{v.magnitude:.12g} {v.units:~}" if hasattr(v, "units") else f"{v:.12g}"
    return out


class Material:
    """Shared behaviour of the materials: rigidities, copies, equality by value."""

    __slots__ = ()

    @property
    def bending_rigidity(self):
        """Bending rigidity B (N m^2): ``E pi r^4 / 4`` (rod), ``A kT`` (DNA)."""
        return quantity(self.si.bending_rigidity, U.N_m2)

    @property
    def torsional_rigidity(self):
        """Torsional rigidity C (N m^2): ``G pi r^4 / 2`` (rod), ``C_t kT`` (DNA)."""
        return quantity(self.si.torsional_rigidity, U.N_m2)

    def replace(self, **changes):
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def as_dict(self):
        """The parameters as ``{field: "value unit"}`` strings (for provenance)."""
        return _as_dict(self, type(self).__name__)

    def __hash__(self):
        return hash(self.si)

    def __eq__(self, other):
        return type(other) is type(self) and self.si == other.si
