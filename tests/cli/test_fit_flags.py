"""``supercoil fit``: the fitting errors name their argument, the command prints its flag.

The fitting package raises its argument errors with an ``argument`` attribute (library
wording, no command-line terms); the command maps it to the flag through the one table
:data:`~supercoil.commands._common.ARGUMENT_FLAGS`. Checked here: every argument the
fitting code names is in the table with a flag of ``supercoil fit``, and every bad
argument given on the command line exits 2 with its flag in front of the message.
"""

import argparse
import ast
import inspect
from pathlib import Path

import pytest

import supercoil as sc
from supercoil import cli
from supercoil.cli import main
from supercoil.commands._common import ARGUMENT_FLAGS, flag_text, warning_text
from supercoil.dna.fitting import (
    compare_models,
    fit_hat_curves,
    fit_many,
    simulate_rotation_curves,
)
from supercoil.dna.tweezers import read_tweezers_csv
from supercoil.exceptions import FitError, FitWarning

FITTING = Path(sc.__file__).parent / "dna" / "fitting"


def _fit_options():
    parser = cli.build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return {o for a in sub.choices["fit"]._actions for o in a.option_strings}


def _strings(node):
    """The string constants of ``node`` (a constant, a tuple of them, or ``a if c else b``)."""
    if isinstance(node, ast.IfExp):
        return _strings(node.body) | _strings(node.orelse)
    if isinstance(node, ast.Tuple | ast.List):
        return set().union(*map(_strings, node.elts))
    return {node.value} if isinstance(node, ast.Constant) and isinstance(node.value, str) \
        else set()


#: arguments of fitting functions that no command exposes (Python only)
PYTHON_ONLY = {
    "return_results": "compare_models(return_results=...): the command writes both",
    "sigma_column": "simulate_rotation_curves is not a command",
}


def _named_arguments():
    """Argument names the fitting code attaches to its errors, read from its source.

    ``argument="x"`` (SupercoilError), ``named(exc, "x")``, ``check_flag(value, "x")``
    and ``_about("x")`` (the FitErrors about the names in ``vary``/``fixed``/...).
    """
    found = {}
    for path in sorted(FITTING.glob("*.py")):
        for node in ast.walk(ast.parse(path.read_text())):
            if not isinstance(node, ast.Call):
                continue
            func = getattr(node.func, "id", getattr(node.func, "attr", ""))
            for kw in node.keywords:
                if kw.arg == "argument":
                    found.update(dict.fromkeys(_strings(kw.value), path.name))
            if func in ("named", "check_flag") and len(node.args) == 2:
                found.update(dict.fromkeys(_strings(node.args[1]), path.name))
            if func == "_about" and node.args:
                found.update(dict.fromkeys(_strings(node.args[0]), path.name))
    return found


def test_every_argument_of_a_fitting_error_maps_to_a_flag_of_fit():
    named = _named_arguments()
    # the scan sees the errors this module checks below
    assert {"vary", "fixed", "start", "bounds", "sigma", "fit_turns_offset",
            "fit_extension_offset"} <= set(named)
    options = _fit_options()
    missing = {a: f for a, f in named.items()
               if a not in PYTHON_ONLY and ARGUMENT_FLAGS.get(a) not in options}
    assert not missing, f"arguments without a flag of supercoil fit: {missing}"


def test_every_table_entry_of_a_fit_argument_is_a_flag_of_fit():
    """The table's entries for the keywords of the fitting functions are fit's flags."""
    keywords = {name for func in (fit_hat_curves, fit_many, compare_models, read_tweezers_csv)
                for name in inspect.signature(func).parameters}
    fit_entries = {a: f for a, f in ARGUMENT_FLAGS.items() if a in keywords}
    assert {"vary", "fixed", "start", "bounds", "sigma"} <= set(fit_entries)
    options = _fit_options()
    assert {a: f for a, f in fit_entries.items() if f not in options} == {}


