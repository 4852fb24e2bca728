"""Fit parameters: one :class:`FitParameter` per fitted or fixed quantity, an ordered set of them.

In the style of lmfit's ``Parameter``/``Parameters`` and pylake's fit
parameters (docs/theory/fitting.md#the-global-fit). Every number is stored in SI
(turns for the turns offset); ``unit`` is only the display unit.

A parameter is one of

* a :class:`~supercoil.DNA` field (``length``, ``bending_persistence``,
  ``twist_persistence``, ``radius``; ``owner="dna"``), shared by all points;
* a parameter the DNA model or the interaction declares
  (:class:`~supercoil.dna.model_parameters.ModelParameter`; ``owner="model"`` or
  ``"interaction"``), shared by all points;
* a nuisance offset of one molecule (``turns_offset[<molecule>]``,
  ``extension_offset[<molecule>]``; ``owner="offset"``, ``shared="per-molecule"``);
* a calibration nuisance parameter (:data:`CALIBRATION`: ``torque_scale``,
  ``force_scale``, ``force_spread``; ``owner="calibration"``), shared by all points,
  held at its off value (:data:`CALIBRATION_OFF`: 1, 1, 0) unless varied
  (docs/theory/fitting.md#calibration-nuisance-parameters).

Plausible limits
----------------
Each parameter carries ``plausible = (low, high)`` and ``plausible_source``:
a fit ending at or beyond them warns (:class:`~supercoil.exceptions.FitWarning`).
They are *not* bounds (the optimiser does not see them). For the DNA fields
they are the choices in :data:`PLAUSIBLE`; for model and interaction
parameters the ``lower``/``upper`` of their declaration.
"""

from __future__ import annotations

import dataclasses
import functools
import math
from collections.abc import Iterator, MutableMapping

import numpy as np
import pandas as pd

from supercoil import display
from supercoil.dna.fitting.spread import FORCE_SPREAD_MAX, FORCE_SPREAD_START
from supercoil.units import ureg

__all__ = ["CALIBRATION", "CALIBRATION_OFF", "DNA_FIELDS", "PLAUSIBLE", "SHARING", "FitParameter",
           "FitParameters", "calibration_parameter", "display_factor"]

#: DNA fields that can be fitted (shared by all forces and molecules).
DNA_FIELDS = ("length", "bending_persistence", "twist_persistence", "radius")
#: the sharing modes of a parameter
SHARING = ("global", "per-force", "per-molecule")
_INF = math.inf

#: Plausible ranges of the DNA fields (SI) with the reason. They are deliberately
#: wide choices around the package's seed set (parameters/dna.toml: A = 48 nm and
#: C_t = 86 nm from Strick, Bensimon & Croquette, Genetica 106, 57 (1999); r0 = 1.75 nm
#: from Vologodskii et al., J. Mol. Biol. 227, 1224 (1992)), not literature limits:
#: an estimate outside them means the fit is describing something other than the
#: elasticity of B-DNA (a flat or distorted curve, wrong units, a broken molecule).
PLAUSIBLE = {
    "length": (0.0, _INF, "no limit: the contour length is the molecule's own"),
    "bending_persistence": (24e-9, 96e-9, "choice: a factor 2 either side of the seed set's "
                            "48 nm (Strick, Bensimon & Croquette, Genetica 106, 57 (1999))"),
    "twist_persistence": (43e-9, 172e-9, "choice: a factor 2 either side of the seed set's "
                          "86 nm (Strick, Bensimon & Croquette, Genetica 106, 57 (1999))"),
    "radius": (0.4375e-9, 7e-9, "choice: a factor 4 either side of the seed set's 1.75 nm "
               "(Vologodskii et al., J. Mol. Biol. 227, 1224 (1992))"),
    "turns_offset": (-_INF, _INF, "no limit"),
    "extension_offset": (-_INF, _INF, "no limit"),
}

#: Calibration nuisance parameters (dimensionless, off at :data:`CALIBRATION_OFF`): name ->
#: (the channels it acts on, plausible low, plausible high, definition);
#: docs/theory/fitting.md#calibration-nuisance-parameters. The measured channel and its
#: sigmas are never rescaled: the model's prediction of the measurement is.
CALIBRATION = {
    "torque_scale": ("torque", 0.5, 2.0,
                     "model torque = torque_scale x measured torque: the fit predicts the "
                     "measured torque as tau_model / torque_scale"),
    "force_scale": ("extension and torque", 0.5, 2.0,
                    "true force = force_scale x nominal force: the model is evaluated at "
                    "force_scale x the data's force"),
    "force_spread": ("extension and torque", -_INF, FORCE_SPREAD_MAX,
                     "relative standard deviation of the true force between the molecules "
                     "whose curves were averaged: the model is the Gauss-Hermite average over "
                     "true force = force_scale x nominal force x (1 + force_spread x xi), xi "
                     "standard normal (supercoil.dna.fitting.spread)"),
}
#: the value at which each calibration parameter changes nothing (the default)
CALIBRATION_OFF = {"torque_scale": 1.0, "force_scale": 1.0, "force_spread": 0.0}
_CALIBRATION_SOURCE = {
    "torque_scale": "choice: a calibration off by more than a factor 2 is not a calibration "
                    "error",
    "force_scale": "choice: a calibration off by more than a factor 2 is not a calibration "
                   "error",
    "force_spread": "the upper bound: the lowest Gauss-Hermite node force at 10 % of the "
                    "nominal force",
}


