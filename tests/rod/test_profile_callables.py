"""Issue 20, item 6: the profile callables are checked once (supercoil._checks).

On main ``design_twist_schedule(rod, 16 mm)`` or ``None`` gave "'Quantity'
object is not callable", a pitch returning 3 values a numpy broadcast error, and
``rough_helix(rod, 40, twist_rate=lambda S: np.ones(3) / m)`` "cannot broadcast
a non-scalar to a scalar array".
"""

import numpy as np
import pytest

import supercoil as sc

u = sc.ureg


@pytest.fixture(scope="module")
def rod():
    return sc.load_parameters("silicone_rubber_rod")


@pytest.mark.parametrize("pitch", [16 * u.mm, None, "16 mm", 16.0])
def test_a_pitch_that_is_not_callable_is_named(rod, pitch):
    with pytest.raises(TypeError, match=r"pitch must be a callable pitch\(s\) -> Quantity "
                                        r"\[length\], got"):
        sc.design_twist_schedule(rod, pitch)


def test_a_pitch_derivative_that_is_not_callable_is_named(rod):
    with pytest.raises(TypeError, match=r"pitch_derivative must be a callable"):
        sc.design_twist_schedule(rod, lambda s: 16 * u.mm, pitch_derivative=0.0)


@pytest.mark.parametrize("which", ["pitch", "pitch_derivative"])
def test_a_profile_of_the_wrong_shape_names_the_shape_expected(rod, which):
    kw = {"pitch": lambda s: np.full(3, 16.0) * u.mm} if which == "pitch" else {
        "pitch": lambda s: 16 * u.mm, "pitch_derivative": lambda s: np.zeros(3) * u.dimensionless}
    with pytest.raises(ValueError, match=rf"{which}\(s\) returned an array of shape \(3,\); "
                                         r"it must return a scalar or one value per point "
                                         r"of its argument \(shape \(41,\)\)"):
        sc.design_twist_schedule(rod, n_points=41, **kw)


def test_a_constant_pitch_given_as_a_scalar_callable_still_works(rod):
    t = sc.design_twist_schedule(rod, lambda s: 16 * u.mm, n_points=41)
    assert np.allclose(t["pitch"], 16.0, rtol=1e-12)


def test_a_twist_rate_of_the_wrong_shape_is_named(rod):
    with pytest.raises(ValueError, match=r"twist_rate\(slack\) returned an array of shape "
                                         r"\(3,\); it must return a scalar or one value per "
                                         r"point"):
        sc.rough_helix(rod, 40, twist_rate=lambda S: np.ones(3) / u.m)
