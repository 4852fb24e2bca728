"""The DNA molecule: material and SI view.

Rigidities (docs/theory/geometry.md#rigidities): ``B = A kT``, ``C = C_t kT``
with A the bending and C_t the twist persistence length and ``kT = k_B t``.
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import numpy as np

from supercoil.materials import Material, derived_positive, format_optional, positive_scalar
from supercoil.units import BOLTZMANN, U, quantity

__all__ = ["DNA", "DNASI"]


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



@dataclasses.dataclass(frozen=True, repr=False, eq=False)
class DNA(Material):
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
        Monovalent ionic strength of the buffer (e.g. ``150 * ureg.mM``), used by
        salt-dependent interactions (``interaction="screened"``). ``None``
        (the default, and the seed set) if unknown: the paper's hard-core
        interaction does not use it.

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
        L = positive_scalar(self.length, U.m, "length", "DNA")
        A = positive_scalar(self.bending_persistence, U.m, "bending_persistence", "DNA")
        Ct = positive_scalar(self.twist_persistence, U.m, "twist_persistence", "DNA")
        r0 = positive_scalar(self.radius, U.m, "radius", "DNA")
        t = positive_scalar(self.temperature, U.K, "temperature", "DNA")
        if self.wlc_persistence is None:
            xi = A
        else:
            xi = positive_scalar(self.wlc_persistence, U.m, "wlc_persistence", "DNA")
        salt = None
        if self.salt is not None:
            salt = positive_scalar(self.salt, U.mol_per_m3, "salt", "DNA")
        with np.errstate(over="ignore", under="ignore"):  # checked just below
            kT, B, C = BOLTZMANN * t, A * BOLTZMANN * t, Ct * BOLTZMANN * t
        kT = derived_positive(kT, "thermal energy kT", "DNA", "temperature")
        B = derived_positive(B, "bending rigidity A kT", "DNA",
                             "bending_persistence, temperature")
        C = derived_positive(C, "torsional rigidity C_t kT", "DNA",
                             "twist_persistence, temperature")
        object.__setattr__(self, "si", DNASI(L, A, Ct, r0, t, xi, kT, B, C, salt))

    @property
    def kT(self):
        """Thermal energy ``k_B t`` (J)."""
        return quantity(self.si.kT, U.J)

    def __repr__(self):
        body = ", ".join(
            f"{f.name}={format_optional(getattr(self, f.name))}"
            for f in dataclasses.fields(self)
            if f.name not in ("salt",) or self.salt is not None
        )
        return f"DNA({body})"
