"""``supercoil hat``: CSV with units in headers, the plot, units parsed, named failures."""

import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main
from supercoil.commands.hat import parse_turns


def test_hat_command_writes_csv_and_plot(tmp_path, capsys, dna, ureg):
    out = tmp_path / "out"
    rc = main(["hat", "--params", "dna", "--force", "0.4pN", "--force", "1.2 pN",
               "--turns=-20:20:0.5", "--out", str(out)])
    assert rc == 0
    assert (out / "hat_curve.png").stat().st_size > 0
    text = (out / "hat_curve.csv").read_text()
    assert "extension [nm]" in text and "torque [pN nm]" in text and "force [pN]" in text
    df = sc.read_csv(out / "hat_curve.csv")
    assert df.attrs["units"]["extension"] == "nm"
    assert sorted(set(df["force"])) == [0.4, 1.2]
    assert len(df) == 2 * 81
    # same numbers as the library call
    ref = sc.hat_curve(dna, 0.4 * ureg.pN, np.arange(-20, 20.25, 0.5))
    np.testing.assert_allclose(df[df.force == 0.4]["extension"], ref["extension"], rtol=1e-10)
    captured = capsys.readouterr()
    assert "denature" in captured.err  # 1.2 pN with negative turns: warned, not fatal
    assert "N_b" in captured.out


def test_hat_command_defaults_are_the_paper_figure(tmp_path):
    out = tmp_path / "d"
    assert main(["hat", "--out", str(out), "--no-plot"]) == 0
    df = sc.read_csv(out / "hat_curve.csv")
    assert sorted(set(df["force"])) == [0.4, 1.2, 3.0]
    assert df["turns"].min() == -40 and df["turns"].max() == 40
    assert not (out / "hat_curve.png").exists()


def test_hat_command_units_are_parsed(tmp_path):
    a, b = tmp_path / "a", tmp_path / "b"
    assert main(["hat", "--force", "1.2pN", "--turns=0:30:1", "--length", "0.75um",
                 "--out", str(a), "--no-plot", "--athermal"]) == 0
    assert main(["hat", "--force", "1200 fN", "--turns=0:30:1", "--length", "750 nm",
                 "--out", str(b), "--no-plot", "--athermal"]) == 0
    da, db = sc.read_csv(a / "hat_curve.csv"), sc.read_csv(b / "hat_curve.csv")
    np.testing.assert_allclose(da["extension"], db["extension"], rtol=1e-10)
    assert da.attrs["provenance"]["thermal"] is False


@pytest.mark.parametrize("argv", [["--force", "0.4nm"], ["--force", "lots"],
                                  ["--turns=3:1:1"], ["--turns=0:1:0"],
                                  ["--length", "5pN"]])
def test_bad_arguments_exit_with_usage_error(argv, tmp_path):
    with pytest.raises(SystemExit) as exc:
        main(["hat", *argv, "--out", str(tmp_path)])
    assert exc.value.code == 2


def test_model_failures_are_reported(tmp_path, capsys):
    rc = main(["hat", "--force", "0.05pN", "--out", str(tmp_path), "--no-plot"])
    assert rc == 2
    err = capsys.readouterr().err
    assert "0.05 pN" in err and "bracket" in err
    rc = main(["hat", "--params", "silicone_rubber_rod", "--out", str(tmp_path)])
    assert rc == 2


def test_parse_turns():
    np.testing.assert_allclose(parse_turns("-20:20:0.1")[[0, -1]], [-20, 20])
    assert parse_turns("-20:20:0.1").size == 401
    assert parse_turns("0:1").size == 11
    np.testing.assert_array_equal(parse_turns("1,2.5,-3"), [1, 2.5, -3])


@pytest.mark.parametrize("model", sc.available_models())
def test_hat_command_with_each_registered_model_equals_the_library(tmp_path, dna, ureg, model):
    out = tmp_path / model
    assert main(["hat", "--model", model, "--force", "0.5pN", "--turns=-6:6:1", "--out",
                 str(out), "--no-plot"]) == 0
    df = sc.read_csv(out / "hat_curve.csv")
    ref = sc.hat_curve(dna, 0.5 * ureg.pN, np.arange(-6, 7.0), model=model)
    np.testing.assert_allclose(df["extension"], ref["extension"], rtol=1e-10)
    assert df.attrs["provenance"]["model"] == model
