"""Bad arguments of the command line: exit status 2 and a message naming the flag.

``--out`` an existing file, ``--settle -5s``, a bad ``--fix``; the argument -> flag table;
no command, CLI help without repository paths, keyword hints as flags.
"""

import argparse
import pickle

import pytest

import supercoil as sc
from supercoil import cli
from supercoil._checks import check_flag
from supercoil.cli import main
from supercoil.commands._common import (
    ARGUMENT_FLAGS,
    check_out_folder,
    error_text,
    flag_text,
)
from supercoil.dna.fitting import simulate_rotation_curves
from supercoil.exceptions import DataError, FitError, SupercoilError


def _parsers():
    stack, seen = [cli.build_parser()], []
    while stack:
        p = stack.pop()
        seen.append(p)
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())
    return seen


@pytest.fixture(scope="module")
def data_csv(tmp_path_factory):
    u = sc.ureg
    df = simulate_rotation_curves(sc.load_parameters("dna"), [0.5] * u.pN,
                                  points_per_force=20, seed=4)
    return sc.write_csv(df, tmp_path_factory.mktemp("d") / "data.csv")


@pytest.mark.parametrize("command", [["hat", "--no-plot"], ["validate"],
                                     ["curves", "recording.h5"], ["fit", "DATA"],
                                     ["rod", "--turns", "40"]])
def test_out_that_is_a_file_exits_2_before_computing(command, tmp_path, capsys, monkeypatch,
                                                    data_csv):
    """It raised FileExistsError (exit 1) after all the work."""
    command = [str(data_csv) if c == "DATA" else c for c in command]
    target = tmp_path / "x"
    target.write_text("")

    def no_work(*args, **kwargs):
        raise AssertionError("computed before checking --out")

    monkeypatch.setattr("supercoil.validation.validate", no_work)
    monkeypatch.setattr("supercoil.dna.hat.hat_curve", no_work)
    for out in (target, target / "sub"):
        assert main([*command, "--out", str(out)]) == 2
        err = capsys.readouterr().err
        assert f"supercoil {command[0]}: error: --out {out}" in err, err
        assert "Traceback" not in err and "FileExistsError" not in err
    assert target.read_text() == ""


def test_check_out_folder_accepts_new_and_existing_folders(tmp_path):
    assert check_out_folder(tmp_path) is None
    assert check_out_folder(tmp_path / "new" / "deeper") is None
    (tmp_path / "f").write_text("")
    assert "is a file" in check_out_folder(tmp_path / "f")


@pytest.mark.parametrize("settle", ["-5s", "nan s", "inf s", "5 nm", "abc"])
def test_curves_bad_settle_exits_2_naming_the_flag(settle, tmp_path, capsys):
    """``--settle -5s`` raised a ValueError traceback (only SupercoilError was caught)."""
    with pytest.raises(SystemExit) as exit_:
        main(["curves", str(tmp_path / "rec.h5"), "--settle", settle,
              "--out", str(tmp_path / "o")])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert "--settle" in err and "Traceback" not in err


@pytest.mark.parametrize("item", ["turns_offset=nan", "twist_persistence=[1,2]nm",
                                  "radius=inf nm", "radius=5", "length=abc", "radius"])
def test_fit_bad_fix_value_exits_2_naming_the_flag(item, data_csv, tmp_path, capsys):
    """``--fix turns_offset=nan`` gave a ValueError traceback and exit 1 (the "fit failed"
    code); ``[1,2]nm`` was read by pint as 12 nm and fitted silently."""
    argv = ["fit", str(data_csv), "--vary", "twist_persistence", "--fix", item,
            "--no-plot", "--out", str(tmp_path / "o")]
    try:
        status = main(argv)
    except SystemExit as exc:  # argparse's own usage error
        status = exc.code
    assert status == 2
    err = capsys.readouterr().err
    assert "--fix" in err and "Traceback" not in err
    assert not (tmp_path / "o" / "fit_report.txt").exists()


def test_no_command_prints_help_and_exits_2(capsys):
    """It printed the help and exited 0 (argparse's convention for a missing command: 2)."""
    assert main([]) == 2
    err = capsys.readouterr().err
    assert "usage: supercoil" in err and "a COMMAND is required" in err
    assert main(["docs"]) == 2
    assert "an ACTION is required" in capsys.readouterr().err


def test_help_cites_no_repository_path():
    """CLI help cited docs/theory/*.md, which ships in neither wheel nor sdist."""
    for parser in _parsers():
        text = parser.format_help()
        assert "docs/theory" not in text and "theory/" not in text, parser.prog


def test_every_flag_of_the_table_is_an_option():
    options = {o for p in _parsers() for a in p._actions for o in a.option_strings}
    missing = {arg: flag for arg, flag in ARGUMENT_FLAGS.items() if flag not in options}
    assert not missing


def test_flag_text_turns_keyword_hints_into_flags():
    text = "increase settle, or check_settled=False"
    assert flag_text(text) == "increase settle, or --no-check-settled"
    assert flag_text("no force: pass calibration= (magnet height -> force)") == (
        "no force: pass --calibration (magnet height -> force)")
    assert flag_text("give sigma=5nm") == "give --sigma 5nm"
    # names the table does not hold, and --flag=value forms, stay as they are
    assert flag_text("n=3 and --turns=-20:20") == "n=3 and --turns=-20:20"


