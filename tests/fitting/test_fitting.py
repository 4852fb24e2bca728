"""Hat-curve fits: parameter recovery within the reported errors, coverage, failures, fit_many."""

from concurrent.futures import ProcessPoolExecutor, ThreadPoolExecutor

import numpy as np
import pandas as pd
import pytest

import supercoil as sc
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting.fit import simulate_rotation_curves
from supercoil.exceptions import (
    BoundWarning,
    DataError,
    FitError,
    FitWarning,
    NoEquilibriumError,
    ValidityWarning,
)
from supercoil.units import as_turns

FORCES = (0.3, 0.5, 0.7)  # pN: below the denaturation force, so both signs of N are valid
TRUE_N0 = 0.4  # turns
TRUE_Z0 = 30.0  # nm
NOISE = 5.0  # nm


@pytest.fixture(scope="module")
def base():
    return sc.load_parameters("dna")


@pytest.fixture(scope="module")
def true_dna(base):
    u = sc.ureg
    # not the defaults (86 nm, 1.75 nm): the fit has to move
    return base.replace(twist_persistence=95 * u.nm, radius=2.0 * u.nm)


def simulate(dna, seed, **kw):
    u = sc.ureg
    kw.setdefault("noise", NOISE * u.nm)
    kw.setdefault("turns_offset", TRUE_N0)
    kw.setdefault("extension_offset", TRUE_Z0 * u.nm)
    return simulate_rotation_curves(dna, np.array(FORCES) * u.pN, seed=seed, **kw)


@pytest.fixture(scope="module")
def data(true_dna):
    return simulate(true_dna, seed=11)


@pytest.fixture(scope="module")
def result(data, base):
    return sc.fit_hat_curves(data, base, vary=["twist_persistence", "radius"])


def truth(true_dna):
    return {"twist_persistence": true_dna.twist_persistence.m_as("nm"),
            "radius": true_dna.radius.m_as("nm"),
            "turns_offset": TRUE_N0, "extension_offset": TRUE_Z0}


# ---- parameter recovery --------------------------------------------------------------------


def test_recovers_non_default_parameters_within_reported_errors(result, true_dna, base):
    assert set(result.parameters) == {"twist_persistence", "radius", "turns_offset",
                                      "extension_offset"}
    for name, value in truth(true_dna).items():
        est, err = result.parameters[name], result.stderr[name]
        unit = "turn" if name == "turns_offset" else "nm"
        est, err = est.m_as(unit), err.m_as(unit)
        assert 0 < err, name
        assert abs(est - value) < 4 * err, (name, est, value, err)
    # the start (the defaults) is far outside the errors: the fit really moved
    assert abs(base.twist_persistence.m_as("nm") - 95) > 10 * result.stderr[
        "twist_persistence"].m_as("nm")
    # unit weights: the scatter estimates the noise level
    assert result.weighting == "unit"
    assert np.sqrt(result.reduced_chi_square) == pytest.approx(NOISE, rel=0.15)
    assert result.residuals.check("[length]")
    assert np.std(result.residuals.m_as("nm")) == pytest.approx(NOISE, rel=0.15)
    assert result.dna.twist_persistence.m_as("nm") == pytest.approx(
        result.parameters["twist_persistence"].m_as("nm"))
    assert result.dna.bending_persistence == base.bending_persistence


def test_sigma_column_gives_absolute_errors(true_dna, base, result):
    df = simulate(true_dna, seed=11, sigma_column=True)
    r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"])
    assert r.weighting == "sigma column"
    assert r.reduced_chi_square == pytest.approx(1.0, abs=0.2)
    for name in r.parameters:
        assert r.parameters[name].m == pytest.approx(result.parameters[name].m, rel=1e-6)
        # absolute vs rescaled errors differ by sqrt(reduced chi-square) only
        assert r.stderr[name].m == pytest.approx(
            result.stderr[name].m / np.sqrt(result.reduced_chi_square) * NOISE, rel=1e-4)
    # the sigma argument overrides the column
    r2 = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"],
                           sigma=2 * NOISE * sc.ureg.nm)
    assert r2.weighting == "sigma argument"
    assert r2.stderr["radius"].m == pytest.approx(2 * r.stderr["radius"].m, rel=1e-4)


