"""Moroz-Nelson corrections (docs/theory/li-zhao.md#moroz-nelson).

C_eff, zeta, and where zeta is not valid.
"""

import numpy as np
import pint
import pytest

import supercoil as sc
from supercoil.core.dna import moroz_nelson as mn
from supercoil.core.dna import plectoneme as pl
from supercoil.units import BOLTZMANN

KT = BOLTZMANN * 300.0
R0 = 1.75e-9
B = 48e-9 * KT
C = 86e-9 * KT


def test_effective_twist_rigidity_formula(dna, ureg):
    F = np.array([0.1, 0.4, 1.2, 3.0, 100.0])
    ceff = sc.effective_twist_rigidity(dna, F * ureg.pN)
    expected = 1 / (1 / C + KT / (4 * B * np.sqrt(B * F * 1e-12)))
    np.testing.assert_allclose(ceff.to("N m^2").magnitude, expected, rtol=1e-12)
    # softer than C, tends to C at large force, rises with force
    assert np.all(ceff.to("N m^2").magnitude < C)
    assert ceff[-1].to("N m^2").magnitude == pytest.approx(C, rel=0.02, abs=0)
    assert np.all(np.diff(ceff.magnitude) > 0)
    # unit invariance
    c2 = sc.effective_twist_rigidity(dna, F * 1e-12 * ureg.N)
    np.testing.assert_allclose(c2.to(ceff.units).magnitude, ceff.magnitude, rtol=1e-12)
    with pytest.raises(ValueError, match="positive"):
        sc.effective_twist_rigidity(dna, 0 * ureg.pN)


def test_zeta_formula_and_limits(dna, ureg):
    f, m, l = 1.2e-12, 10e-21, 700e-9
    Q = B * f / KT**2 - m**2 / (4 * KT**2) - 1 / 32
    expected = 1 - 0.5 / np.sqrt(Q) + B * KT / (l * (B * f - m**2 / 4))
    z = sc.extension_factor(dna, 1.2 * ureg.pN, 10 * ureg.pN * ureg.nm, 700 * ureg.nm)
    assert z.magnitude == pytest.approx(expected, rel=1e-12, abs=0)
    # long tail, no torque: the WLC result 1 - 1/(2 sqrt(A T/kT - 1/32))
    zl = mn.extension_factor(f, 0.0, 1e3, B, KT)
    assert zl == pytest.approx(1 - 0.5 / np.sqrt(B * f / KT**2 - 1 / 32), rel=1e-9)
    # even in the torque, falls with torque, rises with force
    assert mn.extension_factor(f, -m, l, B, KT) == mn.extension_factor(f, m, l, B, KT)
    assert mn.extension_factor(f, 2 * m, l, B, KT) < mn.extension_factor(f, m, l, B, KT)
    assert mn.extension_factor(2 * f, m, l, B, KT) > mn.extension_factor(f, m, l, B, KT)
    # unit invariance
    z2 = sc.extension_factor(dna, 1.2e-12 * ureg.N, 1e-20 * ureg.J, 0.7 * ureg.um)
    assert z2.magnitude == pytest.approx(z.magnitude, rel=1e-12, abs=0)


def test_bracket_not_positive_raises_naming_force_and_torque(dna, ureg):
    with pytest.raises(sc.ValidityError, match=r"0\.05 pN.*torque 30 pN nm"):
        sc.extension_factor(dna, 0.05 * ureg.pN, 30 * ureg.pN * ureg.nm, 700 * ureg.nm)
    with pytest.raises(sc.ValidityError, match="bracket"):
        mn.long_tail_factor(0.002e-12, 0.0, B, KT)


def test_zeta_outside_unit_interval_warns(dna, ureg):
    # a short tail pushes zeta above 1
    with pytest.warns(sc.ValidityWarning, match="outside"):
        z = sc.extension_factor(dna, 0.4 * ureg.pN, 0 * ureg.pN * ureg.nm, 5 * ureg.nm)
    assert z.magnitude > 1
    # a small positive bracket (Q < 1/4) makes zeta negative
    with pytest.warns(sc.ValidityWarning, match="outside"):
        z = sc.extension_factor(dna, 0.11 * ureg.pN, 8.8 * ureg.pN * ureg.nm, 700 * ureg.nm)
    assert z.magnitude < 0


def test_zeta_validity_boundary_in_the_plectoneme_phase():
    """With the plectoneme torque, the bracket crosses zero at 0.0954 pN and the
    long-tail factor at 0.1218 pN (seed set): the reported boundary."""

    def Q(f):
        return mn.zeta_bracket(f, pl.equilibrium(f, B, C, KT, R0).torque, B, KT)

    assert Q(0.0950e-12) < 0 < Q(0.0960e-12)
    assert Q(0.121e-12) < 0.25 < Q(0.123e-12)
    assert Q(0.4e-12) > 0.25


def test_bad_inputs(dna, ureg):
    with pytest.raises(pint.DimensionalityError, match="torque"):
        sc.extension_factor(dna, 1 * ureg.pN, 1 * ureg.pN, 700 * ureg.nm)
    with pytest.raises(ValueError, match="tail_length"):
        sc.extension_factor(dna, 1 * ureg.pN, 0 * ureg.pN * ureg.nm, 0 * ureg.nm)
    with pytest.raises(pint.DimensionalityError, match="tail_length"):
        sc.extension_factor(dna, 1 * ureg.pN, 0 * ureg.pN * ureg.nm, 7.0)
