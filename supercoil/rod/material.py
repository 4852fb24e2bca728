"""The elastic rod (rubber cord, yarn, cable): material and SI view.

Rigidities (docs/theory/geometry.md#rigidities): ``B = E pi r^4 / 4``,
``C = G pi r^4 / 2``.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from supercoil._checks import check_material
from supercoil.materials import Material, derived_positive, format_optional, positive_scalar
from supercoil.units import U, magnitude

__all__ = ["ElasticRod", "RodSI", "check_rod"]


class RodSI(NamedTuple):
    """SI float view of an :class:`ElasticRod` (m, Pa, N m^2)."""

    radius: float
    length: float
    young_modulus: float
    shear_modulus: float
    friction_coefficient: float | None
    bending_rigidity: float
    torsional_rigidity: float



@dataclasses.dataclass(frozen=True, repr=False, eq=False)
class ElasticRod(Material):
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
        r = positive_scalar(self.radius, U.m, "radius", "ElasticRod")
        L = positive_scalar(self.length, U.m, "length", "ElasticRod")
        E = positive_scalar(self.young_modulus, U.Pa, "young_modulus", "ElasticRod")
        G = positive_scalar(self.shear_modulus, U.Pa, "shear_modulus", "ElasticRod")
        mu = self.friction_coefficient
        if mu is not None:
            mu = float(magnitude(mu, U.dimensionless, "ElasticRod.friction_coefficient"))
            if not np.isfinite(mu) or mu < 0:
                raise ValueError(
                    f"ElasticRod.friction_coefficient must be finite and >= 0, got {mu!r}"
                )
            object.__setattr__(self, "friction_coefficient", mu)
        with np.errstate(over="ignore", under="ignore"):  # checked just below
            r4 = np.float64(r) ** 4
            B, C = E * np.pi * r4 / 4.0, G * np.pi * r4 / 2.0
        B = derived_positive(B, "bending rigidity E pi r^4/4", "ElasticRod",
                             "radius, young_modulus")
        C = derived_positive(C, "torsional rigidity G pi r^4/2", "ElasticRod",
                             "radius, shear_modulus")
        object.__setattr__(self, "si", RodSI(r, L, E, G, mu, B, C))

    def __repr__(self):
        body = ", ".join(f"{f.name}={format_optional(getattr(self, f.name))}"
                         for f in dataclasses.fields(self))
        return f"ElasticRod({body})"


def check_rod(rod, name="rod"):
    """The SI view of ``rod``; TypeError naming ``name`` unless it is an :class:`ElasticRod`."""
    return check_material(rod, ElasticRod, name)
