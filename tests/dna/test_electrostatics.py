"""Electrostatics of DNA in salt: permittivity, Bjerrum and Debye lengths, Stigter charge.

Published numbers (each cited on its line) and independent references: SI-constant
formulas written out here, the linear Poisson-Boltzmann limit, a second PB method
(scipy.integrate.solve_bvp against the kernel's inward shooting).
"""

import math

import numpy as np
import pint
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy import constants as sc_const
from scipy.integrate import solve_bvp
from scipy.special import k0, k1

import supercoil as sc
from supercoil.core.dna import electrostatics as el
from supercoil.dna.interactions import get_interaction
from supercoil.exceptions import ValidityError

T25 = 298.15


def test_permittivity_malmberg_maryott_fit_values():
    # Malmberg & Maryott, J. Res. NBS 56, 1 (1956): the fit's constant term is eps_r(0 degC)
    assert el.water_permittivity(273.15) == pytest.approx(87.740, abs=1e-12)
    # the fit evaluated at 25 degC (a computed value, not a table read in the paper)
    assert el.water_permittivity(T25) == pytest.approx(78.30, abs=0.01)
    # permittivity falls with temperature over the whole range of the fit
    t = np.linspace(273.15, 373.15, 101)
    assert np.all(np.diff(el.water_permittivity(t)) < 0)


@pytest.mark.parametrize("t", [272.0, 374.0])
def test_permittivity_outside_fit_range_is_a_named_error(t):
    with pytest.raises(ValidityError, match=r"temperature .* K"):
        el.water_permittivity(t)


def test_bjerrum_length_at_25C():
    # l_B = e^2/(4 pi eps0 eps_r kT) "about 0.715 nm" at 25 degC in water
    lB = el.bjerrum_length(T25)
    assert lB * 1e9 == pytest.approx(0.715, rel=2e-3)
    # independent: CODATA constants from scipy, eps_r from the fit
    ref = sc_const.e**2 / (4 * np.pi * sc_const.epsilon_0 * el.water_permittivity(T25)
                           * sc_const.k * T25)
    assert lB == pytest.approx(ref, rel=1e-9, abs=0)


@given(st.floats(1.0, 1000.0))
def test_debye_length_0304_over_sqrt_molar_at_25C(c_mM):
    # lambda_D = 0.304 / sqrt(c / M) nm for a 1:1 salt at 25 degC (to 0.5 %)
    lam = el.debye_length(c_mM, T25) * 1e9
    assert lam == pytest.approx(0.304 / math.sqrt(c_mM / 1000.0), rel=5e-3)
    # independent: lambda = sqrt(eps0 eps_r kT / (2 N_A e^2 c)), c in mol/m^3
    ref = math.sqrt(sc_const.epsilon_0 * el.water_permittivity(T25) * sc_const.k * T25
                    / (2 * sc_const.N_A * sc_const.e**2 * c_mM))
    assert lam * 1e-9 == pytest.approx(ref, rel=1e-9, abs=0)


def test_debye_length_temperature_enters_through_eps_r_times_T():
    c = 150.0
    for t in (278.15, 298.15, 318.15):
        ratio = el.debye_length(c, t) / el.debye_length(c, T25)
        expect = math.sqrt(el.water_permittivity(t) * t / (el.water_permittivity(T25) * T25))
        assert ratio == pytest.approx(expect, rel=1e-12, abs=0)
    # eps_r T falls with T, so water screens slightly better when warm
    assert el.debye_length(c, 318.15) < el.debye_length(c, 278.15)


@pytest.mark.parametrize("bad", [0.0, -5.0, float("nan"), float("inf")])
def test_debye_length_rejects_nonpositive_salt(bad):
    with pytest.raises(ValueError, match="salt"):
        el.debye_length(bad, T25)


@pytest.mark.parametrize("c", [10.0, 150.0, 1000.0])
def test_effective_charge_linear_pb_limit(c):
    # weakly charged cylinder: nonlinear PB -> linear, nu = nu0 / (kappa a K1(kappa a))
    a = 1e-9
    nu0 = 1e-4 * el.BARE_LINE_CHARGE
    lam = el.debye_length(c, T25)
    x = a / lam
    nu = el.effective_line_charge(c, T25, a, nu0)
    assert nu == pytest.approx(nu0 / (x * k1(x)), rel=1e-6)


