"""The package's single unit registry and the unit boundary.

Every public function of supercoil takes and returns :class:`pint.Quantity`
objects of the one registry :data:`ureg`. Inside, all numerics run on plain
float arrays in **SI base units** (m, N, J, N m, N m^2, rad, K). The helpers in
this module strip units once at the boundary (:func:`magnitude`) and attach
them once on the way out (:func:`quantity`).

Cost on hot paths
-----------------
Parsing a unit string in pint costs one to ten times ``Quantity.m_as(unit)``, and
``m_as`` itself is slow next to a float multiply. Therefore

* all unit objects are built once, at import, in :class:`U`;
* :func:`magnitude` compares the argument's unit container with the target
  (about 40 times cheaper than ``m_as``), and otherwise multiplies by a conversion
  factor that is computed once per (source unit, target unit) pair and cached. Offset units (degC)
  fall back to pint's own conversion.
"""

from __future__ import annotations

import numpy as np
import pint

__all__ = [
    "BOLTZMANN",
    "U",
    "as_turns",
    "magnitude",
    "quantity",
    "ureg",
]

#: The package's single unit registry. Build all quantities with it:
#: ``length = 750 * supercoil.ureg.nm``.
try:  # pint's cached definitions: about a sixth of the import time of parsing them
    ureg = pint.UnitRegistry(cache_folder=":auto:")
except OSError:  # no writable user cache folder: parse the definitions
    ureg = pint.UnitRegistry()
ureg.formatter.default_format = "~P"
# pint's documented way for a package: quantities unpickled in any process (a
# worker of a ProcessPoolExecutor, a joblib/dask task) are rebuilt in this
# registry, so they pass :func:`magnitude` (they were rejected as foreign quantities).
pint.set_application_registry(ureg)
Q_ = ureg.Quantity

#: Boltzmann constant in J/K (exact, SI 2019).
BOLTZMANN = 1.380649e-23

DimensionalityError = pint.DimensionalityError


class U:
    """Unit objects built once at import. Internal system: SI base units."""

    # internal (SI) units
    m = ureg.meter
    N = ureg.newton
    J = ureg.joule
    N_m = ureg.newton * ureg.meter  # torque / twist moment
    N_m2 = ureg.newton * ureg.meter**2  # bending and torsional rigidity
    N_per_m = ureg.newton / ureg.meter  # force per length
    per_m = 1 / ureg.meter  # curvature, torsion, twist density
    Pa = ureg.pascal
    K = ureg.kelvin
    rad = ureg.radian
    s = ureg.second
    dimensionless = ureg.dimensionless
    turn = ureg.turn
    # display units of the scenes (tables and returned quantities)
    nm = ureg.nanometer
    um = ureg.micrometer
    mm = ureg.millimeter
    cm = ureg.centimeter
    pN = ureg.piconewton
    pN_nm = ureg.piconewton * ureg.nanometer
    pN_per_nm = ureg.piconewton / ureg.nanometer
    nm_per_turn = ureg.nanometer / ureg.turn
    per_nm = 1 / ureg.nanometer
    per_mm = 1 / ureg.millimeter
    N_mm = ureg.newton * ureg.millimeter
    N_per_mm = ureg.newton / ureg.millimeter
    deg = ureg.degree
    MPa = ureg.megapascal
    mol_per_m3 = ureg.mol / ureg.meter**3  # concentration (SI; 1 mol/m^3 = 1 mM)
    mM = ureg.millimolar


# (source UnitsContainer, target UnitsContainer) -> multiplicative factor
_FACTORS: dict[tuple, float] = {}


def _dimension_error(value_units, unit, name, detail=""):
    src = ureg.Unit(value_units) if value_units is not None else U.dimensionless
    return DimensionalityError(
        src,
        unit,
        src.dimensionality,
        unit.dimensionality,
        extra_msg=f" for argument '{name}' (expected a quantity in {unit:~P}){detail}",
    )


def magnitude(value, unit: pint.Unit, name: str) -> np.ndarray | float:
    """Strip the unit of ``value`` after converting it to ``unit``.

    Parameters
    ----------
    value : pint.Quantity
        A quantity of :data:`ureg`. A plain number is accepted only where
        ``unit`` is dimensionless.
    unit : pint.Unit
        Target unit, one of the prebuilt :class:`U` members.
    name : str
        The argument's name, used in error messages.

    Returns
    -------
    float or numpy.ndarray
        The magnitude in ``unit`` as float (array for array input).

    Raises
    ------
    pint.DimensionalityError
        If ``value`` has the wrong dimension; the message names ``name``.
    TypeError
        If ``value`` belongs to another unit registry.
    """
    value = _from_sequence(value, unit, name)
    units = getattr(value, "_units", None)
    if units is not None and not hasattr(value, "_magnitude"):
        raise TypeError(f"argument '{name}' is a unit, not a quantity: multiply it by a number")
    if units is None:
        if isinstance(value, str | bytes):
            raise TypeError(f"argument '{name}' is text ({value!r}); give a number or a "
                            "quantity, e.g. supercoil.ureg.Quantity('1.2 pN')")
        if value is None:
            raise TypeError(f"argument '{name}' is None; expected a number or a quantity")
        if unit.dimensionless:
            return _as_float(value, name)
        raise _dimension_error(
            None,
            unit,
            name,
            "; a plain number has no unit: build it with supercoil.ureg, "
            f"e.g. 2.0 * supercoil.ureg.{unit:~}",
        )
    if getattr(value, "_REGISTRY", ureg) is not ureg:
        raise TypeError(
            f"argument '{name}' was built with another pint UnitRegistry; "
            "use supercoil.ureg (the package's single registry)"
        )
    mag = value._magnitude
    target = unit._units
    if units == target:
        return _as_float(mag, name)
    key = (units, target)
    factor = _FACTORS.get(key)
    if factor is None:
        if not value._is_multiplicative:
            try:
                return _as_float(value.m_as(unit), name)
            except DimensionalityError:
                raise _dimension_error(units, unit, name) from None
        try:
            factor = float(Q_(1.0, units).m_as(unit))
        except DimensionalityError:
            raise _dimension_error(units, unit, name) from None
        _FACTORS[key] = factor
    return _as_float(mag, name) * factor


