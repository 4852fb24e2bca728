"""``supercoil fit``: report, parameter CSV and figure; per-molecule batches with progress."""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main
from supercoil.dna.fitting import simulate_rotation_curves


@pytest.fixture(scope="module")
def true_dna():
    u = sc.ureg
    return sc.load_parameters("dna").replace(twist_persistence=95 * u.nm, radius=2.0 * u.nm)


def _write(df, path):
    return sc.write_csv(df, path)


def test_fit_command_single_molecule(tmp_path, capsys, true_dna):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, [0.3, 0.5, 0.7] * u.pN, points_per_force=60,
                                  turns_offset=0.4, extension_offset=30 * u.nm, seed=4)
    path = _write(df, tmp_path / "data.csv")
    out = tmp_path / "out"
    rc = main(["fit", str(path), "--vary", "twist_persistence", "radius", "--out", str(out)])
    assert rc == 0
    report = (out / "fit_report.txt").read_text()
    assert "twist_persistence" in report and "noise estimate" in report
    assert "reduced chi-square" not in report  # unit weights: no chi-square
    assert (out / "fit.png").stat().st_size > 0
    params = sc.read_csv(out / "fit_parameters.csv")
    assert params.attrs["units"]["twist_persistence"] == "nm"
    # the same numbers as the library call
    ref = sc.fit_hat_curves(sc.read_tweezers_csv(path), sc.load_parameters("dna"),
                            vary=["twist_persistence", "radius"])
    assert params["twist_persistence"].iloc[0] == pytest.approx(
        ref.parameters["twist_persistence"].m, rel=1e-9)
    pts = sc.read_csv(out / "fit_points.csv")
    assert len(pts) == len(df)
    assert "[[Parameters]]" in capsys.readouterr().out


def test_fit_command_options(tmp_path, true_dna):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, [0.5] * u.pN, points_per_force=60, seed=4)
    path = _write(df, tmp_path / "data.csv")
    out = tmp_path / "o"
    rc = main(["fit", str(path), "--vary", "twist_persistence", "--fix", "radius=2nm",
               "--no-turns-offset", "--bound", "twist_persistence=50nm:150nm",
               "--sigma", "5nm", "--out", str(out), "--no-plot"])
    assert rc == 0
    params = sc.read_csv(out / "fit_parameters.csv")
    assert "turns_offset" not in params.columns and "extension_offset" in params.columns
    assert params["weighting"].iloc[0] == "sigma argument"
    assert not (out / "fit.png").exists()


def test_fit_command_many_molecules_progress_and_failures(tmp_path, capsys, true_dna):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, [0.3, 0.5, 0.7] * u.pN, points_per_force=40,
                                  molecules=3, turns_offset=[0.1, 0.2, -0.2], seed=9)
    df.loc[(df["molecule"] == "m2") & (df["force"] == 0.5), "force"] = 3e5
    path = _write(df, tmp_path / "many.csv")
    out = tmp_path / "m"
    rc = main(["fit", str(path), "--out", str(out), "--jobs", "2"])
    assert rc == 1  # one molecule failed: reported, the others fitted
    captured = capsys.readouterr()
    # not a terminal, so one line per molecule (no carriage returns piling up)
    done = [line for line in captured.err.splitlines() if " done (" in line]
    assert sorted(line[-4:-1] for line in done) == ["1/3", "2/3", "3/3"]
    assert all(line.startswith("supercoil fit: molecule m") for line in done)
    assert "\r" not in captured.err
    table = sc.read_csv(out / "fit_molecules.csv")
    assert list(table["success"]) == [True, False, True]
    assert "no plectoneme equilibrium" in table["error"].iloc[1]
    assert np.isfinite(table["radius"].iloc[[0, 2]]).all()
    report = (out / "fit_report.txt").read_text()
    assert "FAILED" in report
    # unit weights, so the noise estimate in nm, not a "red.chi2" of ~25 nm^2
    assert "noise [nm]" in report and "red.chi2" not in report
    row = next(line for line in report.splitlines() if line.strip().startswith("m1 "))
    assert float(row.split()[1]) == pytest.approx(table["residual_rms"].iloc[0], rel=1e-3)
    assert table.attrs["units"]["residual_rms"] == "nm"
    assert 3 < table["residual_rms"].iloc[0] < 8  # the noise estimate, nm (default 5 nm noise)
    assert table["reduced_chi_square"].iloc[0] == pytest.approx(1.0)  # dimensionless
    assert (out / "fit_molecules.png").exists()
    # --global: one fit, shared parameters, offsets per molecule
    ok = df[df["molecule"] != "m2"].reset_index(drop=True)
    ok.attrs = df.attrs
    path2 = _write(ok, tmp_path / "ok.csv")
    assert main(["fit", str(path2), "--global", "--out", str(tmp_path / "g"), "--no-plot"]) == 0
    params = sc.read_csv(tmp_path / "g" / "fit_parameters.csv")
    assert "turns_offset[m1]" in params.columns and "turns_offset[m3]" in params.columns


