"""Torque data: the torque columns of read_tweezers_csv and the joint extension + torque fit.

docs/theory/fitting.md#joint-torque-fit. References: the fit recovers the true
parameters of simulated data within its errors; the torque channel's noise
estimate equals the simulated noise; the errors of a fit with the true
torque_sigma equal those of the fit that estimates it; the analytic Jacobian
rows of the torque channel equal central differences; units of the torque
column do not change the estimates; more data (the torque channel) gives
smaller errors on the twist persistence.
"""

import numpy as np
import pytest
from fitting_helpers import FORCES, simulate, truth

import supercoil as sc
from supercoil.dna.fitting import RotationData, simulate_rotation_curves
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting.model import HatCurveModel
from supercoil.dna.interactions import get_interaction
from supercoil.dna.models import get_model
from supercoil.exceptions import DataError, FitError
from supercoil.tables import write_csv

TORQUE_NOISE = 2.0  # pN nm


@pytest.fixture(scope="module")
def torque_data(true_dna):
    return simulate(true_dna, seed=11, torque_noise=TORQUE_NOISE * sc.ureg.pN * sc.ureg.nm)


@pytest.fixture(scope="module")
def joint(torque_data, base):
    return sc.fit_hat_curves(torque_data, base)


@pytest.fixture(scope="module")
def extension_only(torque_data, base):
    return sc.fit_hat_curves(torque_data.drop(columns=["torque"]), base)


def test_read_tweezers_csv_reads_torque_columns(tmp_path, torque_data):
    df = torque_data.copy()
    df["torque_sigma"] = TORQUE_NOISE
    df.attrs["units"] = dict(df.attrs["units"], torque_sigma="pN nm")
    back = sc.read_tweezers_csv(write_csv(df, tmp_path / "t.csv"))
    assert back.attrs["units"]["torque"] == "pN nm"
    np.testing.assert_allclose(back["torque"], df["torque"], rtol=1e-10)
    rot = RotationData.from_frame(back)
    assert rot.torque_weighting == "sigma column"
    np.testing.assert_allclose(rot.torque, df["torque"] * 1e-21, rtol=1e-10)
    np.testing.assert_allclose(rot.torque_sigma, TORQUE_NOISE * 1e-21)


@pytest.mark.parametrize("header, row, match", [
    ("force [pN], turns, extension [um], torque [nm]", "0.5, 1, 0.6, 3",
     r"column 'torque': 'nm' has dimension \[length\], expected a torque"),
    ("force [pN], turns, extension [um], torque [pN nm], torque_sigma [pN nm]",
     "0.5, 1, 0.6, 3, 0", r"line 2, column 'torque_sigma': torque_sigma must be positive"),
    ("force [pN], turns, extension [um], torque [pN nm]", "0.5, 1, 0.6, abc",
     r"line 2, column 'torque': non-numeric value"),
    ("force [pN], turns, extension [um], torque_sigma [pN nm]", "0.5, 1, 0.6, 1",
     r"column 'torque_sigma': no 'torque' column"),
])
def test_bad_torque_columns_are_named(tmp_path, header, row, match):
    path = tmp_path / "bad.csv"
    path.write_text(f"{header}\n{row}\n")
    with pytest.raises(DataError, match=match):
        sc.read_tweezers_csv(path)


def test_simulated_torque_is_the_model_torque_plus_noise(true_dna):
    u = sc.ureg
    clean = simulate(true_dna, seed=3, noise=0 * u.nm, torque_noise=0 * u.pN * u.nm)
    m = get_model("li-zhao")
    inter = get_interaction("hard-core")
    pts = m.points(clean["turns"].to_numpy() - 0.4, clean["force"].to_numpy() * 1e-12,
                   true_dna.si, True, inter, None)
    np.testing.assert_allclose(clean["torque"], np.asarray(pts.torque) * 1e21, rtol=1e-12)
    # odd in N: the torque has the sign of the (offset-corrected) turns
    assert np.all(np.sign(clean["torque"]) == np.sign(clean["turns"] - 0.4))
    with pytest.raises(FitError, match="torque_noise"):
        simulate(true_dna, seed=3, torque_noise=-1 * u.pN * u.nm)


