"""Materials: rigidities, validation, immutability, repr."""

import dataclasses

import numpy as np
import pint
import pytest

import supercoil as sc


def test_rod_rigidities_from_moduli(ureg):
    rod = sc.ElasticRod(1.0 * ureg.mm, 56.7 * ureg.cm, 4.2 * ureg.MPa, 1.51 * ureg.MPa, 0.5)
    r = 1e-3
    assert rod.bending_rigidity.m_as("N*m**2") == pytest.approx(4.2e6 * np.pi * r**4 / 4)
    assert rod.torsional_rigidity.m_as("N*m**2") == pytest.approx(1.51e6 * np.pi * r**4 / 2)
    assert rod.friction_coefficient == 0.5


def test_dna_rigidities_are_persistence_times_kT(ureg, dna):
    kT = 1.380649e-23 * 300.0
    assert dna.kT.m_as("J") == pytest.approx(kT, rel=1e-6, abs=0)
    assert dna.bending_rigidity.m_as("J*m") == pytest.approx(48e-9 * kT, rel=1e-6, abs=0)
    assert dna.torsional_rigidity.m_as("J*m") == pytest.approx(86e-9 * kT, rel=1e-6, abs=0)
    assert dna.si.wlc_persistence == pytest.approx(52e-9, rel=1e-6, abs=0)


def test_dna_wlc_persistence_defaults_to_bending_persistence(ureg):
    d = sc.DNA(750 * ureg.nm, 50 * ureg.nm, 90 * ureg.nm, 1.75 * ureg.nm, 300 * ureg.K)
    assert d.si.wlc_persistence == d.si.bending_persistence
    # and follows a replaced bending persistence
    si = d.replace(bending_persistence=40 * ureg.nm).si
    assert si.wlc_persistence == pytest.approx(40e-9, rel=1e-6, abs=0)


def test_unit_invariance_of_materials(ureg):
    a = sc.DNA(0.75 * ureg.um, 48 * ureg.nm, 86 * ureg.nm, 1.75 * ureg.nm, 300 * ureg.K)
    b = sc.DNA(750e-9 * ureg.m, 4.8e-8 * ureg.m, 0.086 * ureg.um, 17.5 * ureg.angstrom,
               ureg.Quantity(26.85, "degC"))
    np.testing.assert_allclose(a.si[:-1], b.si[:-1], rtol=1e-12)
    assert a.si.salt is None and b.si.salt is None
    # salt: 150 mM = 0.15 mol/L = 150 mol/m^3 (the SI view)
    s1 = a.replace(salt=150 * ureg.mM).si.salt
    s2 = a.replace(salt=0.15 * ureg.mol / ureg.L).si.salt
    assert s1 == pytest.approx(150.0, rel=1e-12) and s2 == pytest.approx(s1, rel=1e-12)
    with pytest.raises(pint.DimensionalityError, match="salt"):
        a.replace(salt=150 * ureg.nm)
    with pytest.raises(ValueError, match="salt"):
        a.replace(salt=-1 * ureg.mM)


def test_materials_are_immutable(rubber_rod):
    with pytest.raises(dataclasses.FrozenInstanceError):
        rubber_rod.radius = 2


@pytest.mark.parametrize(
    ("field", "value", "error", "match"),
    [
        ("radius", 1.0, pint.DimensionalityError, "ElasticRod.radius"),
        ("young_modulus", "1 mm", pint.DimensionalityError, "ElasticRod.young_modulus"),
        ("length", -1.0, ValueError, "positive"),
        ("shear_modulus", float("nan"), ValueError, "finite"),
        ("friction_coefficient", -0.1, ValueError, "friction_coefficient"),
    ],
)
def test_rod_validation(ureg, field, value, error, match):
    kw = dict(radius=1 * ureg.mm, length=50 * ureg.cm, young_modulus=4 * ureg.MPa,
              shear_modulus=1.5 * ureg.MPa)
    if isinstance(value, str):
        value = ureg.Quantity(value)
    elif field != "friction_coefficient" and field != "radius":
        unit = {"length": ureg.m, "shear_modulus": ureg.Pa}[field]
        value = value * unit
    kw[field] = value
    with pytest.raises(error, match=match):
        sc.ElasticRod(**kw)


def test_dna_rejects_array_and_wrong_dimension(ureg):
    with pytest.raises(ValueError, match="scalar"):
        sc.DNA([1, 2] * ureg.um, 48 * ureg.nm, 86 * ureg.nm, 1.75 * ureg.nm, 300 * ureg.K)
    with pytest.raises(pint.DimensionalityError, match=r"DNA\.temperature"):
        sc.DNA(1 * ureg.um, 48 * ureg.nm, 86 * ureg.nm, 1.75 * ureg.nm, 300 * ureg.s)


def test_repr_is_readable(rubber_rod, dna):
    assert repr(rubber_rod) == (
        "ElasticRod(radius=1 mm, length=56.7 cm, young_modulus=4.2 MPa, "
        "shear_modulus=1.51 MPa, friction_coefficient=0.5)"
    )
    assert repr(dna).startswith("DNA(length=750 nm, bending_persistence=48 nm")


def test_equality_and_hash(ureg, rubber_rod):
    same = sc.ElasticRod(0.1 * ureg.cm, 567 * ureg.mm, 4200 * ureg.kPa, 1.51 * ureg.MPa, 0.5)
    assert same == rubber_rod
    assert hash(same) == hash(rubber_rod)