def test_global_fit_of_two_molecules_with_own_offsets(base):
    u = sc.ureg
    true = base.replace(length=800 * u.nm, bending_persistence=52 * u.nm)
    df = simulate_rotation_curves(true, np.array(FORCES) * u.pN, points_per_force=60,
                                  noise=4 * u.nm, molecules=["x", "y"], turns_offset=[0.3, -0.6],
                                  extension_offset=[20, -10] * u.nm, seed=5)
    r = sc.fit_hat_curves(df, base, vary=["length", "bending_persistence"])
    expected = {"length": 800, "bending_persistence": 52, "turns_offset[x]": 0.3,
                "turns_offset[y]": -0.6, "extension_offset[x]": 20, "extension_offset[y]": -10}
    assert set(r.parameters) == set(expected)
    for name, value in expected.items():
        assert abs(r.parameters[name].m - value) < 4 * r.stderr[name].m, name
    assert r.parameters["turns_offset[x]"].check("[]")


def test_small_coverage_run(true_dna, base):
    """1-sigma intervals cover the truth in ~68 % of noise replicates.

    60 replicates x 4 parameters. The replicates are independent but the 4
    parameters of one replicate are not, so the binomial band uses n = 60:
    sd = sqrt(0.683 * 0.317 / 60) = 0.060, band 0.683 +- 3.2 sd = [0.49, 0.87].
    Scaling mistakes fail it: errors 2x too large cover 95 %, 2x too small 38 %.
    """
    rng = np.random.default_rng(2024)
    true = truth(true_dna)
    hits = []
    for _ in range(60):
        df = simulate(true_dna, seed=rng, points_per_force=50)
        r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"])
        hits.append([abs(r.parameters[k].m - v) <= r.stderr[k].m for k, v in true.items()])
    fraction = np.mean(hits)
    assert 0.49 <= fraction <= 0.87, fraction


# ---- units ----------------------------------------------------------------------------------


def test_unit_invariance(data, base, result):
    nm = data.copy()
    nm["extension"] = data["extension"] * 1000.0
    nm["force"] = data["force"] * 1000.0
    nm["turns"] = data["turns"] * 2 * np.pi
    nm.attrs = {"units": {"force": "fN", "turns": "rad", "extension": "nm"}}
    r = sc.fit_hat_curves(nm, base, vary=["twist_persistence", "radius"])
    for name in result.parameters:
        assert r.parameters[name].m == pytest.approx(result.parameters[name].m, rel=1e-7)
        assert r.stderr[name].m == pytest.approx(result.stderr[name].m, rel=1e-5)


def test_wrong_dimension_in_attrs_names_the_column(data, base):
    bad = data.copy()
    bad.attrs = {"units": dict(data.attrs["units"], extension="pN")}
    with pytest.raises(DataError, match="column 'extension'"):
        sc.fit_hat_curves(bad, base)
    nan = data.copy()
    nan.loc[7, "turns"] = np.nan
    with pytest.raises(DataError, match="row 7, column 'turns'"):
        sc.fit_hat_curves(nan, base)


# ---- result object -------------------------------------------------------------------------


