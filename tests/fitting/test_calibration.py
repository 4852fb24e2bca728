"""Calibration nuisance parameters torque_scale and force_scale.

docs/theory/fitting.md#calibration-nuisance-parameters. References: default off (a fit
without them is bit-identical to one that never heard of them); every Jacobian column
against central differences; the fit recovers a known torque scale (model torque =
s x measured torque) and a known force scale (true force = s x nominal force) of
simulated data within its errors; the names are checked.
"""

import numpy as np
import pytest
from fitting_helpers import FORCES

import supercoil as sc
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.dna.fitting.model import HatCurveModel
from supercoil.exceptions import FitError

TORQUE_NOISE = 1.0  # pN nm
TRUE_TS = 0.7  # model torque = 0.7 x measured torque
TRUE_FS = 1.08  # true force = 1.08 x nominal force


def _sim(dna, force_scale=1.0, seed=3, **kw):
    u = sc.ureg
    df = simulate_rotation_curves(dna, np.array(FORCES) * force_scale * u.pN, seed=seed,
                                  points_per_force=60, noise=3 * u.nm, turns_offset=0.4,
                                  extension_offset=20 * u.nm,
                                  torque_noise=TORQUE_NOISE * u.pN * u.nm, **kw)
    df["force"] = np.round(df["force"] / force_scale, 12)  # the nominal force
    return df


@pytest.fixture(scope="module")
def scaled_torque(true_dna):
    df = _sim(true_dna)
    df["torque"] = df["torque"] / TRUE_TS  # measured = model / s
    return df


def test_default_is_off_and_identical(scaled_torque, base):
    plain = sc.fit_hat_curves(scaled_torque, base)
    fixed1 = sc.fit_hat_curves(scaled_torque, base, fixed={"torque_scale": 1.0})
    assert "torque_scale" not in plain.parameters and "torque_scale" not in plain.fixed
    for name in plain.names:
        assert fixed1.parameters[name].m == plain.parameters[name].m


def test_jacobian_columns_of_the_scales_match_central_differences(scaled_torque, base):
    spec = fitting.prepare(scaled_torque.iloc[::3].reset_index(drop=True), base,
                           vary=["twist_persistence", "torque_scale", "force_scale"],
                           start={"turns_offset": 0.3, "extension_offset": 10 * sc.ureg.nm,
                                  "torque_scale": 0.8})
    prob = HatCurveModel(spec.data, spec.params, spec.dna, spec.model, spec.interaction,
                         spec.thermal)
    u = spec.params.vector() * 1.01
    J = prob.jacobian(u)
    n = spec.data.n
    for j, name in enumerate(prob.names):
        h = 1e-4 if "turns" in name else 1e-5
        up, um = u.copy(), u.copy()
        up[j] += h
        um[j] -= h
        ref = (prob.residual(up) - prob.residual(um)) / (2 * h)
        assert np.abs(ref).max() > 0, name
        np.testing.assert_allclose(J[:, j], ref, rtol=0, atol=3e-3 * np.abs(ref).max(),
                                   err_msg=name)
    jt = prob.names.index("torque_scale")
    assert np.all(J[:n, jt] == 0) and np.any(J[n:, jt] != 0)  # the torque rows only
    jf = prob.names.index("force_scale")
    assert np.any(J[:n, jf] != 0) and np.any(J[n:, jf] != 0)  # both channels


def test_fit_recovers_the_torque_scale(scaled_torque, base, true_dna):
    r = sc.fit_hat_curves(scaled_torque, base, vary=["twist_persistence", "radius",
                                                     "torque_scale"])
    ts, err = r.parameters["torque_scale"].m, r.stderr["torque_scale"].m
    assert 0 < err < 0.05
    assert abs(ts - TRUE_TS) < 4 * err
    assert abs(r.parameters["twist_persistence"].m - true_dna.twist_persistence.m_as("nm")) \
        < 4 * r.stderr["twist_persistence"].m
    assert r.channels["torque"]["residual_rms"].m == pytest.approx(TORQUE_NOISE / TRUE_TS,
                                                                   rel=0.15)
    # the torque best fit is the predicted measurement (model / s), residuals are the noise
    res = r.torque_residuals.m_as("pN*nm")
    assert abs(np.mean(res)) < 0.3 and np.std(res) == pytest.approx(TORQUE_NOISE / TRUE_TS,
                                                                     rel=0.15)
    text = r.report()
    assert "torque_scale" in text
    assert "torque_scale" in r.to_frame().columns
    # without the scale the torque channel cannot be fitted as well
    r1 = sc.fit_hat_curves(scaled_torque, base, vary=["twist_persistence", "radius"])
    assert r1.channels["torque"]["residual_rms"].m > 1.5 * r.channels["torque"][
        "residual_rms"].m