def test_joint_fit_recovers_parameters_and_each_channel_noise(joint, true_dna):
    for name, value in truth(true_dna).items():
        unit = "turn" if name == "turns_offset" else "nm"
        est, err = joint.parameters[name].m_as(unit), joint.stderr[name].m_as(unit)
        assert 0 < err and abs(est - value) < 4 * err, (name, est, value, err)
    ch = joint.channels
    assert set(ch) == {"extension", "torque"}
    # each channel's own noise estimate is its residual RMS and the simulated noise
    assert ch["torque"]["noise"].m_as("pN*nm") == pytest.approx(TORQUE_NOISE, rel=0.15)
    assert ch["extension"]["noise"].m_as("nm") == pytest.approx(5.0, rel=0.15)
    for c in ch.values():
        assert c["residual_rms"].m == pytest.approx(c["noise"].m, rel=1e-3)
        assert c["chi_square"] == pytest.approx(c["dof"], rel=2e-3)
    assert joint.torque_residuals.check("[force] * [length]")
    assert np.std(joint.torque_residuals.m_as("pN*nm")) == pytest.approx(TORQUE_NOISE, rel=0.15)
    assert joint.ndata == 2 * len(joint.data)
    report = joint.report()
    assert "torque channel" in report and "extension channel" in report
    row = joint.to_frame()
    assert row.attrs["units"]["torque_residual_rms"] == "pN*nm"


def test_joint_fit_has_smaller_errors_on_twist_persistence(joint, extension_only):
    e_joint = joint.stderr["twist_persistence"].m_as("nm")
    e_ext = extension_only.stderr["twist_persistence"].m_as("nm")
    print(f"stderr C_t: joint {e_joint:.4g} nm, extension only {e_ext:.4g} nm")
    assert e_joint < e_ext
    # the estimates agree within the extension-only errors
    assert abs(joint.parameters["twist_persistence"].m
               - extension_only.parameters["twist_persistence"].m) < 2 * e_ext


def test_torque_sigma_column_gives_absolute_errors(torque_data, base, joint):
    df = torque_data.copy()
    noise_t = joint.channels["torque"]["noise"].m_as("pN*nm")
    noise_z = joint.channels["extension"]["noise"].m_as("nm")
    df["torque_sigma"] = noise_t
    df["sigma"] = noise_z * 1e-3  # um, as the extension
    df.attrs["units"] = dict(df.attrs["units"], torque_sigma="pN nm", sigma="um")
    r = sc.fit_hat_curves(df, base)
    assert r.channels["torque"]["weighting"] == "sigma column"
    assert r.channels["torque"]["noise"] is None
    # the same weights as the estimated ones: the same estimates and errors
    for name in r.names:
        assert r.parameters[name].m == pytest.approx(joint.parameters[name].m, rel=1e-6)
        assert r.stderr[name].m == pytest.approx(joint.stderr[name].m, rel=1e-3)
    assert r.goodness["test"] == "chi-square"


def test_torque_unit_does_not_change_the_fit(torque_data, base, joint):
    df = torque_data.copy()
    df["torque"] = df["torque"] * 1e-21  # SI
    df.attrs["units"] = dict(df.attrs["units"], torque="N * m")
    r = sc.fit_hat_curves(df, base)
    for name in r.names:
        assert r.parameters[name].m == pytest.approx(joint.parameters[name].m, rel=1e-6)