def test_result_tables_report_and_plot(result, tmp_path):
    import matplotlib.figure

    names = list(result.parameters)
    cov, corr = result.covariance, result.correlation
    assert list(cov.index) == names and list(cov.columns) == names
    np.testing.assert_allclose(cov.to_numpy(), cov.to_numpy().T, rtol=1e-12, atol=0)
    np.testing.assert_allclose(np.diag(cov), [result.stderr[k].m ** 2 for k in names], rtol=1e-10)
    np.testing.assert_allclose(np.diag(corr), 1.0)
    assert np.all(np.abs(corr.to_numpy()) <= 1 + 1e-12)
    assert cov.attrs["units"]["radius"] == "nm" and cov.attrs["units"]["turns_offset"] == "turn"

    text = result.report()
    for token in ("reduced chi-square", "twist_persistence", "radius", "turns_offset",
                  "extension_offset", "nm", "turn", "bending_persistence", "[[Fixed]]",
                  "unit weights; covariance scaled by the reduced chi-square"):
        assert token in text, token
    assert "±" in repr(result)

    frame = result.to_frame()
    assert len(frame) == 1
    assert frame.attrs["units"]["twist_persistence"] == "nm"
    assert frame.attrs["units"]["twist_persistence_stderr"] == "nm"
    assert frame["radius"].iloc[0] == pytest.approx(result.parameters["radius"].m)
    back = sc.read_csv(sc.write_csv(frame, tmp_path / "p.csv"))
    assert back["radius"].iloc[0] == pytest.approx(result.parameters["radius"].m, rel=1e-10)

    pts = result.points_frame()
    assert len(pts) == result.ndata
    np.testing.assert_allclose(pts["residual"], result.residuals.m_as("nm"))
    np.testing.assert_allclose(pts["best_fit"] + pts["residual"], pts["extension"], rtol=1e-12)

    fig = result.plot()
    assert isinstance(fig, matplotlib.figure.Figure)
    assert len(fig.axes) == 2 * len(FORCES)
    fig.savefig(tmp_path / "fit.png")
    import matplotlib.pyplot as plt

    plt.close(fig)


# ---- options and failures ------------------------------------------------------------------


def test_switching_offsets_off(true_dna, base):
    u = sc.ureg
    df = simulate(true_dna, seed=3, turns_offset=0.0, extension_offset=0 * u.nm,
                  points_per_force=60)
    r = sc.fit_hat_curves(df, base, vary=["twist_persistence"], fixed={"radius": 2.0 * u.nm},
                          fit_turns_offset=False, fit_extension_offset=False)
    assert set(r.parameters) == {"twist_persistence"}
    assert r.fixed["turns_offset"].m == 0 and r.fixed["extension_offset"].m == 0
    assert abs(r.parameters["twist_persistence"].m - 95) < 4 * r.stderr["twist_persistence"].m
    # a fixed offset value is used, not fitted
    df2 = simulate(true_dna, seed=3, turns_offset=0.4, extension_offset=0 * u.nm,
                   points_per_force=60)
    r2 = sc.fit_hat_curves(df2, base, vary=["twist_persistence"],
                           fixed={"turns_offset": 0.4, "radius": 2.0 * u.nm})
    assert "turns_offset" not in r2.parameters and "extension_offset" in r2.parameters
    assert r2.parameters["twist_persistence"].m == pytest.approx(
        r.parameters["twist_persistence"].m, abs=4 * r.stderr["twist_persistence"].m)


def test_bounds_excluding_the_start_fail_before_fitting(data, base):
    u = sc.ureg
    with pytest.raises(FitError, match=r"start value of radius = 1\.75 nm lies outside"):
        sc.fit_hat_curves(data, base, bounds={"radius": (2.5 * u.nm, 3 * u.nm)})
    with pytest.raises(FitError, match="turns_offset"):
        sc.fit_hat_curves(data, base, bounds={"turns_offset": (1, 2)}, start={"turns_offset": 0})
    with pytest.raises(FitError, match="lower bound"):
        sc.fit_hat_curves(data, base, bounds={"radius": (3 * u.nm, 2 * u.nm)})
    with pytest.raises(FitError, match="not a free parameter"):
        sc.fit_hat_curves(data, base, vary=["radius"], bounds={"length": (1 * u.nm, None)})
    with pytest.raises(FitError, match=r"radius.*length"):
        sc.fit_hat_curves(data, base, bounds={"radius": (1 * u.pN, 3 * u.nm)})


