"""Issue 20, item 5: absurd magnitudes give a named error naming the quantity and the limit.

On main a hard-core radius of 1e-300 nm gave a ZeroDivisionError (``kT r0``
underflowed), a salt of 1e300 M a ZeroDivisionError in the Debye length, and
``geometry.curvature_partials(0.4 rad, 1e300 mm)`` a bare OverflowError
(Python floats raise where numpy gives inf).
"""

import re
import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.exceptions import ValidityError

u = sc.ureg


@pytest.fixture(scope="module")
def dna():
    return sc.load_parameters("dna")


@pytest.fixture(scope="module")
def salty():
    return sc.load_parameters("dna_150mM_nacl")


@pytest.mark.parametrize("radius", [1e-300, 1e-100, 1e-35])
@pytest.mark.parametrize("call", ["plectoneme_equilibrium", "hat_curve li-zhao",
                                  "hat_curve free-energy", "buckling_turns"])
def test_a_vanishing_hard_core_radius_names_the_reduced_stiffness(dna, radius, call):
    d = dna.replace(radius=radius * u.nm)
    fn, *model = call.split()
    kw = {"model": model[0]} if model else {}
    args = (1 * u.pN, [0, 5]) if fn == "hat_curve" else (1 * u.pN,)
    with pytest.raises(ValidityError, match=r"A/r0 .*DNA\.radius.* above its limit 1e\+30"):
        getattr(sc, fn)(d, *args, **kw)


def test_the_radius_limit_leaves_the_solvable_range_open(dna):
    # b = A/r0 = 4.8e29: inside the limit, the solver still follows its power law
    st = sc.plectoneme_equilibrium(dna.replace(radius=1.6e-28 * u.nm), 1 * u.pN)
    assert 1.0 < (st.radius / (1.6e-28 * u.nm)).m_as("") < 100.0
    # a model without the hard-core state ignores r0
    t = sc.hat_curve(dna.replace(radius=1e-300 * u.nm), 1 * u.pN, [0, 5], model="marko2007")
    assert np.isfinite(t["extension"]).all()


@pytest.mark.parametrize(("salt", "side"), [(1e300, "below"), (1e4, "below"),
                                            (1e-300, "above"), (1e-10, "above")])
def test_an_absurd_salt_names_the_debye_length_and_its_limit(salty, salt, side):
    d = salty.replace(salt=salt * u.M)
    pattern = rf"lambda_D/a \(salt {re.escape(format(salt, '.6g'))} M.* {side} its limit"
    for call in (lambda: sc.hat_curve(d, 1 * u.pN, [0, 5], interaction="screened"),
                 lambda: sc.plectoneme_equilibrium(d, 1 * u.pN, interaction="screened")):
        with pytest.raises(ValidityError, match=pattern):
            call()


def test_salts_of_real_buffers_stay_inside_the_limit(salty):
    for c in (1e-7, 5.0, 8000.0):  # 5 M is beyond NaCl's solubility; 1e-7 M is nearly pure water
        with warnings.catch_warnings():  # at 1e-7 M the gap is below a Debye length (warned)
            warnings.simplefilter("ignore", sc.exceptions.ValidityWarning)
            st = sc.plectoneme_equilibrium(salty.replace(salt=c * u.M), 4 * u.pN,
                                           interaction="screened")
        assert st.radius.m_as("nm") >= 1.0 - 1e-12  # a = 1 nm: at or outside contact


@pytest.mark.parametrize("fn", ["curvature_partials", "torsion_partials"])
def test_geometry_partials_at_huge_and_tiny_radii(fn):
    da, dr = getattr(sc.geometry, fn)(0.4 * u.rad, 1e300 * u.mm)
    assert da.m > 0 and da.m == pytest.approx(
        (np.sin(0.8) if fn == "curvature_partials" else np.cos(0.8)) / 1e297, rel=1e-14, abs=0)
    assert dr.m == 0.0  # -1.5e-595 m^-2: below the float range, 0 to rounding
    with pytest.raises(ValidityError, match=r"d (kappa|tau)/d R is -inf"):
        getattr(sc.geometry, fn)(0.4 * u.rad, 1e-300 * u.mm)  # -1.5e593 m^-2: no float


def test_geometry_scalars_overflow_into_a_named_error_not_a_python_one():
    with pytest.raises(ValidityError, match="writhe"):
        sc.geometry.writhe(0.4 * u.rad, 1e-300 * u.mm, 1e300 * u.mm)
    with pytest.raises(ValidityError, match="superhelical_turns"):
        sc.geometry.superhelical_turns(0.4 * u.rad, 1e-300 * u.mm, 1e300 * u.mm)


def test_the_simulation_and_the_fit_check_the_hard_core_scale_too(dna):
    bad = dna.replace(radius=1e-300 * u.nm)
    with pytest.raises(ValidityError, match=r"A/r0"):  # main: ZeroDivisionError
        sc.simulate_rotation_curves(bad, 1 * u.pN)
    data = sc.simulate_rotation_curves(dna, [1.2] * u.pN, np.linspace(-20, 20, 11), seed=1)
    with pytest.raises(ValidityError, match=r"A/r0"):
        sc.fit_hat_curves(data, bad)