def _from_sequence(value, unit, name):
    """A list or tuple holding quantities as one array quantity (else ``value`` unchanged).

    ``[1 * turn, 2 * turn]`` must mean exactly what ``[1, 2] * turn`` means.
    pint's own ``from_list`` keeps the unit of the first element; building
    the magnitudes here also refuses a list that mixes quantities with plain
    numbers (pint would read ``[1 * pN, 2]`` as 1 pN and 2 pN) or nested
    sequences of a ragged shape.
    """
    if not isinstance(value, list | tuple) or not value:
        return value
    flat = _flatten(value)
    has_units = [hasattr(v, "_units") for v in flat]
    if not any(has_units):
        return value
    if not all(has_units):
        raise TypeError(f"argument '{name}' mixes quantities and plain numbers; give "
                        "every element a unit (or none)")
    first = flat[0]
    for v in flat:
        if getattr(v, "_REGISTRY", ureg) is not ureg:
            raise TypeError(
                f"argument '{name}' was built with another pint UnitRegistry; "
                "use supercoil.ureg (the package's single registry)")
    try:
        mags = _nested(value, lambda v: v.m_as(first.units))
    except DimensionalityError:
        raise _dimension_error(None, unit, name,
                               "; the list mixes incompatible units") from None
    try:
        arr = np.asarray(mags, dtype=complex if any(np.iscomplexobj(m) for m in
                                                    _flatten(mags)) else float)
    except (TypeError, ValueError):
        raise ValueError(f"argument '{name}' is a ragged nested list of quantities") from None
    return Q_(arr, first.units)


def _flatten(value):
    out = []
    for v in value:
        if isinstance(v, list | tuple):
            out.extend(_flatten(v))
        else:
            out.append(v)
    return out


def _nested(value, fn):
    return [_nested(v, fn) if isinstance(v, list | tuple) else fn(v) for v in value]


def _as_float(mag, name="value"):
    """``mag`` as a float or float array; TypeError naming ``name`` for complex or text."""
    if isinstance(mag, float):
        return mag
    if isinstance(mag, complex) or np.iscomplexobj(mag):
        raise TypeError(f"argument '{name}' is complex ({mag!r}); supercoil takes real numbers")
    if isinstance(mag, str | bytes) or mag is None:
        raise TypeError(f"argument '{name}' must be a number or an array of numbers, "
                        f"got {type(mag).__name__}")
    try:
        arr = np.asarray(mag, dtype=float)
    except (TypeError, ValueError):
        raise TypeError(f"argument '{name}' must be a number or an array of numbers, "
                        f"got {type(mag).__name__} {_short(mag)}") from None
    return float(arr) if arr.ndim == 0 else arr


def _short(value, width=60):
    text = repr(value)
    return text if len(text) <= width else text[: width - 3] + "..."


def as_turns(value, name: str = "turns") -> np.ndarray | float:
    """Number of turns from a plain number, a dimensionless quantity or an angle.

    A plain number or a dimensionless quantity counts turns (``40`` is 40
    turns). A quantity in an angle unit is converted: ``40 * ureg.turn`` and
    ``80 * pi * ureg.rad`` are both 40 turns. (pint treats angles as
    dimensionless, so a plain ``.m_as("dimensionless")`` would turn 40 turns
    into 251; this function avoids that trap.)
    """
    value = _from_sequence(value, U.turn, name)
    units = getattr(value, "_units", None)
    if units is None:
        return magnitude(value, U.dimensionless, name)
    if getattr(value, "_REGISTRY", ureg) is not ureg:
        raise TypeError(
            f"argument '{name}' was built with another pint UnitRegistry; "
            "use supercoil.ureg (the package's single registry)"
        )
    if units == U.dimensionless._units:
        return _as_float(value._magnitude, name)
    if _is_angle(units):  # turn, rad, degree, ...: convert to turns
        return magnitude(value, U.turn, name)
    # other dimensionless units (percent, m/mm, ...) are plain ratios of a count
    return magnitude(value, U.dimensionless, name)


_ANGLE_CACHE: dict = {}


def _is_angle(units) -> bool:
    """True if the unit container contains an angle (its root units hold radian)."""
    hit = _ANGLE_CACHE.get(units)
    if hit is None:
        root = ureg.get_root_units(ureg.Unit(units))[1]
        hit = _ANGLE_CACHE[units] = "radian" in root._units
    return hit


def quantity(mag, unit: pint.Unit) -> pint.Quantity:
    """Attach ``unit`` (a prebuilt :class:`U` member) to a float or array."""
    return Q_(mag, unit)
