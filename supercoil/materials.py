"""Materials: an elastic rod (rubber cord, yarn, cable) and a DNA molecule.

Both are immutable, validated at construction (dimension, finite, positive)
and carry an ``si`` view: a named tuple of plain SI floats that the kernels in
:mod:`supercoil.core` use, so the unit boundary is crossed once per object and
not once per call.

Rigidities (MODEL.md section 1):

* rod: ``B = E pi r^4 / 4``, ``C = G pi r^4 / 2``;
* DNA: ``B = A kT``, ``C = C_t kT`` with A the bending and C_t the twist
  persistence length and ``kT = k_B t``.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from .units import BOLTZMANN, U, magnitude, quantity

__all__ = ["DNA", "DNASI", "ElasticRod", "RodSI"]


class RodSI(NamedTuple):
    """SI float view of an :class:`ElasticRod` (m, Pa, N m^2)."""

    radius: float
    length: float
    young_modulus: float
    shear_modulus: float
    friction_coefficient: float | None
    bending_rigidity: float
    torsional_rigidity: float


class DNASI(NamedTuple):
    """SI float view of a :class:`DNA` molecule (m, K, J, N m^2)."""

    length: float
    bending_persistence: float
    twist_persistence: float
    radius: float
    temperature: float
    wlc_persistence: float
    kT: float
    bending_rigidity: float
    torsional_rigidity: float
    salt: float | None = None  # monovalent ionic strength, mol/m^3 (= mM); None if unset


def _scalar(value, unit, name, owner):
    mag = magnitude(value, unit, f"{owner}.{name}")
    if np.ndim(mag) != 0:
        raise ValueError(f"{owner}.{name} must be a scalar, got shape {np.shape(mag)}")
    mag = float(mag)
    if not np.isfinite(mag):
        raise ValueError(f"{owner}.{name} must be finite, got {value!r}")
    if mag <= 0:
        raise ValueError(f"{owner}.{name} must be positive, got {value!r}")
    return mag


def _fmt(q):
    return f"{q.magnitude:.6g} {q.units:~P}"


def _fmt_opt(q):
    if q is None:
        return "None"
    if hasattr(q, "units"):
        return _fmt(q)
    return f"{q:g}"


def _as_dict(obj, kind):
    out = {"kind": kind}
    for f in dataclasses.fields(obj):
        v = getattr(obj, f.name)
        if v is None:
            continue
        out[f.name] = f"{v.magnitude:.12g} {v.units:~}" if hasattr(v, "units") else f"{v:.12g}"
    return out


class _Material:
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


@dataclasses.dataclass(frozen=True, repr=False, eq=False)
class ElasticRod(_Material):
    """A straight, inextensible elastic rod of circular cross section.

    Parameters
    ----------
    radius : Quantity [length]
        Rod radius r (the strand radius; two strands in contact have R = r).
    length : Quantity [length]
        Rod length L.
    young_modulus : Quantity [pressure]
        Young's modulus E.
    shear_modulus : Quantity [pressure]
        Shear modulus G.
    friction_coefficient : float or dimensionless Quantity, optional
        Static friction coefficient mu between the strands (needed for the
        no-slip check of the rough helix). ``None`` if unknown.

    Attributes
    ----------
    bending_rigidity : Quantity [N m^2]
        ``B = E pi r^4 / 4``.
    torsional_rigidity : Quantity [N m^2]
        ``C = G pi r^4 / 2``.
    si : RodSI
        The same numbers as plain SI floats, for the float kernels.
    """

    radius: object
    length: object
    young_modulus: object
    shear_modulus: object
    friction_coefficient: object = None

    def __post_init__(self):
        r = _scalar(self.radius, U.m, "radius", "ElasticRod")
        L = _scalar(self.length, U.m, "length", "ElasticRod")
        E = _scalar(self.young_modulus, U.Pa, "young_modulus", "ElasticRod")
        G = _scalar(self.shear_modulus, U.Pa, "shear_modulus", "ElasticRod")
        mu = self.friction_coefficient
        if mu is not None:
            mu = float(magnitude(mu, U.dimensionless, "ElasticRod.friction_coefficient"))
            if not np.isfinite(mu) or mu < 0:
                raise ValueError(
                    f"ElasticRod.friction_coefficient must be finite and >= 0, got {mu!r}"
                )
            object.__setattr__(self, "friction_coefficient", mu)
        B = E * np.pi * r**4 / 4.0
        C = G * np.pi * r**4 / 2.0
        object.__setattr__(self, "si", RodSI(r, L, E, G, mu, B, C))

    def __repr__(self):
        mu = self.friction_coefficient
        return (
            f"ElasticRod(radius={_fmt(self.radius)}, length={_fmt(self.length)}, "
            f"young_modulus={_fmt(self.young_modulus)}, "
            f"shear_modulus={_fmt(self.shear_modulus)}, "
            f"friction_coefficient={mu if mu is None else f'{mu:g}'})"
        )




@dataclasses.dataclass(frozen=True, repr=False, eq=False)
class DNA(_Material):
    """A DNA molecule treated as a worm-like elastic rod at temperature t.

    Parameters
    ----------
    length : Quantity [length]
        Contour length L.
    bending_persistence : Quantity [length]
        Bending persistence length A; ``B = A kT``.
    twist_persistence : Quantity [length]
        Twist persistence length C_t; ``C = C_t kT``.
    radius : Quantity [length]
        Hard-core radius r_0 of the Marko-Siggia interaction.
    temperature : Quantity [temperature]
        Temperature t (kelvin or degC).
    wlc_persistence : Quantity [length], optional
        The worm-like-chain persistence length xi_T used only for the paper's
        supercoiling axis ``eta = 2 pi N xi_T / L``. In the WLC model it is the
        bending persistence length, which is the default; the paper's seed set
        uses 52 nm from a force-extension fit beside A = 48 nm.
    salt : Quantity [concentration], optional
        Monovalent ionic strength of the buffer, a molar concentration
        (``150 * ureg.mM``); needed by the screened interaction, ignored by the
        paper's hard-core one. ``None`` (default) if unknown.

    Attributes
    ----------
    kT : Quantity [energy]
        Thermal energy ``k_B t``.
    bending_rigidity, torsional_rigidity : Quantity [N m^2]
        ``B = A kT`` and ``C = C_t kT``.
    si : DNASI
        The same numbers as plain SI floats, for the float kernels.
    """

    length: object
    bending_persistence: object
    twist_persistence: object
    radius: object
    temperature: object
    wlc_persistence: object = None
    salt: object = None

    def __post_init__(self):
        L = _scalar(self.length, U.m, "length", "DNA")
        A = _scalar(self.bending_persistence, U.m, "bending_persistence", "DNA")
        Ct = _scalar(self.twist_persistence, U.m, "twist_persistence", "DNA")
        r0 = _scalar(self.radius, U.m, "radius", "DNA")
        t = _scalar(self.temperature, U.K, "temperature", "DNA")
        if self.wlc_persistence is None:
            xi = A
        else:
            xi = _scalar(self.wlc_persistence, U.m, "wlc_persistence", "DNA")
        salt = None if self.salt is None else _scalar(self.salt, U.mol_per_m3, "salt", "DNA")
        kT = BOLTZMANN * t
        object.__setattr__(self, "si", DNASI(L, A, Ct, r0, t, xi, kT, A * kT, Ct * kT, salt))

    @property
    def kT(self):
        """Thermal energy ``k_B t`` (J)."""
        return quantity(self.si.kT, U.J)

    def __repr__(self):
        return (
            f"DNA(length={_fmt(self.length)}, "
            f"bending_persistence={_fmt(self.bending_persistence)}, "
            f"twist_persistence={_fmt(self.twist_persistence)}, "
            f"radius={_fmt(self.radius)}, temperature={_fmt(self.temperature)}, "
            f"wlc_persistence={_fmt_opt(self.wlc_persistence)}, salt={_fmt_opt(self.salt)})"
        )


