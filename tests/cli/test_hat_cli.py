"""``supercoil hat``: CSV with units in headers, the plot, units parsed, named failures."""

import warnings

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
    assert df["turns"].max() == 40
    # negative turns only where real DNA does not melt (<= 0.8 pN)
    low, high = df[df.force == 0.4]["turns"], df[df.force > 0.8]["turns"]
    assert low.min() == -40 and len(low) == 801
    assert high.min() == 0 and len(high) == 2 * 401
    assert not (out / "hat_curve.png").exists()


def test_main_job_prints_no_warning(tmp_path, capsys):
    """The README's main job: no Python warning and nothing on stderr."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        assert main(["hat", "--params", "dna", "--out", str(tmp_path), "--no-plot"]) == 0
    assert caught == []
    assert capsys.readouterr().err == ""


def test_warning_asked_for_is_shown_once_in_plain_words(tmp_path, capsys):
    assert main(["hat", "--force", "1.2pN", "--force", "3pN", "--turns", "-5:5:1",
                 "--out", str(tmp_path), "--no-plot"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 1, err
    assert "denatures" in err[0] and "--turns=0:40" in err[0]
    assert "Warning" not in err[0]  # no Python warning category / file:line text


def test_help_shows_the_defaults(capsys):
    with pytest.raises(SystemExit):
        main(["hat", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    for default in ("0.4pN, 1.2pN, 3.0pN", "-40:40:0.1", "0:40:0.1", "0.8 pN", "li-zhao",
                    "hard-core", "hat_out"):
        assert default in text, default


def test_buckling_table_is_the_library_and_li_zhao_torque_is_the_plectoneme_torque(
        tmp_path, dna, ureg):
    forces = [0.4, 1.2, 3.0] * ureg.pN
    tables = {}
    for model in ("li-zhao", "free-energy"):
        assert main(["hat", "--model", model, "--turns=0:1:1", "--out", str(tmp_path / model),
                     "--no-plot"]) == 0
        t = tables[model] = sc.read_csv(tmp_path / model / "buckling.csv")
        assert t.attrs["units"]["buckling_torque"] == "pN nm"
        np.testing.assert_allclose(t["buckling_turns"],
                                   sc.buckling_turns(dna, forces, model=model).m_as("turn"),
                                   rtol=1e-10)
        np.testing.assert_allclose(
            t["post_buckling_slope"],
            sc.post_buckling_slope(dna, forces, model=model).m_as("nm/turn"), rtol=1e-10)
    # li-zhao buckles where the tail torque reaches the plectoneme torque (an independent
    # solve: the uniform plectoneme equilibrium at the same force)
    eq = sc.plectoneme_equilibrium(dna, forces)
    np.testing.assert_allclose(tables["li-zhao"]["buckling_torque"], eq.torque.m_as("pN nm"),
                               rtol=1e-9)
    # the stretched phase is linear in N up to buckling: M_b = C_eff 2 pi N_b / L, so the
    # torque at buckling is the hat curve's torque just below N_b
    for model, t in tables.items():
        for f, nb, mb in zip(t["force"], t["buckling_turns"], t["buckling_torque"], strict=True):
            ref = sc.hat_curve(dna, f * ureg.pN, [nb * (1 - 1e-9)], model=model)
            assert ref["torque"].iloc[0] == pytest.approx(mb, rel=1e-6), (model, f)


@pytest.mark.parametrize("spelling", [["--turns", "-20:20:0.5"], ["--turns=-20:20:0.5"],
                                      ["--turns", "-20,-1.5,3"], ["--turns", "-.5:.5:0.5"]])
def test_negative_ranges_in_both_spellings(tmp_path, spelling):
    out = tmp_path / "o"
    assert main(["hat", "--force", "0.4pN", *spelling, "--out", str(out), "--no-plot"]) == 0
    got = sc.read_csv(out / "hat_curve.csv")["turns"].to_numpy()
    expected = parse_turns(spelling[-1].removeprefix("--turns="))
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12)
    assert got[0] < 0


@pytest.mark.parametrize("argv", [["--turns", "-20:x"], ["--turns=-20:-30:1"],
                                  ["--turns", "-1:1:0"], ["--turns", "-inf:1"],
                                  ["--force", "-0.4nm"], ["--length", "-5pN"],
                                  ["--length", "-5nm"], ["--short-tail=-1nm"]])
def test_bad_values_exit_2_naming_the_flag(argv, tmp_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["hat", *argv, "--out", str(tmp_path)])
    assert exc.value.code == 2
    assert f"argument {argv[0].split('=')[0]}" in capsys.readouterr().err


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


def test_values_starting_with_a_minus_are_values_and_flags_stay_flags():
    from supercoil.cli import build_parser

    parser = build_parser()
    args = parser.parse_args(["hat", "--turns", "-1:1", "--athermal", "--force", "-.4pN"])
    # abs: np.arange gives 2e-16 for the 0
    assert list(args.turns) == pytest.approx(np.arange(-1, 1.05, 0.1), rel=1e-6, abs=1e-12)
    assert args.athermal and args.force[0].magnitude == -0.4
    args = parser.parse_args(["rod", "--turns", "-4", "--slack", "-1cm", "-2 cm", "--out", "o"])
    assert args.turns == "-4" and args.slack == ["-1cm", "-2 cm"]
    with pytest.raises(SystemExit):  # "-x" is still an (unknown) option
        parser.parse_args(["rod", "--turns", "-x", "--out", "o"])


def test_short_tail_zero_flags_no_point(tmp_path):
    assert main(["hat", "--force", "1pN", "--turns=0:40:10", "--short-tail", "0nm",
                 "--out", str(tmp_path), "--no-plot"]) == 0
    assert not sc.read_csv(tmp_path / "hat_curve.csv")["short_tail"].any()


def test_default_turns_switch_exactly_at_the_denaturation_force(tmp_path, capsys):
    """0.8 pN itself keeps negative turns (the library warns above 0.8 pN only)."""
    assert main(["hat", "--force", "0.8pN", "--force", "0.81pN", "--out", str(tmp_path),
                 "--no-plot"]) == 0
    assert capsys.readouterr().err == ""
    df = sc.read_csv(tmp_path / "hat_curve.csv")
    assert df[df.force == 0.8]["turns"].min() == -40
    assert df[df.force == 0.81]["turns"].min() == 0


def test_end_loop_flag_gives_the_library_curve_with_the_loop(tmp_path, dna, ureg):
    """--end-loop: the model with its end loop (the library's numbers, provenance says so);
    a model without one is a named usage error."""
    from supercoil.dna.models import get_model

    out = tmp_path / "loop"
    assert main(["hat", "--model", "marko2007", "--end-loop", "--force", "1pN",
                 "--turns", "0:20:0.5", "--out", str(out), "--no-plot"]) == 0
    df = sc.read_csv(out / "hat_curve.csv")
    assert df.attrs["provenance"]["model_options"] == {"end_loop": True}
    turns = np.arange(0, 20.25, 0.5)
    looped = sc.hat_curve(dna, 1 * ureg.pN, turns, model=get_model("marko2007", end_loop=True))
    plain = sc.hat_curve(dna, 1 * ureg.pN, turns, model="marko2007")
    np.testing.assert_allclose(df["extension"], looped["extension"], rtol=1e-10)
    assert not np.allclose(looped["extension"], plain["extension"])  # the loop shows
    nb = sc.read_csv(out / "buckling.csv")["buckling_turns"][0]
    assert nb == pytest.approx(sc.buckling_turns(dna, 1 * ureg.pN, model=get_model(
        "marko2007", end_loop=True)).m[0], rel=1e-10)


def test_end_loop_flag_on_a_model_without_one_names_the_models_with_one(tmp_path, capsys):
    assert main(["hat", "--end-loop", "--out", str(tmp_path), "--no-plot"]) == 2
    err = capsys.readouterr().err
    assert "--end-loop: model 'li-zhao' has no end loop" in err
    assert "free-energy" in err and "marko2007" in err
    assert main(["fit", "missing.csv", "--end-loop", "--out", str(tmp_path)]) == 2
    assert "--end-loop: model 'li-zhao' has no end loop" in capsys.readouterr().err
