"""Error of the mean of correlated frames: blocking (Flyvbjerg & Petersen 1989)."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.signal import lfilter

from supercoil.traces import blocking_error
from supercoil.traces.errors import blocking_levels


def _ar1(rng, n, phi, reps):
    e = rng.normal(size=(reps, n)) * np.sqrt(1 - phi**2)
    e[:, 0] = rng.normal(size=reps)
    return lfilter([1.0], [1.0, -phi], e, axis=1)


def _exact_error(n, phi):
    """Standard error of the mean of a unit-variance AR(1) series (closed form)."""
    k = np.arange(1, n)
    return np.sqrt((1 + 2 * np.sum((1 - k / n) * phi**k)) / n)


def test_uncorrelated_frames_give_the_naive_error():
    """White noise: block size just above (2n)^(1/3), error = std/sqrt(n) within its
    statistical error, and over 200 series the median within 3 %."""
    xs = np.random.default_rng(0).normal(size=(200, 2048))
    res = [blocking_error(x) for x in xs]
    r, x = res[0], xs[0]
    assert r.block_size == 32 and r.converged  # 32**3 > 2 * 2048 > 16**3
    naive = np.std(x, ddof=1) / np.sqrt(x.size)
    assert r.naive_error == pytest.approx(naive, rel=1e-12, abs=0)
    assert abs(r.error - naive) < 3 * r.error / np.sqrt(2 * (x.size / 32 - 1))
    assert r.mean == pytest.approx(x.mean(), rel=1e-14, abs=0)
    assert np.median([q.error for q in res]) == pytest.approx(1 / np.sqrt(2048), rel=0.03)


@pytest.mark.parametrize("phi", [0.5, 0.8])
def test_ar1_error_matches_closed_form(phi):
    """Median blocking error over 200 series within 10 % of the exact AR(1) error, while
    the naive error is off by sqrt((1 - phi)/(1 + phi)) (0.58 at 0.5, 0.33 at 0.8)."""
    n = 4096
    xs = _ar1(np.random.default_rng(1), n, phi, 200)
    res = [blocking_error(x) for x in xs]
    exact = _exact_error(n, phi)
    est = np.median([r.error for r in res])
    assert est == pytest.approx(exact, rel=0.10)
    assert np.std(xs.mean(axis=1)) == pytest.approx(exact, rel=0.15)  # the simulation itself
    naive = np.median([r.naive_error for r in res])
    assert naive / exact == pytest.approx(np.sqrt((1 - phi) / (1 + phi)), rel=0.05)
    assert all(r.converged for r in res)
    tau2 = (1 + phi) / (1 - phi)  # 2 tau_int, the statistical inefficiency
    assert np.median([r.inefficiency for r in res]) == pytest.approx(tau2, rel=0.2)


def test_too_short_for_its_correlation_is_flagged_and_conservative():
    x = _ar1(np.random.default_rng(2), 64, 0.99, 1)[0]
    r = blocking_error(x)
    assert not r.converged
    assert r.error >= r.naive_error


def test_levels_are_powers_of_two_and_start_naive():
    x = np.random.default_rng(3).normal(size=100)
    sizes, se, se_err = blocking_levels(x)
    assert list(sizes) == [1, 2, 4, 8, 16, 32]
    assert se[0] == pytest.approx(np.std(x, ddof=1) / 10, rel=1e-12, abs=0)
    assert np.all(se_err > 0)


@pytest.mark.parametrize("bad", [[1.0], [[1.0, 2.0]], [1.0, np.nan, 2.0]])
def test_bad_input_raises(bad):
    with pytest.raises(ValueError, match="blocking needs"):
        blocking_error(bad)


@given(scale=st.floats(1e-3, 1e3), shift=st.floats(-1e4, 1e4), seed=st.integers(0, 50))
def test_affine_invariance(scale, shift, seed):
    """A change of unit or origin scales the error and moves the mean, nothing else."""
    x = _ar1(np.random.default_rng(seed), 512, 0.6, 1)[0]
    a, b = blocking_error(x), blocking_error(scale * x + shift)
    assert b.block_size == a.block_size
    # abs: the shifted values carry rounding of eps |shift| each (scale 1e-3, shift 8193:
    # 1.1e-9 relative on the error)
    assert b.error == pytest.approx(scale * a.error, rel=1e-9, abs=1e-13 * abs(shift))
    assert b.mean == pytest.approx(scale * a.mean + shift, rel=1e-9, abs=1e-9 * abs(shift))


def test_quantity_in_quantity_out():
    import supercoil as sc

    x = _ar1(np.random.default_rng(4), 1024, 0.5, 1)[0]
    q = blocking_error(x * sc.ureg.nm)
    r = blocking_error(x)
    assert q.error.m_as("nm") == pytest.approx(r.error, rel=1e-12, abs=0)
    assert q.mean.to("um").m == pytest.approx(r.mean * 1e-3, rel=1e-12, abs=0)
    assert q.block_size == r.block_size


def test_pooled_inefficiency_of_short_ar1_series_is_unbiased():
    """20 AR(1) series of 240 frames (phi = 0.43, as 20 ms at 60 Hz): g = (1 + phi)/(1 - phi)
    within 3 % on average over 50 draws (measured +0.2 %; without the plateau-mean bias
    correction -9 %),
    and the error of a mean from it matches the exact one."""
    from supercoil.traces.errors import error_from_inefficiency, pooled_inefficiency

    phi, n = 0.43, 240
    rng = np.random.default_rng(7)
    exact_g = (1 + phi) / (1 - phi)
    gs = []
    for _ in range(50):
        e = rng.normal(size=(20, n))
        x = np.empty_like(e)
        x[:, 0] = e[:, 0] / np.sqrt(1 - phi**2)
        for i in range(1, n):
            x[:, i] = phi * x[:, i - 1] + e[:, i]
        g, window, ok = pooled_inefficiency(list(x))
        assert ok and 3 <= window <= 30
        gs.append(g)
    assert abs(np.mean(gs) / exact_g - 1) < 0.03
    k = np.arange(1, n)
    var_exact = (1 + 2 * np.sum((1 - k / n) * phi**k)) / n / (1 - phi**2)
    err, naive = error_from_inefficiency(x[0], np.mean(gs))
    assert err > naive
    assert abs(err**2 / var_exact - 1) < 0.35  # one series' own variance scatters ~10 %