def test_joint_jacobian_matches_central_differences(torque_data, base):
    spec = fitting.prepare(torque_data.iloc[::3].reset_index(drop=True), base,
                           start={"turns_offset": 0.3, "extension_offset": 20 * sc.ureg.nm})
    prob = HatCurveModel(spec.data, spec.params, spec.dna, spec.model, spec.interaction,
                         spec.thermal)
    u = spec.params.vector() * 1.01
    J = prob.jacobian(u)
    n = spec.data.n
    assert J.shape == (2 * n, len(u))
    for j, name in enumerate(prob.names):
        h = 1e-4 if "turns" in name else 1e-5
        up, um = u.copy(), u.copy()
        up[j] += h
        um[j] -= h
        ref = (prob.residual(up) - prob.residual(um)) / (2 * h)
        np.testing.assert_allclose(J[:, j], ref, rtol=0, atol=3e-3 * np.abs(ref).max(),
                                   err_msg=name)
    # the extension offset does not act on the torque rows
    jz = prob.names.index("extension_offset")
    assert np.all(J[n:, jz] == 0) and np.all(J[:n, jz] != 0)


def test_plot_shows_both_channels(joint):
    import matplotlib.pyplot as plt

    fig = joint.plot()
    labels = {ax.get_ylabel() for ax in fig.axes}
    assert {"torque (pN nm)", "residual (pN nm)", "residual (nm)"} <= labels
    assert len(fig.axes) == 4 * len(FORCES)
    plt.close(fig)


def test_fit_many_carries_the_torque_channel(true_dna, base):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=40,
                                  molecules=2, seed=4, torque_noise=TORQUE_NOISE * u.pN * u.nm)
    table = sc.fit_many(df, base)
    assert table["success"].all()
    single = sc.fit_hat_curves(df[df["molecule"] == "m2"].reset_index(drop=True), base)
    assert table["twist_persistence"].iloc[1] == pytest.approx(
        single.parameters["twist_persistence"].m, rel=1e-6)


@pytest.mark.filterwarnings("ignore:model marko2007:supercoil.exceptions.FitWarning",
                            "ignore:model marko2007:supercoil.exceptions.ValidityWarning")
def test_compare_models_on_torque_data_uses_fixed_scales(torque_data, base):
    """With estimated channel noise every model's chi-square is N: the criterion must use
    the fixed unit scales (1 nm, 1 pN nm), so it still ranks the models."""
    from supercoil.dna.fitting import compare_models

    table = compare_models(torque_data, base, models=["li-zhao", "marko2007"]).table
    assert table["success"].all()
    rows = {m: r for m, r in zip(table["model"], table.to_dict("records"), strict=True)}
    for m in ("li-zhao", "marko2007"):
        r = rows[m]
        assert r["chi_square"] == pytest.approx(r["ndata"], rel=1e-2)  # estimated weights
    # the AIC difference is not the trivial 2 * (difference of parameter counts)
    d_aic = rows["marko2007"]["aic"] - rows["li-zhao"]["aic"]
    assert abs(d_aic - 2 * (rows["marko2007"]["nparams"] - rows["li-zhao"]["nparams"])) > 1
    # the data were made by li-zhao: it wins
    assert rows["li-zhao"]["delta_aic"] == 0 and d_aic > 0


def test_joint_errors_match_the_scatter_over_replicates(true_dna, base):
    """The joint fit's errors (weights from the estimated channel noise) are the scatter of
    its estimates: pulls (estimate - truth) / stderr over 40 noise replicates have sd 1
    (sampling sd of the sd about 0.11: band 0.67-1.33) and mean 0 (band +-0.5)."""
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=60,
                                  molecules=40, turns_offset=0.4, extension_offset=30 * u.nm,
                                  noise=5 * u.nm, torque_noise=TORQUE_NOISE * u.pN * u.nm,
                                  seed=2026)
    table = sc.fit_many(df, base, progress=False)
    assert table["success"].all()
    for name, value in truth(true_dna).items():
        pull = (table[name] - value) / table[f"{name}_stderr"]
        assert 0.67 < pull.std(ddof=1) < 1.33, (name, pull.std(ddof=1))
        assert abs(pull.mean()) < 0.5, (name, pull.mean())
    np.testing.assert_allclose(table["torque_residual_rms"], TORQUE_NOISE, rtol=0.2)
    assert table.attrs["units"]["torque_residual_rms"] == "pN*nm"
