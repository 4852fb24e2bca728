"""Display units: the one table mapping each quantity kind to the unit it is shown in.

Kernels compute in SI floats; results, tables, reports and figures show values
in the units of :data:`DISPLAY` (per domain: rods in mm and N, DNA in nm and
pN). Every factor between the two is computed by pint (:data:`supercoil.ureg`)
from this table, once per unit (:func:`factor`); no module writes ``1e9`` for
"metres to nanometres".

Angles are stored in radians and turn counts in turns (factor 1); every other
kind in SI base units.
"""

from __future__ import annotations

import functools

import numpy as np

from supercoil.units import Q_, ureg

__all__ = ["DISPLAY", "factor", "from_display", "quantity", "spec", "text", "to_display",
           "unit"]

#: display unit of every quantity kind, per domain (pint unit strings; "" dimensionless)
DISPLAY = {
    "rod": {
        "turns": "turn", "slack": "mm", "alpha": "rad", "pitch": "mm", "omega": "1/mm",
        "curvature": "1/mm", "torsion": "1/mm", "tension": "N", "torque": "N*mm",
        "normal_force": "N/m", "twist": "turn", "writhe": "turn", "linking_number": "turn",
        "superhelical_turns": "turn", "head_tension": "N", "beta": "rad",
        "alpha_slacking": "rad", "pitch_slacking": "mm", "pitch_increase": "",
        "alpha0": "rad", "s_max": "mm", "slip_onset": "mm", "curvature_error_onset": "mm",
        "s_end": "mm",
    },
    "dna": {
        "force": "pN", "alpha": "rad", "radius": "nm", "pitch": "nm", "omega": "1/nm",
        "torque": "pN*nm", "curvature": "1/nm", "torsion": "1/nm", "bending_energy": "pN",
        "twist_energy": "pN", "interaction_energy": "pN",
        # hat curves and fits
        "turns": "turn", "extension": "nm", "length": "nm", "plectoneme_length": "nm",
        "phase": "", "supercoiling_density": "", "eta": "", "short_tail": "",
        "free_energy": "pN*nm", "sum_squares": "nm**2", "torque_sum_squares": "pN**2*nm**2",
        "temperature": "K", "salt": "mM",
    },
}

_COUNTS = ("rad", "turn")  # stored as they are shown (radians, counts of turns)


@functools.lru_cache(maxsize=256)
def spec(unit_text: str):
    """``(pint Unit, factor SI -> display)`` of a display unit string (parsed once)."""
    if not unit_text:
        return ureg.dimensionless, 1.0
    u = ureg.Unit(unit_text)
    if unit_text in _COUNTS:
        return u, 1.0
    base = Q_(1.0, u).to_base_units().units
    return u, float(Q_(1.0, base).m_as(u))


def unit(kind: str, domain: str = "dna") -> str:
    """The display unit string of ``kind`` in ``domain``."""
    return DISPLAY[domain][kind]


def factor(kind: str, domain: str = "dna") -> float:
    """The factor from the SI value of ``kind`` to its display unit."""
    return spec(DISPLAY[domain][kind])[1]


def to_display(si_value, kind: str, domain: str = "dna"):
    """An SI float or array of ``kind`` in its display unit (float or float array)."""
    f = factor(kind, domain)
    x = np.asarray(si_value, dtype=float)
    return float(x * f) if x.ndim == 0 else x * f


def from_display(value, kind: str, domain: str = "dna"):
    """A float or array in the display unit of ``kind`` back to SI."""
    f = factor(kind, domain)
    x = np.asarray(value, dtype=float)
    return float(x / f) if x.ndim == 0 else x / f


def quantity(si_value, kind: str, domain: str = "dna"):
    """An SI float or array of ``kind`` as a quantity in its display unit."""
    u, f = spec(DISPLAY[domain][kind])
    return Q_(np.asarray(si_value, dtype=float) * f if f != 1.0 else si_value, u)


def text(si_value, kind: str, fmt: str = ".6g", domain: str = "dna") -> str:
    """``"<value> <unit>"`` of an SI float in the display unit of ``kind``, for messages
    (``text(1.2e-12, "force")`` is ``"1.2 pN"``; products spelled with a space)."""
    u = DISPLAY[domain][kind].replace("**", "^").replace("*", " ")
    return f"{to_display(si_value, kind, domain):{fmt}} {u}".rstrip()