def test_error_text_puts_the_flag_of_the_argument_in_front():
    exc = FitError("sigma must be finite and positive", argument="sigma")
    assert error_text("fit", exc) == "supercoil fit: error: --sigma: sigma must be finite and " \
                                     "positive"
    # a message that already names the flag is not prefixed twice
    exc = DataError("--calibration x.csv is empty", argument="calibration")
    assert error_text("curves", exc) == "supercoil curves: error: --calibration x.csv is empty"
    assert error_text("hat", SupercoilError("plain")) == "supercoil hat: error: plain"


def test_the_argument_attribute_survives_pickling_and_the_checks_set_it():
    exc = FitError("bad", argument="fixed")
    again = pickle.loads(pickle.dumps(exc))
    assert type(again) is FitError and again.argument == "fixed" and str(again) == "bad"
    assert SupercoilError("x").argument is None
    with pytest.raises(TypeError) as info:
        check_flag("no", "thermal")
    assert info.value.argument == "thermal"
    assert "--athermal" in error_text("hat", info.value)


def test_a_library_type_error_naming_an_argument_exits_2(monkeypatch, tmp_path, capsys):
    """A TypeError/ValueError with an ``argument`` is a bad flag value (2); one without is a
    bug and keeps its traceback."""
    def bad(*args, **kwargs):
        check_flag("yes", "thermal")

    monkeypatch.setattr("supercoil.commands.hat._curves", bad)
    assert main(["hat", "--no-plot", "--out", str(tmp_path / "o")]) == 2
    assert "--athermal: thermal must be True or False" in capsys.readouterr().err

    def bug(*args, **kwargs):
        raise ValueError("internal")

    monkeypatch.setattr("supercoil.commands.hat._curves", bug)
    with pytest.raises(ValueError, match="internal"):
        main(["hat", "--no-plot", "--out", str(tmp_path / "o")])


def test_curves_calibration_error_names_the_flag(tmp_path, capsys):
    from supercoil.traces import simulate_recording, write_synthetic_magscope

    rec = simulate_recording(molecules=1, reference=1, points_per_force=3, seed=2)
    write_synthetic_magscope(tmp_path / "acq", rec)
    assert main(["curves", str(tmp_path / "acq"), "--calibration", str(tmp_path / "no.csv"),
                 "--no-plot", "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--calibration: " in err and "no.csv" in err
    # the library's keyword hint reaches the user as the flag
    assert main(["curves", str(tmp_path / "acq"), "--no-plot", "--out",
                 str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "--calibration" in err and "calibration=" not in err


def _fake_checkout(root):
    (root / "examples").mkdir(parents=True)
    (root / "docs").mkdir()
    (root / "docs" / "conf.py").write_text("")
    (root / "README.md").write_text("# x\n")
    return root


def test_docs_figures_defaults_the_root_to_the_working_checkout(tmp_path, monkeypatch,
                                                                capsys):
    """``supercoil docs figures --skip-bench`` exited 2 asking for --root after
    ``pip install .`` (the package then lives outside the checkout)."""
    from supercoil.commands import docs_figures

    root = _fake_checkout(tmp_path / "repo")
    seen = {}

    def run_scripts(r, work, quick, skip_bench, log):
        seen.update(root=r, skip_bench=skip_bench)
        raise RuntimeError("stop here")

    monkeypatch.setattr(docs_figures, "run_scripts", run_scripts)
    monkeypatch.chdir(root)
    assert main(["docs", "figures", "--skip-bench"]) == 2
    assert seen == {"root": root, "skip_bench": True}
    err = capsys.readouterr().err
    assert "stop here" in err and "--root" not in err


def test_docs_build_defaults_the_source_to_the_working_checkout(tmp_path, monkeypatch, capsys):
    """``supercoil docs build`` needed ``--source docs`` (after ``pip install .`` the
    package's own folder is no checkout): it builds the working folder's docs/."""
    import importlib.util
    import sys
    import types

    from supercoil.commands._common import source_checkout

    root = _fake_checkout(tmp_path / "repo")
    monkeypatch.chdir(root)
    assert source_checkout(None, needs=("docs/conf.py",)) == root
    assert str(source_checkout("elsewhere")) == "elsewhere"  # a given --root wins
    calls = []
    build = types.ModuleType("sphinx.cmd.build")
    build.build_main = lambda argv: calls.append(argv) or 0
    for name, module in (("sphinx", types.ModuleType("sphinx")),
                         ("sphinx.cmd", types.ModuleType("sphinx.cmd")),
                         ("sphinx.cmd.build", build)):
        monkeypatch.setitem(sys.modules, name, module)
    monkeypatch.setattr(importlib.util, "find_spec", lambda name: object())
    assert main(["docs", "build", "--out", str(tmp_path / "html")]) == 0
    assert calls and calls[0][-2:] == [str(root / "docs"), str(tmp_path / "html")]
    capsys.readouterr()