def test_estimate_on_a_bound_warns(data, base):
    u = sc.ureg
    with pytest.warns(BoundWarning, match="radius .* sits on its upper bound"):
        r = sc.fit_hat_curves(data, base, bounds={"radius": (1 * u.nm, 1.9 * u.nm)})
    assert r.parameters["radius"].m == pytest.approx(1.9, rel=1e-6)
    assert "sits on its upper bound" in r.report()


def test_bad_parameter_names(data, base):
    u = sc.ureg
    with pytest.raises(FitError, match="cannot vary 'temperature'"):
        sc.fit_hat_curves(data, base, vary=["temperature"])
    with pytest.raises(FitError, match="both in vary and in fixed"):
        sc.fit_hat_curves(data, base, vary=["radius"], fixed={"radius": 2 * u.nm})
    with pytest.raises(FitError, match="unknown parameter 'pitch'"):
        sc.fit_hat_curves(data, base, fixed={"pitch": 2 * u.nm})
    with pytest.raises(FitError, match="nothing to fit"):
        sc.fit_hat_curves(data, base, vary=[], fit_turns_offset=False,
                          fit_extension_offset=False)


def test_force_without_equilibrium_fails_before_fitting(data, base):
    """Above ~1e5 pN the superhelix would be thinner than r0/2: no plectoneme equilibrium."""
    bad = data.copy()
    bad.loc[bad["force"] == 0.7, "force"] = 2e5
    calls = []
    orig = fitting.least_squares

    def spy(*a, **k):
        calls.append(1)
        return orig(*a, **k)

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(fitting, "least_squares", spy)
        with pytest.raises(FitError, match=r"cannot start the fit.*no plectoneme equilibrium "
                           r"at force 200000 pN") as exc:
            sc.fit_hat_curves(bad, base)
    assert not calls
    assert isinstance(exc.value.__cause__, NoEquilibriumError)
    # a force too low for the Moroz-Nelson tail: also named before fitting
    low = data.copy()
    low.loc[low["force"] == 0.3, "force"] = 0.01
    with pytest.raises(FitError, match=r"0\.01 pN"):
        sc.fit_hat_curves(low, base)


def test_kernel_failure_during_the_fit_is_step_controlled(data, base, result, monkeypatch):
    """A trial step where the kernel raises is rejected (smaller trust region), not fatal."""
    orig = fitting._hat_points
    calls = [0]

    def flaky(*a, **k):
        calls[0] += 1
        if calls[0] == 6:  # the first trial step after the start and the first Jacobian
            raise NoEquilibriumError("no plectoneme equilibrium (injected)")
        return orig(*a, **k)

    monkeypatch.setattr(fitting, "_hat_points", flaky)
    r = sc.fit_hat_curves(data, base, vary=["twist_persistence", "radius"])
    assert r._core["kernel_failures"] == 1
    for name in result.parameters:
        assert r.parameters[name].m == pytest.approx(result.parameters[name].m,
                                                     abs=1e-3 * result.stderr[name].m)


def test_no_convergence_is_a_fit_error(data, base):
    with pytest.raises(FitError, match=r"did not converge.*twist_persistence ="):
        sc.fit_hat_curves(data, base, max_nfev=1)


def test_singular_jacobian_warns_and_uses_pseudo_inverse(base):
    """Stretched-phase points only: the extension does not depend on r0 there."""
    u = sc.ureg
    # as_turns: buckling_turns may be dimensionless or in turn
    nb = as_turns(sc.buckling_turns(base, 0.5 * u.pN))
    df = simulate_rotation_curves(base, [0.5] * u.pN, turns=np.linspace(-0.6, 0.6, 40) * nb,
                                  noise=2 * u.nm, seed=1)
    with pytest.warns(FitWarning, match="singular.*do not determine radius"):
        r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"],
                              fit_turns_offset=False)
    # the determined parameters keep the pseudo-inverse errors; r0 is not determined
    assert np.isfinite(r.stderr["twist_persistence"].m)
    assert r.stderr["twist_persistence"].m > 0
    assert r.undetermined == ["radius"]
    assert np.isinf(r.stderr["radius"].m)