def test_report_gives_c_over_the_torque_scale_with_its_propagated_error(scaled_torque, base):
    """C / s (the twist stiffness in the measured torque's units) and its delta-method
    error against a second method: the spread of C / s over draws from the covariance."""
    from supercoil.dna.fitting.report import twist_in_trap_units

    r = sc.fit_hat_curves(scaled_torque, base, vary=["twist_persistence", "radius",
                                                     "torque_scale"])
    value, err = twist_in_trap_units(r)
    C, s = r.parameters["twist_persistence"].m_as("nm"), r.parameters["torque_scale"].m
    assert value == pytest.approx(C / s, rel=1e-15, abs=0)
    cov = r.covariance.loc[["twist_persistence", "torque_scale"],
                           ["twist_persistence", "torque_scale"]].to_numpy()
    draws = np.random.default_rng(7).multivariate_normal([C, s], cov, size=200_000)
    assert err == pytest.approx(np.std(draws[:, 0] / draws[:, 1]), rel=0.03)
    assert f"twist_persistence / torque_scale = {value:.6g} +/- {err:.4g} nm" in r.report()
    # without a free torque scale there is nothing to derive
    plain = sc.fit_hat_curves(scaled_torque, base, vary=["twist_persistence", "radius"])
    assert twist_in_trap_units(plain) is None and "[[Derived]]" not in plain.report()


def test_fixed_torque_scale_is_reported_as_fixed(scaled_torque, base):
    r = sc.fit_hat_curves(scaled_torque, base, fixed={"torque_scale": TRUE_TS})
    assert r.fixed["torque_scale"].m == pytest.approx(TRUE_TS)
    res = r.torque_residuals.m_as("pN*nm")
    assert np.std(res) == pytest.approx(TORQUE_NOISE / TRUE_TS, rel=0.15)


def test_fit_recovers_the_force_scale(true_dna, base):
    df = _sim(true_dna, force_scale=TRUE_FS, seed=9)
    r = sc.fit_hat_curves(df, true_dna, vary=["force_scale"])
    fs, err = r.parameters["force_scale"].m, r.stderr["force_scale"].m
    assert 0 < err < 0.05
    assert abs(fs - TRUE_FS) < 4 * err
    # the nominal forces alone leave a worse fit
    with pytest.warns(sc.FitWarning, match="runs test"):
        r0 = sc.fit_hat_curves(df, true_dna, vary=[], fit_turns_offset=True)
    assert r0.residual_rms.m > 1.15 * r.residual_rms.m


@pytest.mark.parametrize("kw, match", [
    ({"vary": ["torque_scale"]}, "no 'torque' column"),
    ({"fixed": {"force_scale": -1.0}}, "finite and positive"),
    ({"vary": ["torque_scal"]}, "torque_scale"),
])
def test_bad_calibration_names_and_values(true_dna, base, kw, match):
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * sc.ureg.pN, seed=1,
                                  points_per_force=30)
    with pytest.raises(FitError, match=match):
        sc.fit_hat_curves(df, base, **kw)


def test_compare_models_takes_the_scale_and_start_values(scaled_torque, base):
    from supercoil.dna.fitting import compare_models

    start = {"turns_offset": 0.2}
    comparison = compare_models(scaled_torque, base, ["li-zhao"], start=start,
                                vary={"li-zhao": ["twist_persistence", "radius", "torque_scale"]})
    table, res = comparison.table, comparison.results
    single = sc.fit_hat_curves(scaled_torque, base,
                               vary=["twist_persistence", "radius", "torque_scale"],
                               start=start)
    assert table["torque_scale"].iloc[0] == pytest.approx(
        single.parameters["torque_scale"].m, rel=1e-9)
    assert res["li-zhao"].start["turns_offset"].m_as("turn") == pytest.approx(0.2)


def test_plot_and_fit_many_carry_the_scales(scaled_torque, base):
    import matplotlib.pyplot as plt

    vary = ["twist_persistence", "radius", "torque_scale"]
    r = sc.fit_hat_curves(scaled_torque, base, vary=vary)
    fig = r.plot()
    # the fitted torque curve is the predicted measurement tau / s: its plateau matches the
    # measured plateau (about 1 / 0.7 of the model's own)
    ax = next(a for a in fig.axes if a.get_ylabel() == "torque (pN nm)")
    curve = ax.get_lines()[-1].get_ydata()
    f0 = scaled_torque["force"].min()
    measured = scaled_torque.loc[scaled_torque["force"] == f0, "torque"]
    assert np.max(curve) == pytest.approx(np.percentile(measured, 95), rel=0.1)
    plt.close(fig)
    df = scaled_torque.copy()
    df.insert(0, "molecule", "m1")
    df.attrs["units"] = {"molecule": "", **scaled_torque.attrs["units"]}
    table = sc.fit_many(df, base, vary=vary)
    assert table["torque_scale"].iloc[0] == pytest.approx(r.parameters["torque_scale"].m,
                                                          rel=1e-6)
