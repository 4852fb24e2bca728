"""Issue 22 item 5: profile-likelihood confidence intervals, checked against the Jacobian
errors on a near-linear problem and against repeated simulation on a non-linear one."""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.exceptions import FitError


def test_near_linear_profile_matches_the_jacobian_errors(result):
    # the extension offset enters linearly; the others nearly so at 5 nm noise
    for name, tol in (("extension_offset", 0.08), ("turns_offset", 0.05), ("radius", 0.08)):
        p = result.profile(name)
        e = result.stderr[name].magnitude
        assert p.best == pytest.approx(result.parameters[name].magnitude, rel=1e-9)
        assert p.best - p.lower_bound == pytest.approx(e, rel=tol), name
        assert p.upper_bound - p.best == pytest.approx(e, rel=tol), name
        # two sigma: twice as wide on a parabola
        hi2 = p.interval(0.9545)[1]
        assert np.isnan(hi2) or hi2 - p.best == pytest.approx(2 * e, rel=2 * tol)
    table = result.conf_interval(["extension_offset"], sigmas=(1, 2))
    row = table.loc["extension_offset"]
    assert row["lower_1sigma"] < row["best"] < row["upper_1sigma"]
    assert row["upper_2sigma"] - row["best"] == pytest.approx(
        2 * (row["upper_1sigma"] - row["best"]), rel=0.1)
    assert table.attrs["units"]["extension_offset"] == "nm"


def test_profile_plot_and_errors(result, tmp_path):
    import matplotlib.pyplot as plt

    p = result.profile("radius")
    fig = p.plot(path=tmp_path / "profile.png", dpi=40)  # saved where asked, figure returned
    assert (tmp_path / "profile.png").read_bytes()[:4] == b"\x89PNG"
    ax = fig.axes[0]
    assert ax.get_ylabel() == "Δχ²" and len(ax.lines) >= 3
    x, y = ax.lines[0].get_data()  # the profile passes through the best fit at zero
    assert np.all(np.diff(x) > 0) and y[list(x).index(p.best)] == 0.0
    plt.close(fig)
    with pytest.raises(FitError, match="not a free parameter"):
        result.profile("length")
    with pytest.raises(FitError, match="confidence_level"):
        result.profile("radius", confidence_level=1.5)


def test_non_linear_profile_against_repeated_simulation(base):
    """One low force, few noisy points: C_t's profile is asymmetric, the Jacobian's error
    symmetric; the profile's width agrees with the spread of repeated fits."""
    u = sc.ureg
    true = base.replace(twist_persistence=95 * u.nm, radius=2.0 * u.nm)
    vary = ["radius", "twist_persistence"]

    def fit(seed):
        d = sc.simulate_rotation_curves(true, [0.3] * u.pN, points_per_force=30,
                                        noise=20 * u.nm, seed=seed)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # misfit warnings of single noisy samples
            return sc.fit_hat_curves(d, base, vary=vary, fit_turns_offset=False)

    r = fit(1)
    p = r.profile("twist_persistence")
    up, down = p.upper_bound - p.best, p.best - p.lower_bound
    assert up / down > 1.2  # non-linear: the profile is asymmetric
    est = np.array([fit(s).parameters["twist_persistence"].m_as("nm") for s in range(2, 32)])
    q16, q84 = np.percentile(est, [16, 84])
    assert up + down == pytest.approx(q84 - q16, rel=0.3)