def test_undetermined_parameter_gets_infinite_stderr(base):
    """Audit B1: one force, stretched phase only (|N| <= 3 at 1 pN), only r0 varied.

    Before the fix the pseudo-inverse gave r0 a standard error of exactly 0 nm.
    """
    u = sc.ureg
    df = simulate_rotation_curves(base, [1.0] * u.pN, turns=np.linspace(-3, 3, 40),
                                  noise=2 * u.nm, seed=1)
    with pytest.warns(ValidityWarning, match="denatures"), \
            pytest.warns(FitWarning, match="do not determine radius; its standard error is inf"):
        r = sc.fit_hat_curves(df, base, vary=["radius"], fit_turns_offset=False)
    assert not np.isfinite(r.stderr["radius"].m)
    assert r.undetermined == ["radius"]
    # the extension offset is determined (the mean extension) and keeps a finite error
    assert 0 < r.stderr["extension_offset"].m < 2
    assert np.isnan(r.covariance.loc["radius"]).all()
    assert np.isnan(r.covariance["radius"]).all()
    assert np.isfinite(r.covariance.loc["extension_offset", "extension_offset"])
    text = r.report()
    radius_row = next(line for line in text.splitlines() if line.strip().startswith("radius"))
    assert "not determined" in radius_row
    assert "not determined" in repr(r)
    frame = r.to_frame()
    assert np.isinf(frame["radius_stderr"].iloc[0]) and not frame["determined"].iloc[0]


def _flat_molecule(base, forces, points, seed):
    """A nicked molecule: the extension does not change with the turns."""
    u = sc.ureg
    flat = simulate_rotation_curves(base, np.array(forces) * u.pN, turns=np.zeros(points),
                                    noise=5 * u.nm, seed=seed)
    return flat["extension"].to_numpy()


def test_fit_many_marks_a_flat_molecule_as_not_determined(true_dna, base):
    """Audit B1: a flat curve in fit_many had success True and stderr ~1e-11."""
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=40,
                                  noise=5 * u.nm, molecules=2, seed=1)
    flat = (df["molecule"] == "m2").to_numpy()
    df.loc[flat, "extension"] = _flat_molecule(true_dna, FORCES, 40, seed=3)
    with pytest.warns(FitWarning, match="molecule m2: .*do not determine radius"):
        table = sc.fit_many(df, base, vary=["twist_persistence", "radius"])
    assert list(table["success"]) == [True, True]
    assert list(table["determined"]) == [True, False]
    assert np.isfinite(table.loc[0, "radius_stderr"]) and table.loc[0, "radius_stderr"] > 0
    assert not np.isfinite(table.loc[1, "radius_stderr"])
    assert "do not determine radius" in table.loc[1, "warnings"]


def test_fit_many_reports_the_points_of_a_molecule_rejected_in_preparation(true_dna, base):
    """Audit S3: 3 points for 4 free parameters was reported with ndata = 0."""
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=30,
                                  molecules=["a", "b"], seed=2)
    keep = (df["molecule"] == "a").to_numpy().copy()
    keep[np.flatnonzero(df["molecule"] == "b")[:3]] = True
    small = df.loc[keep].reset_index(drop=True)
    small.attrs = dict(df.attrs)
    table = sc.fit_many(small, base, vary=["twist_persistence", "radius"])
    assert list(table["success"]) == [True, False]
    assert "3 data points cannot determine 4 free parameters" in table.loc[1, "error"]
    assert list(table["ndata"]) == [90, 3]
    assert not table.loc[1, "determined"]