def calibration_parameter(name, value=None, vary=True) -> FitParameter:
    """The :class:`FitParameter` of the calibration parameter ``name`` (see :data:`CALIBRATION`).

    The scales are bounded below by 0 (exclusive) and plausible within a factor 2
    of 1. ``force_spread`` is bounded to ``[0, FORCE_SPREAD_MAX]``; varied from
    its off value 0 it starts at ``FORCE_SPREAD_START`` (the model is even in the
    spread, so its derivative vanishes at 0). ``value`` defaults to the off value.
    """
    lo, hi = CALIBRATION[name][1:3]
    value = CALIBRATION_OFF[name] if value is None else float(value)
    upper = _INF
    if name == "force_spread":
        upper = FORCE_SPREAD_MAX
        if vary and value == 0.0:
            value = FORCE_SPREAD_START
    return FitParameter(name, value, "", vary=vary, min=0.0, max=upper, kind=name,
                        owner="calibration", plausible=(lo, hi),
                        plausible_source=_CALIBRATION_SOURCE[name], scale=1.0)


@functools.lru_cache(maxsize=256)
def display_factor(unit: str) -> float:
    """Factor from the SI value to ``unit`` (an angle's SI unit is the radian).

    Memoised per unit string: pint parses each display unit once per process,
    not once per parameter and fit.
    """
    if unit == "":
        return 1.0
    q = ureg.Quantity(1.0, unit)
    return 1.0 / q.to_base_units().magnitude


@functools.lru_cache(maxsize=256)
def parse_unit(unit: str):
    """The pint unit of a unit string (``""``: dimensionless), parsed once per process."""
    return ureg.Unit(unit or "dimensionless")


@dataclasses.dataclass
class FitParameter:
    """One parameter of a hat-curve fit (values in SI; ``unit`` is for display).

    Attributes
    ----------
    name : str
        Full name: ``"radius"``, ``"turns_offset[m1]"``, a model parameter.
    value : float
        Start value before the fit, best-fit value after it (SI; turns).
    unit : str
        Display unit (``"nm"``, ``"turn"``, a model parameter's unit).
    vary : bool
        Fitted (True) or held at ``value``.
    min, max : float
        Bounds seen by the optimiser (SI; ``-inf``/``inf`` for none). The start
        value must lie strictly inside.
    stderr : float or None
        One-sigma standard error after a fit (``inf``: not determined).
    shared : {"global", "per-force", "per-molecule"}
        Which points share it: all, the points of one force, one molecule's.
    molecule : int or None
        Index of the molecule of a per-molecule parameter.
    force : float or None
        The force (N) of a per-force parameter (its points share it).
    kind : str
        Base name (``"turns_offset"`` for ``"turns_offset[m1]"``).
    owner : {"dna", "model", "interaction", "offset", "calibration"}
        Where the value goes: a DNA field, the model, the interaction, an offset,
        a calibration scale of a channel (:data:`CALIBRATION`).
    plausible : (float, float)
        Plausible range (SI); a fit ending at or beyond it warns.
    plausible_source : str
        The reason or source of :attr:`plausible`.
    given : bool
        The start value was given (False: read from the data: the offsets, and
        a varied ``length`` not in ``start``; :mod:`supercoil.dna.fitting.start`).
    scale : float
        The optimiser works on ``value / scale`` (of order one).
    """

    name: str
    value: float
    unit: str
    vary: bool = True
    min: float = -_INF
    max: float = _INF
    stderr: float | None = None
    shared: str = "global"
    molecule: int | None = None
    force: float | None = None
    kind: str = ""
    owner: str = "dna"
    plausible: tuple = (-_INF, _INF)
    plausible_source: str = ""
    given: bool = True
    scale: float = 1.0

    def __post_init__(self):
        if self.shared not in SHARING:
            raise ValueError(f"parameter {self.name!r}: shared must be one of {SHARING}, "
                             f"got {self.shared!r}")
        if not self.kind:
            self.kind = self.name.split("[", 1)[0]

    @property
    def bounds(self):
        """``(min, max)`` in SI."""
        return (self.min, self.max)

    @property
    def factor(self) -> float:
        """SI -> display unit (the turns offset is stored in turns, not radians)."""
        if self.owner == "offset" and self.unit == "turn":
            return 1.0
        return display_factor(self.unit)

    def quantity(self, si_value=None):
        """``si_value`` (default :attr:`value`) as a quantity in the display unit."""
        v = self.value if si_value is None else si_value
        return ureg.Quantity(v * self.factor, parse_unit(self.unit))

    def implausible(self, value=None):
        """A message if ``value`` (default :attr:`value`) is at or beyond the plausible range."""
        v = self.value if value is None else value
        lo, hi = self.plausible
        f = self.factor
        for bound, side, bad in ((lo, "lower", v <= lo), (hi, "upper", v >= hi)):
            if math.isfinite(bound) and bad:
                return (f"{self.name} = {v * f:.6g} {self.unit} is at or beyond its plausible "
                        f"{side} limit {bound * f:.6g} {self.unit} ({self.plausible_source}); "
                        "the data may not be a hat curve of intact DNA, or the model does "
                        "not describe them")
        return None