@pytest.fixture(scope="module")
def csv_files(tmp_path_factory):
    u = sc.ureg
    dna = sc.load_parameters("dna")
    folder = tmp_path_factory.mktemp("flags")
    one = simulate_rotation_curves(dna, [0.5] * u.pN, points_per_force=12, seed=4)
    two = simulate_rotation_curves(dna, [0.5] * u.pN, points_per_force=12, molecules=2,
                                   seed=5)
    return {"one": sc.write_csv(one, folder / "one.csv"),
            "two": sc.write_csv(two, folder / "two.csv")}


@pytest.mark.parametrize("data, argv, prefix, text", [
    ("one", ["--vary", "pitch"], "--vary", "cannot vary 'pitch'"),
    ("one", ["--vary", "turns_offset"], "--vary",
     "switched off with --no-turns-offset and --no-extension-offset"),
    ("one", ["--vary", "radius", "--fix", "radius=2nm"], "--vary/--fix",
     "parameter 'radius' is both varied and fixed"),
    ("one", ["--fix", "length=-1nm"], "--fix",
     "the fixed value of length must be finite and positive, got -1 nm"),
    ("one", ["--fix", "pitch=2nm"], "--fix", "unknown parameter 'pitch'"),
    ("one", ["--fix", "radius=2s"], "--fix", "parameter 'radius': "),
    ("one", ["--start", "length=700nm"], "--start",
     "a start value is given for 'length', which is not varied"),
    ("one", ["--start", "radius=2s"], "--start", "parameter 'radius': "),
    ("one", ["--bound", "length=1nm:2nm"], "--bound",
     "bounds are given for 'length', which is not a free parameter"),
    ("one", ["--bound", "radius=3nm:1nm"], "--bound",
     "the bounds of 'radius': lower bound 3 nm is not below 1 nm"),
    ("one", ["--sigma", "0nm"], "--sigma", "sigma must be finite and positive"),
    ("one", ["--sigma", "1km"], "--sigma", "is above the contour length"),
    ("two", ["--fix", "turns_offset[m1]=0"], "--fix",
     "each molecule is fitted alone here, so per-molecule names do not apply"),
    ("two", ["--start", "turns_offset[m1]=0"], "--start", "each molecule is fitted alone"),
])
def test_a_bad_argument_exits_2_with_its_flag_in_front(csv_files, tmp_path, capsys, data,
                                                       argv, prefix, text):
    status = main(["fit", str(csv_files[data]), *argv, "--no-plot",
                   "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert status == 2, err
    assert f"supercoil fit: error: {prefix}: " in err and text in err, err
    # no Python keyword of the fitting functions is left in the message
    assert "fit_turns_offset" not in err and "fit_extension_offset" not in err
    assert "Traceback" not in err and not (tmp_path / "o").exists()


def test_the_library_messages_keep_python_terms_and_the_argument():
    """The same errors in Python: keyword names in the text, the argument attached."""
    u = sc.ureg
    dna = sc.load_parameters("dna")
    df = simulate_rotation_curves(dna, [0.5] * u.pN, points_per_force=12, seed=4)
    with pytest.raises(FitError, match=r"fit_turns_offset=False") as info:
        fit_hat_curves(df, dna, vary=["turns_offset"])
    assert info.value.argument == "vary"
    with pytest.raises(FitError, match="no parameter is varied") as info:
        fit_hat_curves(df, dna, vary=[], fit_turns_offset=False, fit_extension_offset=False)
    assert info.value.argument == "vary"
    with pytest.raises(FitError, match="unknown parameter 'pitch'") as info:
        fit_hat_curves(df, dna, bounds={"pitch": (1 * u.nm, 2 * u.nm)})
    assert info.value.argument == "bounds"


def test_warnings_get_their_flag_and_calls_written_out_stay_python():
    w = FitWarning("the offsets are degenerate")
    w.argument = "fit_extension_offset"
    assert warning_text("fit", w) == ("supercoil fit: warning: --no-extension-offset: the "
                                      "offsets are degenerate")
    text = "hold it at 0 (fit_extension_offset=False), or dna.replace(length=...)"
    assert flag_text(text) == "hold it at 0 (--no-extension-offset), or dna.replace(length=...)"