def test_chi_square_is_in_the_units_of_the_weighting(result, true_dna, base):
    """Audit B2: chi_square was in m^2 with unit weights while reduced_chi_square used nm^2."""
    resid = result.residuals.m_as("nm")
    assert result.chi_square == pytest.approx(np.sum(resid**2), rel=1e-9)  # sigma = 1 nm
    assert result.chi_square / result.nfree == pytest.approx(result.reduced_chi_square,
                                                             rel=1e-12)
    assert result.to_frame()["chi_square"].iloc[0] == pytest.approx(result.chi_square)
    assert result.residual_rms.m_as("nm") == pytest.approx(
        np.sqrt(result.reduced_chi_square), rel=1e-9)
    df = simulate(true_dna, seed=11, sigma_column=True)
    r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"])
    assert r.chi_square == pytest.approx(np.sum((r.residuals.m_as("nm") / NOISE) ** 2),
                                         rel=1e-9)
    assert r.chi_square / r.nfree == pytest.approx(r.reduced_chi_square, rel=1e-12)


def test_unit_weights_show_the_noise_estimate_not_a_chi_square(result, true_dna, base):
    """Audit P3: with unit weights the headline is the residual RMS in nm."""
    import matplotlib.pyplot as plt

    noise = np.sqrt(result.reduced_chi_square)
    fig = result.plot()
    title = fig._suptitle.get_text()
    plt.close(fig)
    assert f"noise estimate (residual RMS) {noise:.3g} nm" in title
    assert "chi-square" not in title
    text = result.report()
    stats = text.split("[[Fit statistics]]")[1].split("[[Parameters]]")[0]
    first = next(line for line in stats.splitlines() if "chi" in line or "noise" in line)
    assert first.strip().startswith(f"noise estimate     = {noise:.4g} nm")
    assert "nm^2" in stats
    # with per-point sigma the reduced chi-square is a goodness of fit and stays in the title
    r = sc.fit_hat_curves(simulate(true_dna, seed=11, sigma_column=True), base,
                          vary=["twist_persistence", "radius"])
    fig = r.plot()
    title = fig._suptitle.get_text()
    plt.close(fig)
    assert f"reduced chi-square {r.reduced_chi_square:.3g}" in title


def test_messages_print_plain_numbers(data, base):
    """Audit P5: no np.float64(...) or <Quantity(...)> reprs in messages."""
    u = sc.ureg
    with pytest.raises(FitError, match=r"fixed radius must be finite and positive, got -1 nm$"):
        sc.fit_hat_curves(data, base, vary=["twist_persistence"], fixed={"radius": -1 * u.nm})
    with pytest.raises(FitError, match=r"lower bound 2\.0 is not below 1\.0$"):
        sc.fit_hat_curves(data, base, bounds={"turns_offset": (np.float64(2), np.float64(1))})


@pytest.mark.parametrize("unit", ["", "dimensionless", "turn"])
def test_turns_as_plain_numbers_dimensionless_or_turn(data, base, result, unit):
    """Turns given without unit, as dimensionless or in turn all count turns."""
    df = data.copy()
    df.attrs = {"units": dict(data.attrs["units"], turns=unit)}
    r = sc.fit_hat_curves(df, base, vary=["twist_persistence", "radius"])
    for name in result.parameters:
        assert r.parameters[name].m == pytest.approx(result.parameters[name].m, rel=1e-9)
    assert r.parameters["turns_offset"].m == pytest.approx(TRUE_N0, abs=0.1)


def test_short_tail_data_warn(base):
    u = sc.ureg
    df = simulate_rotation_curves(base, [0.5] * u.pN, turns=np.linspace(-22, 22, 89),
                                  noise=3 * u.nm, seed=2)
    with pytest.warns(ValidityWarning, match="not valid"):
        sc.fit_hat_curves(df, base, vary=["twist_persistence"])


# ---- many molecules -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def many(true_dna):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=50,
                                  molecules=4, turns_offset=[0.2, -0.3, 0.5, 0.0],
                                  extension_offset=[10, 0, -5, 20] * u.nm, seed=8)
    # molecule m3 was measured at a force without plectoneme equilibrium
    df.loc[(df["molecule"] == "m3") & (df["force"] == 0.7), "force"] = 2e5
    return df


