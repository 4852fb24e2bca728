"""Issue 20, item 4: compare_models keeps one labelled row and one result per model.

On main ``["marko2007", Marko2007(end_loop=True)]`` labelled both rows
``marko2007`` and the results dict kept only one of them (the worse).
"""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.dna.fitting.compare import model_labels
from supercoil.dna.models import Marko2007

u = sc.ureg


def test_labels_carry_the_non_default_options_and_parameters():
    plain, looped = Marko2007(), Marko2007(end_loop=True)
    assert model_labels(["marko2007", looped]) == ["marko2007", "marko2007(end_loop=True)"]
    assert model_labels([plain, "li-zhao"]) == ["marko2007", "li-zhao"]
    (key, spec), *_ = plain.parameters.items()
    other = plain.replace(**{key: spec.quantity(spec.default * 1.5)})
    label = model_labels([plain, other])[1]
    assert label.startswith(f"marko2007({key}=") and label != "marko2007"
    nearly = plain.replace(**{key: spec.quantity(spec.default * (1 + 1e-9))})
    a, b = model_labels([plain.replace(**{key: spec.quantity(spec.default * 1.5)}),
                         plain.replace(**{key: spec.quantity(spec.default * 1.5 * (1 + 1e-9))})])
    assert a != b  # equal to 6 digits, yet distinct models: every digit
    assert model_labels([plain, nearly])[0] == "marko2007"


@pytest.mark.parametrize("models", [["marko2007", "marko2007"], ["marko2007", Marko2007()],
                                    [Marko2007(end_loop=True), Marko2007(end_loop=True)]])
def test_the_same_model_twice_is_a_value_error(one_force_data, dna, models):
    with pytest.raises(ValueError, match=r"models\[0\] and models\[1\] are the same model"):
        sc.compare_models(one_force_data, dna, models)


def test_one_row_and_one_result_per_model(one_force_data, dna):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)  # the fits' own diagnostics
        comparison = sc.compare_models(one_force_data, dna,
                                       ["marko2007", Marko2007(end_loop=True)])
    table, results = comparison.table, comparison.results
    assert sorted(table["model"]) == ["marko2007", "marko2007(end_loop=True)"]
    assert sorted(results) == sorted(table["model"])
    assert results["marko2007(end_loop=True)"].model.end_loop is True
    assert results["marko2007"].model.end_loop is False
    for label, chi2 in zip(table["model"], table["chi_square"], strict=True):
        assert results[label].chi_square == pytest.approx(chi2, rel=1e-12)


def test_a_failed_row_keeps_its_error_and_the_argument_it_is_about():
    """A model whose fit cannot start (a start value for a parameter it does not have) is a
    failed row whose error keeps its type and ``argument`` (in ``errors``, the
    ``error_argument`` column, through pickling, and as the flag in the CLI's report)."""
    import pickle

    from supercoil.commands._common import flagged_error
    from supercoil.exceptions import FitError

    dna = sc.load_parameters("dna")
    data = sc.simulate_rotation_curves(dna, [0.5, 1.0] * u.pN, turns=np.linspace(-20, 20, 21),
                                       noise=3 * u.nm, seed=1)
    vary = {"li-zhao": ["twist_persistence"],
            "marko2007": ["twist_persistence", "plectoneme_twist_persistence"]}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        comp = sc.compare_models(data, dna, ["li-zhao", "marko2007"], vary=vary,
                                 start={"plectoneme_twist_persistence": 20 * u.nm})
    table = comp.table.set_index("model")
    assert table.loc["marko2007", "success"] and not table.loc["li-zhao", "success"]
    assert list(comp.errors) == ["li-zhao"] and list(comp.results) == ["marko2007"]
    exc = comp.errors["li-zhao"]
    assert isinstance(exc, FitError) and exc.argument == "start"
    assert table.loc["li-zhao", "error_argument"] == "start"
    assert table.loc["marko2007", "error_argument"] == ""
    assert table.loc["li-zhao", "error"] == f"FitError: {exc}"
    assert pickle.loads(pickle.dumps(comp)).errors["li-zhao"].argument == "start"
    assert "FAILED: FitError: --start: unknown parameter" in comp.report(error_text=flagged_error)
    assert f"FAILED: FitError: {exc}" in comp.report()
