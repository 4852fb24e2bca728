"""The unit boundary: one registry, dimension checks naming the argument, cheap conversions."""

import numpy as np
import pint
import pytest

import supercoil as sc
from supercoil.units import U, as_turns, magnitude, quantity


def test_single_registry_is_exported():
    assert sc.ureg is sc.units.ureg
    assert isinstance(sc.ureg, pint.UnitRegistry)


def test_magnitude_converts_to_target_unit(ureg):
    assert magnitude(3.0 * ureg.nm, U.m, "x") == pytest.approx(3e-9, rel=1e-15, abs=0)
    assert magnitude(2.0 * ureg.pN * ureg.nm, U.J, "x") == pytest.approx(2e-21, rel=1e-15, abs=0)
    arr = magnitude(np.array([1.0, 2.0]) * ureg.mm, U.m, "x")
    np.testing.assert_allclose(arr, [1e-3, 2e-3], rtol=1e-15)


def test_magnitude_handles_offset_units(ureg):
    assert magnitude(ureg.Quantity(26.85, "degC"), U.K, "t") == pytest.approx(300.0)


def test_wrong_dimension_names_the_argument(ureg):
    with pytest.raises(pint.DimensionalityError, match="'pitch'"):
        magnitude(1.0 * ureg.s, U.m, "pitch")


def test_plain_number_rejected_for_dimensional_argument():
    with pytest.raises(pint.DimensionalityError, match=r"'radius'.*plain number"):
        magnitude(1.0, U.m, "radius")


def test_other_registry_rejected():
    other = pint.UnitRegistry()
    with pytest.raises(TypeError, match="another pint UnitRegistry"):
        magnitude(1.0 * other.m, U.m, "length")


def test_unit_object_instead_of_quantity_rejected(ureg):
    with pytest.raises(TypeError, match="unit, not a quantity"):
        magnitude(ureg.m, U.m, "length")


def test_turns_from_numbers_and_angles(ureg):
    assert as_turns(40) == 40.0
    assert as_turns(40 * ureg.dimensionless) == 40.0
    assert as_turns(40 * ureg.turn) == pytest.approx(40.0)
    assert as_turns(80 * np.pi * ureg.rad) == pytest.approx(40.0)
    assert as_turns(720 * ureg.degree) == pytest.approx(2.0)
    with pytest.raises(pint.DimensionalityError, match="'turns'"):
        as_turns(3 * ureg.m)


def test_quantity_attaches_prebuilt_unit():
    q = quantity(np.array([1.0, 2.0]), U.nm)
    assert q.units == sc.ureg.nm
    assert q._REGISTRY is sc.ureg


def test_conversion_factor_cache_is_consistent(ureg):
    # the same conversion done twice (second time from the cache) agrees with pint
    for _ in range(2):
        v = magnitude(5.0 * ureg.um, U.m, "x")
        assert v == pytest.approx((5.0 * ureg.um).m_as(ureg.m), rel=1e-15, abs=0)


def test_dimensionless_accepts_any_array_like_and_rejects_text():
    np.testing.assert_array_equal(as_turns(range(3)), [0.0, 1.0, 2.0])
    import pandas as pd

    np.testing.assert_array_equal(as_turns(pd.Series([1, 2])), [1.0, 2.0])
    with pytest.raises(TypeError, match="'turns' must be a number"):
        as_turns({"forty": 40})


def test_list_of_quantities_and_text_inputs(ureg):
    np.testing.assert_allclose(magnitude([0.4 * ureg.pN, 1.2 * ureg.pN], U.N, "force"),
                               [0.4e-12, 1.2e-12])
    with pytest.raises(pint.DimensionalityError, match=r"'force'.*incompatible"):
        magnitude([0.4 * ureg.pN, 1.2 * ureg.nm], U.N, "force")
    with pytest.raises(TypeError, match="'turns' is text"):
        as_turns("5")
    with pytest.raises(TypeError, match="'force' is text"):
        magnitude("1 pN", U.N, "force")


def test_thermal_flag_must_be_boolean(dna, ureg):
    with pytest.raises(TypeError, match="thermal must be True or False"):
        sc.hat_curve(dna, 1 * ureg.pN, [0.0], thermal="no")


def test_turns_from_non_angle_dimensionless_units_are_ratios(ureg):
    """percent or m/mm are plain ratios of a count, not radians (no 2 pi trap)."""
    assert as_turns(4000 * ureg.percent) == pytest.approx(40.0)
    assert as_turns(0.04 * ureg.m / ureg.mm) == pytest.approx(40.0)
    assert as_turns(2 * np.pi * ureg.rad / ureg.m * ureg.m) == pytest.approx(1.0)


def test_turns_from_another_registry_rejected():
    other = pint.UnitRegistry()
    with pytest.raises(TypeError, match="another pint UnitRegistry"):
        as_turns(40 * other.dimensionless)
