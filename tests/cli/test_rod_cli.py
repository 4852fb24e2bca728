"""``supercoil rod``: writes the profile CSV (units in headers) and a PNG."""

import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main

u = sc.ureg


def test_rough_profile_written_and_consistent_with_the_api(tmp_path, capsys):
    rc = main(["rod", "--params", "silicone_rubber_rod", "--turns", "40", "--out", str(tmp_path)])
    assert rc == 0
    assert (tmp_path / "rod_profile.png").stat().st_size > 0
    table = sc.read_csv(tmp_path / "rod_profile.csv")
    assert table.attrs["units"]["pitch"] == "mm" and table.attrs["units"]["tension"] == "N"
    ref = sc.rough_helix(sc.load_parameters("silicone_rubber_rod"), 40)
    np.testing.assert_allclose(table["pitch"], ref.profile["pitch"], rtol=1e-10)
    out = capsys.readouterr().out
    assert "s_max = 214.668 mm" in out and "slip onset" in out


def test_smooth_at_given_slacks(tmp_path, capsys):
    rc = main(["rod", "--turns", "80 pi rad", "--surface", "smooth", "--slack", "10 cm", "0.2 m",
               "--out", str(tmp_path)])
    assert rc == 0
    t = sc.read_csv(tmp_path / "rod_smooth.csv")
    assert list(t["slack"]) == pytest.approx([100.0, 200.0])
    h = sc.smooth_helix(sc.load_parameters("silicone_rubber_rod"), 40, [10, 20] * u.cm)
    np.testing.assert_allclose(t["alpha"], h.alpha.m_as(u.rad), rtol=1e-10)
    assert (tmp_path / "rod_smooth.png").exists()
    assert "Wr" in capsys.readouterr().out


def test_smooth_sweep_and_rough_stop(tmp_path):
    assert main(["rod", "--turns", "20", "--surface", "smooth", "--points", "50",
                 "--out", str(tmp_path / "a")]) == 0
    assert len(sc.read_csv(tmp_path / "a" / "rod_smooth.csv")) == 50
    assert main(["rod", "--turns", "40", "--slack", "20 cm", "--method", "ode",
                 "--out", str(tmp_path / "b")]) == 0
    t = sc.read_csv(tmp_path / "b" / "rod_profile.csv")
    assert t["slack"].iloc[-1] == pytest.approx(200.0)


def test_rough_stop_prints_the_helix_end_and_where_the_run_stopped(tmp_path, capsys):
    assert main(["rod", "--turns", "40", "--slack", "20 cm", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    # k = 0: the helix end is known beyond the stop; s_end is where the run stopped
    assert "s_max = 214.668 mm" in out and "s_end = 100 mm (s_stop)" in out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--turns", "0"], "N_0 = 0"),
        (["--turns", "40", "--surface", "smooth", "--slack", "1 m"], "rod length"),
        (["--turns", "40", "--surface", "smooth", "--slack", "10"], "--slack"),
        (["--turns", "4 m"], "turns"),
        (["--params", "dna", "--turns", "4"], "not an ElasticRod"),
        (["--params", "no_such_set", "--turns", "4"], "unknown parameter set"),
        (["--turns", "40", "--points", "1"], "n_points must be >= 2"),
        (["--turns", "nan"], "turns must be finite"),
    ],
)
def test_errors_exit_2_with_a_named_reason(tmp_path, capsys, argv, message):
    assert main(["rod", *argv, "--out", str(tmp_path)]) == 2
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("spelling", [["--turns", "-40"], ["--turns=-40"],
                                      ["--turns", "-40turn"], ["--turns", "-80 pi rad"]])
def test_negative_turns_in_both_spellings_mirror_the_helix(tmp_path, capsys, spelling):
    """Twisting the other way gives the mirror helix: the same tilt, s_max and pitch."""
    assert main(["rod", *spelling, "--points", "51", "--out", str(tmp_path)]) == 0
    t = sc.read_csv(tmp_path / "rod_profile.csv")
    ref = sc.rough_helix(sc.load_parameters("silicone_rubber_rod"), 40, n_points=51)
    np.testing.assert_allclose(t["pitch"], ref.profile["pitch"], rtol=1e-10)
    assert "s_max = 214.668 mm" in capsys.readouterr().out


@pytest.mark.parametrize(("argv", "flag"), [
    (["--turns", "-4m"], "--turns"), (["--turns=-nan"], "--turns"), (["--turns", "-x"], "--turns"),
    (["--turns", "40", "--points", "-3x"], "--points"),
    (["--turns", "40", "--curvature-tolerance", "-1:2"], "--curvature-tolerance")])
def test_bad_values_name_the_flag(tmp_path, capsys, argv, flag):
    try:
        status = main(["rod", *argv, "--out", str(tmp_path)])
    except SystemExit as exc:  # argparse's own type errors
        status = exc.code
    assert status == 2
    assert flag in capsys.readouterr().err
