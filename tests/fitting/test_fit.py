"""Hat-curve fits: parameter recovery within the reported errors, units, options, failures."""


import numpy as np
import pytest
from fitting_helpers import FORCES, NOISE, TRUE_N0, simulate, truth

import supercoil as sc
from supercoil.dna.fitting import fit as fitting
from supercoil.dna.fitting import model as fit_model
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.exceptions import (
    BoundWarning,
    DataError,
    FitError,
    FitWarning,
    NoEquilibriumError,
    ValidityWarning,
)
from supercoil.tables import row_lines


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
    assert result.residual_rms.m_as("nm") == pytest.approx(NOISE, rel=0.15)
    assert result.reduced_chi_square == 1.0  # the noise estimate is the sigma
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
            result.stderr[name].m / result.residual_rms.m_as("nm") * NOISE, rel=1e-4)
    # the sigma argument overrides the column; sigmas twice the noise fail the chi-square test
    with pytest.warns(FitWarning, match=r"chi-square .* smaller than the stated sigmas imply"):
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
    # pinned below the true 2 nm, the model misses the shape: the runs test says so too
    with pytest.warns(BoundWarning, match="radius .* sits on its upper bound"), \
            pytest.warns(FitWarning, match="runs test"):
        r = sc.fit_hat_curves(data, base, bounds={"radius": (1 * u.nm, 1.9 * u.nm)})
    assert r.parameters["radius"].m == pytest.approx(1.9, rel=1e-6)
    assert "sits on its upper bound" in r.report()


def test_bad_parameter_names(data, base):
    u = sc.ureg
    with pytest.raises(FitError, match="cannot vary 'temperature'"):
        sc.fit_hat_curves(data, base, vary=["temperature"])
    with pytest.raises(FitError, match="is both varied and fixed"):
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
    orig = fit_model.evaluate
    calls = [0]

    def flaky(*a, **k):
        calls[0] += 1
        # calls: 1 start, 2-3 Jacobian columns of C_t and r0, 4 dz/dN; 5 the first trial step
        if calls[0] == 5:
            raise NoEquilibriumError("no plectoneme equilibrium (injected)")
        return orig(*a, **k)

    monkeypatch.setattr(fit_model, "evaluate", flaky)
    r = sc.fit_hat_curves(data, base, vary=["twist_persistence", "radius"])
    assert r.kernel_failures == 1
    for name in result.parameters:
        assert r.parameters[name].m == pytest.approx(result.parameters[name].m,
                                                     abs=1e-3 * result.stderr[name].m)


def test_no_convergence_is_a_fit_error(data, base):
    with pytest.raises(FitError, match=r"did not converge.*twist_persistence ="):
        sc.fit_hat_curves(data, base, max_nfev=1)


def test_messages_print_plain_numbers(data, base):
    """Audit P5: no np.float64(...) or <Quantity(...)> reprs in messages."""
    u = sc.ureg
    with pytest.raises(FitError, match=r"fixed value of radius must be finite and positive, "
                                       r"got -1 nm$"):
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


def test_fit_names_file_lines_of_a_read_table(data, base, tmp_path):
    path = sc.write_csv(data, tmp_path / "d.csv")
    df = sc.read_tweezers_csv(path)
    df.loc[4, "turns"] = np.nan  # edited after reading
    line = row_lines(df)[4]
    with pytest.raises(DataError, match=rf"line {line}, column 'turns'"):
        sc.fit_hat_curves(df, base)