class FitParameters(MutableMapping):
    """Ordered mapping name -> :class:`FitParameter`, with the free-parameter vector.

    ``vector()`` gives the scaled free values (``value / scale``) in order,
    ``set_vector(u)`` writes them back; ``free`` lists the varied names.
    ``to_frame()`` (also the ``repr``) is the parameter table.
    """

    def __init__(self, items=()):
        self._p: dict[str, FitParameter] = {}
        for p in items:
            self.add(p)

    # ---- mapping ----
    def __getitem__(self, key) -> FitParameter:
        try:
            return self._p[key]
        except KeyError:
            raise KeyError(f"no fit parameter {key!r}; have {list(self._p)}") from None

    def __setitem__(self, key, value):
        if not isinstance(value, FitParameter) or value.name != key:
            raise TypeError(f"FitParameters[{key!r}] must be a FitParameter named {key!r}")
        self._p[key] = value

    def __delitem__(self, key):
        del self._p[key]

    def __iter__(self) -> Iterator[str]:
        return iter(self._p)

    def __len__(self):
        return len(self._p)

    def add(self, param: FitParameter):
        """Append ``param`` (its name must be new)."""
        if param.name in self._p:
            raise ValueError(f"fit parameter {param.name!r} already exists")
        self._p[param.name] = param
        return param

    def split_per_force(self, name, forces):
        """Replace the global parameter ``name`` by one per force, named ``name[0.3 pN]``.

        ``forces`` (Quantity [force], e.g. the data's distinct forces): each new
        parameter starts from the global one's value, bounds and limits and
        is shared by the points at its force only. Returns the new names.
        """
        from supercoil.units import U, magnitude

        p = self[name]
        if p.owner == "offset" or p.shared != "global":
            raise ValueError(f"only a global parameter can be split per force, not {name!r}")
        f_si = np.atleast_1d(np.asarray(magnitude(forces, U.N, "forces"), dtype=float))
        new = [dataclasses.replace(p, name=f"{p.kind}[{display.text(f, 'force')}]",
                                   shared="per-force", force=float(f))
               for f in np.unique(f_si)]
        items = []
        for key, q in self._p.items():
            items.extend(new if key == name else [q])
        self._p = {q.name: q for q in items}
        return [q.name for q in new]

    def copy(self) -> FitParameters:
        """A deep copy (the fit never changes the caller's parameters)."""
        return FitParameters(dataclasses.replace(p) for p in self._p.values())

    # ---- vector view ----
    @property
    def free(self) -> list[str]:
        """Names of the varied parameters, in order."""
        return [k for k, p in self._p.items() if p.vary]

    def free_params(self) -> list[FitParameter]:
        return [p for p in self._p.values() if p.vary]

    @property
    def scales(self) -> np.ndarray:
        return np.array([p.scale for p in self.free_params()], dtype=float)

    def vector(self) -> np.ndarray:
        """Scaled free values ``value / scale``."""
        return np.array([p.value / p.scale for p in self.free_params()], dtype=float)

    def bounds_vector(self):
        """Scaled ``(lower, upper)`` arrays of the free parameters."""
        free = self.free_params()
        lo = np.array([p.min / p.scale for p in free], dtype=float)
        hi = np.array([p.max / p.scale for p in free], dtype=float)
        return lo, hi

    def set_vector(self, u, stderr=None):
        """Write scaled free values ``u`` (and standard errors in SI) back."""
        for j, p in enumerate(self.free_params()):
            p.value = float(u[j] * p.scale)
            if stderr is not None:
                p.stderr = float(stderr[j])

    # ---- table ----
    def to_frame(self) -> pd.DataFrame:
        """One row per parameter: value, stderr, unit, vary, bounds, plausible range."""
        rows = []
        for p in self._p.values():
            f = p.factor
            rows.append({"name": p.name, "value": p.value * f,
                         "stderr": np.nan if p.stderr is None else p.stderr * f,
                         "unit": p.unit, "vary": p.vary, "min": p.min * f, "max": p.max * f,
                         "shared": p.shared, "plausible_low": p.plausible[0] * f,
                         "plausible_high": p.plausible[1] * f})
        return pd.DataFrame(rows).set_index("name") if rows else pd.DataFrame()

    def __repr__(self):
        if not self._p:
            return "FitParameters()"
        return "FitParameters\n" + self.to_frame().to_string()