def _compare(a, b):
    cols = [c for c in a.columns if c not in ("warnings",)]
    pd.testing.assert_frame_equal(a[cols], b[cols], rtol=1e-9)


def test_fit_many_reports_failures_per_molecule(many, base):
    seen = []
    table = sc.fit_many(many, base, vary=["twist_persistence", "radius"],
                        progress=lambda done, total, mol: seen.append((done, total, mol)))
    assert list(table["molecule"]) == ["m1", "m2", "m3", "m4"]
    assert list(table["success"]) == [True, True, False, True]
    assert "no plectoneme equilibrium" in table.loc[2, "error"]
    assert np.isnan(table.loc[2, "twist_persistence"])
    assert (table.loc[[0, 1, 3], "error"] == "").all()
    assert [s[0] for s in seen] == [1, 2, 3, 4] and {s[1] for s in seen} == {4}
    assert {s[2] for s in seen} == {"m1", "m2", "m3", "m4"}
    assert table.attrs["units"]["radius_stderr"] == "nm"
    assert table.attrs["units"]["turns_offset"] == "turn"
    # each row equals the single-molecule fit
    for i, lab in ((0, "m1"), (3, "m4")):
        sub = many[many["molecule"] == lab].drop(columns="molecule").reset_index(drop=True)
        sub.attrs = dict(many.attrs)
        r = sc.fit_hat_curves(sub, base, vary=["twist_persistence", "radius"])
        for name in r.parameters:
            assert table.loc[i, name] == pytest.approx(r.parameters[name].m, rel=1e-9)
            assert table.loc[i, f"{name}_stderr"] == pytest.approx(r.stderr[name].m, rel=1e-9)
        assert abs(table.loc[i, "twist_persistence"] - 95) < 4 * table.loc[
            i, "twist_persistence_stderr"]
    assert abs(table.loc[1, "turns_offset"] + 0.3) < 4 * table.loc[1, "turns_offset_stderr"]


@pytest.mark.parametrize("pool", [ThreadPoolExecutor, ProcessPoolExecutor])
def test_fit_many_in_parallel_equals_serial(many, base, pool):
    serial = sc.fit_many(many, base, vary=["twist_persistence", "radius"])
    seen = []
    with pool(max_workers=2) as ex:
        par = sc.fit_many(many, base, vary=["twist_persistence", "radius"], executor=ex,
                          progress=lambda d, t, m: seen.append(d))
    _compare(serial, par)
    assert sorted(seen) == [1, 2, 3, 4]


def test_fit_many_rejects_common_problems_up_front(many, base):
    with pytest.raises(FitError, match="cannot vary"):
        sc.fit_many(many, base, vary=["pitch"])
    with pytest.raises(FitError, match="fits each molecule alone"):
        sc.fit_many(many, base, fixed={"turns_offset[m1]": 0})


def test_fit_names_file_lines_of_a_read_table(data, base, tmp_path):
    path = sc.write_csv(data, tmp_path / "d.csv")
    df = sc.read_tweezers_csv(path)
    df.loc[4, "turns"] = np.nan  # edited after reading
    line = df.attrs["lines"][4]
    with pytest.raises(DataError, match=rf"line {line}, column 'turns'"):
        sc.fit_hat_curves(df, base)


class _LazyFuture:
    def __init__(self, fn, args):
        self.fn, self.args = fn, args

    def result(self):
        return self.fn(*self.args)


class _NonStandardExecutor:
    """Like a dask Client: submit() returns futures that are not concurrent.futures.Future."""

    def submit(self, fn, *args):
        return _LazyFuture(fn, args)


def test_fit_many_with_a_client_like_executor(many, base):
    serial = sc.fit_many(many, base, vary=["twist_persistence", "radius"])
    other = sc.fit_many(many, base, vary=["twist_persistence", "radius"],
                        executor=_NonStandardExecutor())
    _compare(serial, other)
