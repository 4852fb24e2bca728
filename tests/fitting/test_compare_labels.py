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


@pytest.fixture(scope="module")
def dna():
    return sc.load_parameters("dna")


@pytest.fixture(scope="module")
def data(dna):
    return sc.simulate_rotation_curves(dna, [1.2] * u.pN, np.linspace(-20, 20, 41), seed=1)


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
def test_the_same_model_twice_is_a_value_error(data, dna, models):
    with pytest.raises(ValueError, match=r"models\[0\] and models\[1\] are the same model"):
        sc.compare_models(data, dna, models)


def test_one_row_and_one_result_per_model(data, dna):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)  # the fits' own diagnostics
        comparison = sc.compare_models(data, dna, ["marko2007", Marko2007(end_loop=True)])
    table, results = comparison.table, comparison.results
    assert sorted(table["model"]) == ["marko2007", "marko2007(end_loop=True)"]
    assert sorted(results) == sorted(table["model"])
    assert results["marko2007(end_loop=True)"].model.end_loop is True
    assert results["marko2007"].model.end_loop is False
    for label, chi2 in zip(table["model"], table["chi_square"], strict=True):
        assert results[label].chi_square == pytest.approx(chi2, rel=1e-12)
