"""Issue 20, items 8-10: the fitting package's arguments give named errors.

On main: ``fit_hat_curves(d, dna, sigma=[5, 5, 5] nm)`` a numpy broadcast error
and ``sigma=1e-300 nm`` "cannot start the fit: None"; ``fit_many(...,
executor="pool")`` an AttributeError and an executor whose submit() returned
None a bare KeyError; ``simulate_rotation_curves`` with molecules=0 or -3, an
empty force array, turns_offset of the wrong length or seed="abc" raw numpy
errors.
"""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.exceptions import FitError

u = sc.ureg


@pytest.fixture(scope="module")
def dna():
    return sc.load_parameters("dna")


@pytest.fixture(scope="module")
def three(dna):
    return sc.simulate_rotation_curves(dna, [0.4, 1.2, 3.0] * u.pN, seed=1)


@pytest.fixture(scope="module")
def small(dna):
    return sc.simulate_rotation_curves(dna, [1.2] * u.pN, np.linspace(-20, 20, 21),
                                       molecules=3, seed=1)


# ---- item 8: sigma ----

def test_a_sigma_per_force_is_refused_with_the_accepted_shapes(three, dna):
    with pytest.raises(ValueError, match=r"sigma has shape \(3,\); give a scalar or one value "
                                         r"per data row \(shape \(330,\)\)"):
        sc.fit_hat_curves(three, dna, sigma=np.array([5, 5, 5]) * u.nm)


def test_a_sigma_per_row_is_accepted(dna):
    d = sc.simulate_rotation_curves(dna, [1.2] * u.pN, np.linspace(-20, 20, 21), seed=1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)
        a = sc.fit_hat_curves(d, dna, sigma=np.full(len(d), 5.0) * u.nm)
        b = sc.fit_hat_curves(d, dna, sigma=5.0 * u.nm)
    assert a.chi_square == pytest.approx(b.chi_square, rel=1e-12)


@pytest.mark.parametrize(("sigma", "limit"), [(1e-300, r"below 1e-150 L = 7\.5e-148 nm"),
                                              (1e7, r"above the contour length L = 750 nm")])
def test_an_absurd_sigma_names_its_limit(three, dna, sigma, limit):
    with pytest.raises(FitError, match=rf"sigma \(sigma argument\) of .* nm is {limit}"):
        sc.fit_hat_curves(three, dna, sigma=sigma * u.nm)


def test_an_absurd_sigma_column_names_its_limit(three, dna):
    d = three.copy()
    d["sigma"] = 1e-300
    d.attrs = dict(three.attrs, units=dict(three.attrs["units"], sigma="nm"))
    with pytest.raises(FitError, match=r"sigma \(sigma column\) of 1e-300 nm is below"):
        sc.fit_hat_curves(d, dna)


def test_fit_many_checks_the_sigma_shape_once(small, dna):
    with pytest.raises(ValueError, match=r"sigma has shape \(2,\)"):
        sc.fit_many(small, dna, sigma=[5, 5] * u.nm)


# ---- item 9: executors ----

class _NoneFuture:
    def submit(self, fn, *args, **kwargs):
        return None


class _SameFuture:
    def __init__(self):
        self.future = None

    def submit(self, fn, *args, **kwargs):
        from concurrent.futures import Future

        if self.future is None:
            self.future = Future()
            self.future.set_result(fn(*args, **kwargs))
        return self.future


@pytest.mark.parametrize("executor", ["pool", 4, object()])
def test_an_executor_without_submit_is_a_type_error(small, dna, executor):
    with pytest.raises(TypeError, match=r"executor must be None, a concurrent\.futures\."
                                        r"Executor or a dask\.distributed\.Client"):
        sc.fit_many(small, dna, executor=executor)


@pytest.mark.parametrize(("executor", "match"), [
    (_NoneFuture(), r"executor\.submit\(\) returned NoneType, not a future"),
    (_SameFuture(), r"executor\.submit\(\) returned the same future for two tasks")])
def test_a_submit_without_a_new_future_is_a_type_error(small, dna, executor, match):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)
        with pytest.raises(TypeError, match=match):
            sc.fit_many(small, dna, executor=executor)


# ---- item 10: simulate_rotation_curves ----

@pytest.mark.parametrize(("kw", "exc", "match"), [
    ({"molecules": 0}, ValueError, r"molecules must be at least 1"),
    ({"molecules": -3}, ValueError, r"molecules must be at least 1"),
    ({"molecules": True}, TypeError, r"molecules must be a positive integer"),
    ({"molecules": []}, ValueError, r"molecules is empty"),
    ({"molecules": ["a", "a"]}, ValueError, r"molecules repeats the label 'a'"),
    ({"molecules": 3, "turns_offset": [1, 2]}, ValueError,
     r"turns_offset has shape \(2,\); give one value, or one per molecule \(shape \(3,\)"),
    ({"molecules": 2, "extension_offset": [1, 2, 3] * u.nm}, ValueError,
     r"extension_offset has shape \(3,\)"),
    ({"turns_offset": np.nan}, ValueError, r"turns_offset must be finite"),
    ({"seed": "abc"}, TypeError, r"seed must be None, a non-negative integer"),
    ({"seed": -1}, ValueError, r"seed must be a non-negative integer, got -1"),
    ({"points_per_force": 1}, ValueError, r"points_per_force must be >= 2"),
    ({"turns": []}, ValueError, r"turns is empty"),
    ({"turns": [0, np.inf]}, ValueError, r"turns must be finite"),
])
def test_simulate_names_its_bad_arguments(dna, kw, exc, match):
    with pytest.raises(exc, match=match):
        sc.simulate_rotation_curves(dna, 1.2 * u.pN, **kw)


@pytest.mark.parametrize(("force", "exc", "match"), [
    (np.array([]) * u.pN, ValueError, r"force is empty"),
    (-1 * u.pN, sc.NoEquilibriumError, r"force must be positive"),
    (np.nan * u.pN, ValueError, r"force must be finite")])
def test_simulate_checks_its_forces_like_every_dna_function(dna, force, exc, match):
    with pytest.raises(exc, match=match):
        sc.simulate_rotation_curves(dna, force)


def test_per_molecule_offsets_and_seeds_still_work(dna):
    a = sc.simulate_rotation_curves(dna, 1.2 * u.pN, [0, 5], molecules=2, turns_offset=[1, 2],
                                    seed=np.random.SeedSequence(3), noise=0 * u.nm)
    b = sc.simulate_rotation_curves(dna, 1.2 * u.pN, [-1, 4], seed=np.int64(3), noise=0 * u.nm)
    assert a.attrs["provenance"]["turns_offset"] == [1.0, 2.0]
    np.testing.assert_allclose(a["extension"][:2], b["extension"], rtol=1e-13)


@pytest.mark.parametrize("model", ["li-zhao", "marko2007"])
def test_valid_turns_range_checks_its_forces_like_every_dna_function(dna, model):
    from supercoil.dna.fitting import valid_turns_range

    assert valid_turns_range(dna, np.array([]) * u.pN, model=model).shape == (0,)
    with pytest.raises(sc.NoEquilibriumError, match="force must be positive"):
        valid_turns_range(dna, -1 * u.pN, model=model)  # main (marko2007): raw sqrt warning
    with pytest.raises(ValueError, match="force must be finite"):
        valid_turns_range(dna, np.nan * u.pN, model=model)
    with pytest.raises(ValueError, match=r"force must be a scalar or 1-D"):
        valid_turns_range(dna, np.ones((2, 2)) * u.pN, model=model)