def _nu_by_solve_bvp(c, a, nu0):
    """Second method: PB on [a, r_far] as a boundary-value problem (Robin far condition)."""
    lB = el.bjerrum_length(T25)
    kappa = 1 / el.debye_length(c, T25)
    r_far = a + 30 / kappa
    r = np.linspace(a, r_far, 4001)
    nu_lin = el.linear_line_charge(nu0, a, 1 / kappa)
    y_guess = np.vstack([2 * lB * 0.5 * nu_lin * k0(kappa * r),
                         -2 * lB * 0.5 * nu_lin * kappa * k1(kappa * r)])

    def f(x, y):
        return np.vstack([y[1], kappa**2 * np.sinh(y[0]) - y[1] / x])

    q = kappa * k1(kappa * r_far) / k0(kappa * r_far)

    def bc(ya, yb):
        return np.array([ya[1] + 2 * lB * nu0 / a, yb[1] + q * yb[0]])

    sol = solve_bvp(f, bc, r, y_guess, tol=1e-9, max_nodes=200000)
    assert sol.success
    return sol.sol(r_far)[0] / (2 * lB * k0(kappa * r_far))


@pytest.mark.parametrize("c", [10.0, 150.0, 1000.0])
def test_effective_charge_matches_a_second_pb_method(c):
    a, nu0 = 1e-9, el.BARE_LINE_CHARGE
    assert el.effective_line_charge(c, T25, a, nu0) == pytest.approx(
        _nu_by_solve_bvp(c, a, nu0), rel=1e-5)


def test_effective_charge_trends_and_renormalisation():
    salts = [10.0, 20.0, 50.0, 100.0, 150.0, 200.0, 500.0, 1000.0]
    nu = np.array([el.effective_line_charge(c, T25, 1e-9) for c in salts])
    lin = np.array([el.linear_line_charge(el.BARE_LINE_CHARGE, 1e-9, el.debye_length(c, T25))
                    for c in salts])
    assert np.all(np.diff(nu) > 0)  # the far field of the cylinder grows with salt
    assert np.all(nu < lin)  # nonlinear screening renormalises the charge down
    # independent recomputation of Stigter's matching (a separate solve_bvp computation,
    # not literature): 2.377, 5.621, 7.203, 51.74 per nm at 10, 100, 150, 1000 mM
    for c, ref in ((10.0, 2.377), (100.0, 5.621), (150.0, 7.203), (1000.0, 51.74)):
        assert el.effective_line_charge(c, T25, 1e-9) * 1e-9 == pytest.approx(ref, rel=1e-3)


def test_charge_fraction_reduces_the_effective_charge():
    # Maffeo et al., PRL 105, 158101 (2010), abstract: 40 % of the nominal charge density
    full = el.effective_line_charge(150.0, T25, 1e-9)
    reduced = el.effective_line_charge(150.0, T25, 1e-9, 0.4 * el.BARE_LINE_CHARGE)
    assert reduced < full
    # nonlinear screening: a 60 % cut of the bare charge is a smaller cut of the far field
    assert reduced / full > 0.4


def test_screening_lengths_unit_invariance(ureg):
    dna = sc.load_parameters("dna_150mM_nacl")
    inter = get_interaction("screened")
    ref = inter.lengths(dna)
    for salt in (0.15 * ureg.molar, 150 * ureg.mol / ureg.m**3, 150e3 * ureg.umolar):
        got = inter.lengths(dna.replace(salt=salt, temperature=ureg.Quantity(25.0, "degC")))
        for key, q in ref.items():
            assert got[key].m_as(q.units) == pytest.approx(q.magnitude, rel=1e-12, abs=0)
    assert ref["debye_length"].m_as("nm") == pytest.approx(0.7845, rel=1e-3)


def test_dna_salt_is_a_checked_concentration(ureg):
    dna = sc.load_parameters("dna")
    assert dna.salt is None and dna.si.salt is None
    with pytest.raises(pint.DimensionalityError, match=r"DNA\.salt"):
        dna.replace(salt=150 * ureg.nm)
    with pytest.raises(ValueError, match=r"DNA\.salt"):
        dna.replace(salt=-1 * ureg.mM)


@pytest.mark.parametrize(("name", "salt_mM", "A_nm"),
                         [("dna_10mM_nacl", 10, 56), ("dna_150mM_nacl", 150, 50),
                          ("dna_1M_nacl", 1000, 46)])
def test_salt_parameter_sets_load_with_sources(name, salt_mM, A_nm):
    ps = sc.parameters.read_parameter_set(name)
    dna = ps.material
    assert dna.si.salt == pytest.approx(salt_mM, rel=1e-12)
    assert dna.si.temperature == pytest.approx(T25)
    assert dna.bending_persistence.m_as("nm") == pytest.approx(A_nm)
    assert dna.twist_persistence.m_as("nm") == pytest.approx(100.0)
    assert set(ps.sources) == set(ps.values)  # one source line per value
    assert "Wenner" in ps.sources["bending_persistence"]
    assert "Bryant" in ps.sources["twist_persistence"]


def test_seed_set_is_unchanged():
    dna = sc.load_parameters("dna")
    si = dna.si
    assert si.salt is None
    assert (si.length, si.bending_persistence, si.twist_persistence, si.radius,
            si.temperature, si.wlc_persistence) == pytest.approx(
        (750e-9, 48e-9, 86e-9, 1.75e-9, 300.0, 52e-9), rel=1e-12, abs=0)
