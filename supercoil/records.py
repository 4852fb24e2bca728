"""One result pattern for every scene: lazy quantities over SI arrays, one display-unit table.

Every result record of the public API (:class:`~supercoil.rod.smooth.SmoothHelix`,
:class:`~supercoil.rod.spinning.TwistSpinningHelix`,
:class:`~supercoil.rod.rough.RoughHelix`,
:class:`~supercoil.dna.plectoneme.PlectonemeEquilibrium`) is a :class:`Record`: it holds
the kernel's SI arrays and builds the quantity of a field, in its display unit, only when
the field is read (a scene pays for no quantity it does not use; building one costs more
than the float arithmetic behind it). The display units of all fields live in one table,
:data:`supercoil.display.DISPLAY` (per domain: rods are shown in mm and N, DNA in nm and pN); the
SI-to-display factors are computed from it by pint once per record class. ``to_table()``
gives the same fields as a table in the package convention (docs/theory/conventions.md),
with the same units.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from supercoil.display import DISPLAY
from supercoil.display import spec as _spec
from supercoil.units import Q_

__all__ = ["DISPLAY", "Record", "si_value"]

def si_value(x):
    """A kernel result as a record stores it: a float for a 0-d value, else a float array."""
    x = np.asarray(x, float)
    return float(x) if x.ndim == 0 else x


def _rebuild(cls, si, extra):
    return cls(**si, **extra)


class Record:
    """Immutable result record: SI values in, quantities in display units out, lazily.

    Subclasses declare ``DOMAIN`` (a key of :data:`DISPLAY`), ``FIELDS`` (the quantity
    fields, in order; ``turn`` fields hold counts of turns, ``rad`` fields radians, every
    other field SI) and ``EXTRA`` (plain attributes: strings, tables, dicts, floats). A
    field whose SI value is None reads as None. Records iterate like named tuples over
    ``FIELDS``.
    """

    __slots__ = ("_cache", "_extra", "_si")
    DOMAIN: ClassVar[str] = ""
    FIELDS: ClassVar[tuple] = ()
    EXTRA: ClassVar[tuple] = ()
    _SPEC: ClassVar[dict] = {}

    def __init_subclass__(cls, **kw):
        super().__init_subclass__(**kw)
        if cls.DOMAIN:
            table = DISPLAY[cls.DOMAIN]
            cls._SPEC = {f: _spec(table[f]) for f in cls.FIELDS}

    def __init__(self, **values):
        missing = (set(self.FIELDS) | set(self.EXTRA)) - set(values)
        unknown = set(values) - set(self.FIELDS) - set(self.EXTRA)
        if missing or unknown:
            raise TypeError(f"{type(self).__name__}: missing {sorted(missing)}, "
                            f"unknown {sorted(unknown)}")
        object.__setattr__(self, "_si", {k: values[k] for k in self.FIELDS})
        object.__setattr__(self, "_extra", {k: values[k] for k in self.EXTRA})
        object.__setattr__(self, "_cache", {})

    def __getattr__(self, name):
        spec = type(self)._SPEC.get(name)
        if spec is None:
            try:
                return self._extra[name]
            except KeyError:
                raise AttributeError(f"{type(self).__name__} has no field {name!r}") from None
        cache = self._cache
        if name not in cache:
            mag = self._si[name]
            unit, factor = spec
            cache[name] = None if mag is None else Q_(mag * factor if factor != 1.0 else mag,
                                                      unit)
        return cache[name]

    def __setattr__(self, name, value):
        raise AttributeError(f"{type(self).__name__} is immutable")

    def __reduce__(self):
        return (_rebuild, (type(self), dict(self._si), dict(self._extra)))

    @property
    def _fields(self):
        return self.FIELDS

    def _asdict(self):
        return {name: getattr(self, name) for name in self.FIELDS}

    def __iter__(self):
        return (getattr(self, name) for name in self.FIELDS)

    def __len__(self):
        return len(self.FIELDS)

    def si(self, name):
        """The SI value of field ``name`` as stored (no quantity built)."""
        return self._si[name]

    def to_table(self, fields=None):
        """The fields as a flat table in the package convention (the display units).

        Array fields are broadcast to one shape and flattened, one row per element.
        """
        from supercoil.tables import make_table

        fields = [f for f in (fields or self.FIELDS) if self._si[f] is not None]
        shape = np.broadcast_shapes(*(np.shape(self._si[f]) for f in fields))
        cols, units = {}, {}
        table = DISPLAY[self.DOMAIN]
        for f in fields:
            _, factor = self._SPEC[f]
            cols[f] = np.ravel(np.broadcast_to(np.asarray(self._si[f], float) * factor, shape))
            units[f] = table[f]
        return make_table(cols, units, self._extra.get("provenance"))

    def __repr__(self):
        def fmt(v):
            return "None" if v is None else f"{v:~P}"
        body = ", ".join(f"{k}={fmt(getattr(self, k))}" for k in self.FIELDS)
        return f"{type(self).__name__}({body})"