def test_fit_command_joint_torque_fit_and_flags(tmp_path, capsys, true_dna):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, [0.3, 0.5, 0.7] * u.pN, points_per_force=40,
                                  seed=9, torque_noise=2 * u.pN * u.nm)
    path = _write(df, tmp_path / "torque.csv")
    out = tmp_path / "t"
    assert main(["fit", str(path), "--out", str(out), "--no-plot"]) == 0
    report = (out / "fit_report.txt").read_text()
    assert "torque channel" in report
    points = sc.read_csv(out / "fit_points.csv")
    assert points.attrs["units"]["torque_residual"] == "pN*nm"
    assert np.std(points["torque_residual"]) == pytest.approx(2.0, rel=0.25)
    assert main(["fit", str(path), "--jobs", "0", "--out", str(out)]) == 2
    assert "--jobs must be at least 1" in capsys.readouterr().err


def test_fit_command_bad_input(tmp_path, capsys):
    path = tmp_path / "bad.csv"
    path.write_text("force [pN], turns, extension [um]\n0.5, 1, 0.6\n0.5, x, 0.6\n")
    assert main(["fit", str(path), "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert "line 3" in err and "'turns'" in err
    good = tmp_path / "g.csv"
    good.write_text("force [pN], turns, extension [um]\n0.5, 1, 0.6\n")
    assert main(["fit", str(good), "--bound", "radius=3nm", "--out", str(tmp_path / "y")]) == 2
    assert "LO:HI" in capsys.readouterr().err


def test_fit_command_malformed_row_is_an_error_not_a_traceback(tmp_path, capsys):
    """A decimal comma row raised pandas' ParserError out of `supercoil fit`."""
    path = tmp_path / "dc.csv"
    path.write_text("# rig: 2\nforce [pN],turns,extension [um]\n0.5,1,0.6\n0.5,2,0,61\n")
    assert main(["fit", str(path), "--out", str(tmp_path / "x")]) == 2
    err = capsys.readouterr().err
    assert "dc.csv, line 4: 4 fields" in err and "decimal comma" in err
    assert "Traceback" not in err


def test_fit_command_messages_name_the_flags(tmp_path, capsys, true_dna):
    """Audit P5: messages name --no-turns-offset, --fix, --start, not keyword arguments."""
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, [0.5] * u.pN, points_per_force=30, seed=4)
    path = _write(df, tmp_path / "data.csv")
    out = str(tmp_path / "o")
    assert main(["fit", str(path), "--vary", "turns_offset", "--out", out]) == 2
    err = capsys.readouterr().err
    assert "--no-turns-offset" in err and "--vary" in err
    assert "fit_turns_offset" not in err and "fit_extension_offset" not in err
    assert main(["fit", str(path), "--vary", "radius", "--fix", "radius=2nm",
                 "--out", out]) == 2
    assert "--vary/--fix: parameter 'radius' is both varied and fixed" in capsys.readouterr().err
    assert main(["fit", str(path), "--vary", "radius", "--fix", "length=-1nm",
                 "--out", out]) == 2
    err = capsys.readouterr().err
    assert "--fix: the fixed value of length must be finite and positive, got -1 nm" in err
    assert "Quantity" not in err
    assert main(["fit", str(path), "--vary", "radius", "--start", "length=700nm",
                 "--out", out]) == 2
    assert "--start: a start value is given for 'length'" in capsys.readouterr().err
    # values that do not parse name their flag
    for flag, item in (("--fix", "length=abc"), ("--start", "radius=1 parsec/"),
                       ("--bound", "radius=x:3nm"), ("--sigma", "5 blorp")):
        assert main(["fit", str(path), flag, item, "--out", out]) == 2
        err = capsys.readouterr().err
        assert f"cannot read {flag}" in err, (flag, err)


def test_fit_command_reports_a_molecule_whose_parameters_are_not_determined(
        tmp_path, capsys, true_dna):
    """A nicked molecule (flat curve) is reported, and the exit status is 1."""
    u = sc.ureg
    forces = [0.3, 0.5, 0.7]
    df = simulate_rotation_curves(true_dna, forces * u.pN, points_per_force=30, molecules=2,
                                  seed=1)
    flat = simulate_rotation_curves(true_dna, forces * u.pN, turns=np.zeros(30), seed=3)
    df.loc[(df["molecule"] == "m2").to_numpy(), "extension"] = flat["extension"].to_numpy()
    path = _write(df, tmp_path / "nicked.csv")
    out = tmp_path / "n"
    assert main(["fit", str(path), "--out", str(out)]) == 1
    captured = capsys.readouterr()
    assert "molecule m2: " in captured.err and "do not determine radius" in captured.err
    report = (out / "fit_report.txt").read_text()
    assert "[[Not determined]]" in report
    m2 = next(line for line in report.splitlines() if line.strip().startswith("m2"))
    assert "not determined" in m2
    table = sc.read_csv(out / "fit_molecules.csv")
    assert list(table["determined"]) == [True, False]
    assert (out / "fit_molecules.png").stat().st_size > 0


def test_fit_end_loop_flag_fits_the_model_with_its_loop(tmp_path, true_dna):
    """--end-loop fits the looped model: the library's numbers for that model, which
    differ from the model without the loop on data made with the loop."""
    from supercoil.dna.models import get_model

    u = sc.ureg
    looped = get_model("marko2007", end_loop=True)
    df = simulate_rotation_curves(true_dna, [1.0, 2.0, 3.0] * u.pN, points_per_force=60,
                                  turns_offset=0.4, extension_offset=30 * u.nm, seed=7,
                                  model=looped)
    path = _write(df, tmp_path / "data.csv")
    out = tmp_path / "out"
    assert main(["fit", str(path), "--model", "marko2007", "--end-loop", "--vary",
                 "twist_persistence", "--out", str(out), "--no-plot"]) == 0
    params = sc.read_csv(out / "fit_parameters.csv")
    data = sc.read_tweezers_csv(path)
    dna = sc.load_parameters("dna")
    with warnings.catch_warnings():  # short tails, negative N above 0.8 pN
        warnings.simplefilter("ignore")  # and the plain model misfits the looped data
        ref = sc.fit_hat_curves(data, dna, vary=["twist_persistence"], model=looped)
        plain = sc.fit_hat_curves(data, dna, vary=["twist_persistence"], model="marko2007")
    got = params["twist_persistence"].iloc[0]
    assert got == pytest.approx(ref.parameters["twist_persistence"].m, rel=1e-9)
    assert got != pytest.approx(plain.parameters["twist_persistence"].m, rel=1e-6)


def test_fit_command_compares_models_with_their_cost_and_start_values(tmp_path, true_dna):
    """Several --model: the ranked table gives each model's CPU cost beside AIC and BIC; a
    --start value reaches every model's fit (the same start as the library call)."""
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, [1.2] * u.pN, np.linspace(-20, 20, 41), seed=1)
    path = _write(df, tmp_path / "data.csv")
    out = tmp_path / "out"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)
        assert main(["fit", str(path), "--model", "li-zhao", "--model", "marko2007",
                     "--start", "turns_offset=0.3", "--out", str(out), "--no-plot"]) == 0
        ref = sc.compare_models(sc.read_tweezers_csv(path), sc.load_parameters("dna"),
                                ["li-zhao", "marko2007"], start={"turns_offset": 0.3})
    table = sc.read_csv(out / "fit_comparison.csv")
    assert list(table["model"]) == list(ref.table["model"]) == ["li-zhao", "marko2007"]
    assert (table["cpu_seconds"] > 0).all() and table.attrs["units"]["cpu_seconds"] == "s"
    np.testing.assert_allclose(table["aic"], ref.table["aic"], rtol=1e-9)
    assert ref.results["li-zhao"].start["turns_offset"].m_as("turn") == pytest.approx(0.3)
    assert "fit CPU s" in (out / "fit_report.txt").read_text()
