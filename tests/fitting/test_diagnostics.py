"""Plausible limits and goodness of fit: warnings, report, test statistics."""

import math
import warnings

import numpy as np
import pytest
from fitting_helpers import simulate
from scipy import stats

import supercoil as sc
from supercoil.dna.fitting import diagnostics
from supercoil.exceptions import FitWarning, ValidityWarning


def test_runs_test_closed_forms():
    # 10 positive then 10 negative: 2 runs; mu = 1 + 2*10*10/20 = 11, var = 10*9/19
    r = np.r_[np.ones(10), -np.ones(10)]
    runs, mu, z, p = diagnostics.runs_test(r, np.arange(20))
    assert (runs, mu) == (2, 11.0)
    assert z == pytest.approx((2 - 11) / math.sqrt(90 / 19), rel=1e-12)
    assert p == pytest.approx(stats.norm.cdf(z), rel=1e-12, abs=0)
    # alternating signs: the most runs possible, nothing suspicious
    alt = np.tile([1.0, -1.0], 10)
    assert diagnostics.runs_test(alt, np.arange(20))[0] == 20
    assert diagnostics.runs_test(alt, np.arange(20))[3] > 0.99
    # the order matters: the even rows, then the odd rows: + + + + + - - - - - twice
    assert diagnostics.runs_test(r, np.argsort(np.tile([0, 1], 10), kind="stable"))[0] == 4
    assert math.isnan(diagnostics.runs_test(np.ones(5), np.arange(5))[3])  # one sign: no test


def test_runs_test_is_calibrated_on_white_noise():
    """Independent residuals: P(p < 0.05) = 0.05 (binomial band over 400 sequences)."""
    rng = np.random.default_rng(7)
    ps = np.array([diagnostics.runs_test(rng.normal(size=200), np.arange(200))[3]
                   for _ in range(400)])
    frac = np.mean(ps < 0.05)
    band = 3.5 * math.sqrt(0.05 * 0.95 / 400)
    assert abs(frac - 0.05) < band, frac


def test_chi_square_test_is_two_sided():
    p, high = diagnostics.chi_square_test(100.0, 100)
    assert p > 0.5 and high
    p, high = diagnostics.chi_square_test(200.0, 100)
    assert p == pytest.approx(2 * stats.chi2.sf(200, 100), rel=1e-10, abs=0) and high
    p, high = diagnostics.chi_square_test(40.0, 100)
    assert p == pytest.approx(2 * stats.chi2.cdf(40, 100), rel=1e-10, abs=0) and not high


def test_constant_data_warn_about_implausible_values_and_misfit(base):
    """Issue 9 item 4: constant extensions gave C_t = 15 +- 2 nm, r0 = 0.03 nm silently."""
    u = sc.ureg
    # the case with 40 instead of 110 points per force (same outcome, a third the time)
    d = sc.simulate_rotation_curves(base.replace(twist_persistence=95 * u.nm, radius=2 * u.nm),
                                    [0.4, 1.2, 3] * u.pN, seed=1, points_per_force=40)
    d["extension"] = 0.5
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = sc.fit_hat_curves(d, base)
    fit = [str(w.message) for w in caught if issubclass(w.category, FitWarning)]
    assert any(m.startswith("twist_persistence = ") and "plausible lower limit 43 nm" in m
               for m in fit), fit
    # the turns offset starts at 0 here (no channel locates zero in a flat curve),
    # and the radius ends undetermined instead of at an implausible value: both say it
    assert any((m.startswith("radius = ") and "plausible lower limit 0.4375 nm" in m)
               or "do not determine radius" in m for m in fit), fit
    assert any("runs test" in m and "does not describe the shape" in m for m in fit), fit
    assert any(issubclass(w.category, ValidityWarning) for w in caught)  # denaturation
    assert r.goodness["p_value"] < 1e-10
    text = r.report()
    assert "plausible lower limit" in text and "runs test" in text.split("[[Warnings]]")[1]


def test_sigmas_too_small_fail_the_chi_square_test(true_dna, base):
    u = sc.ureg
    df = simulate(true_dna, seed=11, noise=10 * u.nm)
    with pytest.warns(FitWarning, match=r"goodness of fit: chi-square .* larger than the "
                      r"stated sigmas allow"):
        r = sc.fit_hat_curves(df, base, sigma=5 * u.nm)
    assert r.reduced_chi_square == pytest.approx(4, rel=0.2)
    assert "goodness of fit    = chi-square test" in r.report()
    # the right sigma passes (no warning: warnings are errors in this suite)
    ok = sc.fit_hat_curves(df, base, sigma=10 * u.nm)
    assert ok.goodness["test"] == "chi-square" and ok.goodness["p_value"] > 1e-3


def test_a_correct_fit_passes_the_runs_test(result):
    assert result.goodness["test"] == "runs"
    assert result.goodness["p_value"] > 1e-3
    assert not [w for w in result.warnings if "goodness" in w]


def test_p_values_are_scipy_stats_own():
    """The diagnostics and profile levels call scipy.special directly (scipy.stats costs
    ~0.5-1 s to import): the same numbers as scipy.stats' chi2 and norm, bit for bit."""
    from supercoil.dna.fitting import profile

    for chi2, nfree in ((0.3, 1), (100.0, 100), (250.0, 180), (1e-3, 7), (900.0, 360)):
        p, high = diagnostics.chi_square_test(chi2, nfree)
        upper, lower = stats.chi2.sf(chi2, nfree), stats.chi2.cdf(chi2, nfree)
        assert p == min(1.0, 2.0 * min(upper, lower)) and high == (upper <= lower)
    r = np.random.default_rng(4).normal(size=300)
    assert diagnostics.runs_test(r, np.arange(300))[3] == stats.norm.cdf(
        diagnostics.runs_test(r, np.arange(300))[2])
    for level in (0.5, 0.6827, 0.95, 0.999):
        assert profile._chi2_ppf_1(level) == stats.chi2.ppf(level, 1)
    assert profile.sigma_level(1.0) == stats.chi2.cdf(1.0, 1)
    # erf(sqrt 2)
    assert profile.sigma_level(2.0) == pytest.approx(0.9544997361036416, rel=1e-15, abs=0)

