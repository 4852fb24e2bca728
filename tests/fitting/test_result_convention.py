"""One result convention for fits: a typed engine result, one comparison object, one set
of shared keywords with their defaults, display factors from pint."""

import dataclasses
import inspect
import pickle
import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil import display
from supercoil.dna.fitting import DEFAULTS, Comparison, FitOptions, FitSolution
from supercoil.dna.fitting.fit import run_fit
from supercoil.dna.fitting.prepare import prepare

u = sc.ureg


@pytest.fixture(scope="module")
def comparison(one_force_data, dna):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)  # the fits' own diagnostics
        return sc.compare_models(one_force_data, dna, ["li-zhao", "marko2007"])


def test_the_engine_returns_a_picklable_typed_solution(one_force_data, dna):
    spec = prepare(one_force_data, dna)
    solution = run_fit(spec)
    assert isinstance(solution, FitSolution)
    with pytest.raises(dataclasses.FrozenInstanceError):
        solution.nfev = 0
    back = pickle.loads(pickle.dumps(solution))
    np.testing.assert_array_equal(back.best_fit, solution.best_fit)
    assert back.model == solution.model and back.names == solution.names
    # the model extensions at the data points: with unit weights (1 nm) the raw chi-square
    # is the sum of their squared differences to the data in nm^2
    z = spec.data.extension
    assert solution.chi_square == pytest.approx(np.sum(((z - solution.best_fit) / 1e-9) ** 2),
                                                rel=1e-9)
    assert solution.cpu_seconds > 0 and solution.curve_cpu_seconds is None


def test_compare_models_returns_one_comparison_with_the_cost_of_each_model(comparison):
    assert isinstance(comparison, Comparison)
    t = comparison.table
    assert list(comparison.results) == list(t["model"])  # the table's order, best first
    assert t.attrs["units"]["cpu_seconds"] == t.attrs["units"]["curve_cpu_seconds"] == "s"
    assert (t["cpu_seconds"] > 0).all() and (t["curve_cpu_seconds"] > 0).all()
    # one hat-curve evaluation costs less than the fit, which makes several of them
    assert (t["curve_cpu_seconds"] < t["cpu_seconds"]).all()
    assert comparison.best == t["model"].iloc[0] == "li-zhao"  # the data's own model
    text = comparison.report()
    assert "fit CPU s" in text and "==== model marko2007 ====" in text
    assert repr(comparison).startswith("<Comparison of 2 models: li-zhao")
    assert pickle.loads(pickle.dumps(comparison)).table.equals(t)


def test_old_call_sites_of_compare_models_still_work_with_a_deprecation_warning(
        comparison, one_force_data, dna):
    with pytest.warns(DeprecationWarning, match=r"\.table"):
        assert list(comparison["model"]) == list(comparison.table["model"])
    with pytest.warns(DeprecationWarning, match=r"\.iloc"):
        assert comparison.iloc[0]["model"] == "li-zhao"
    assert len(comparison) == 2
    with pytest.warns(DeprecationWarning, match="return_results"), warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.SupercoilWarning)
        table, results = sc.compare_models(one_force_data, dna, ["li-zhao"], return_results=True)
    assert list(results) == ["li-zhao"] and table["success"].all()


def test_the_shared_keywords_have_their_defaults_in_one_place():
    options = FitOptions.names()
    with pytest.raises(dataclasses.FrozenInstanceError):
        DEFAULTS.tol = 1.0
    for func, own in ((sc.fit_hat_curves, options), (sc.fit_many, options),
                      (sc.compare_models, [n for n in options if n != "model"]),
                      (sc.fit_parameters, ["vary", "fixed", "bounds", "start",
                                           "fit_turns_offset", "fit_extension_offset",
                                           "model", "interaction"])):
        sig = inspect.signature(func).parameters
        for name in own:
            assert name in sig, f"{func.__name__} lacks {name}"
            assert sig[name].default == getattr(DEFAULTS, name), (func.__name__, name)
    assert DEFAULTS.replace(tol=1e-6).tol == 1e-6 and DEFAULTS.tol == 1e-10
    with pytest.raises(TypeError, match="unknown fit option"):
        DEFAULTS.replace(tolerance=1e-6)


def test_display_factors_come_from_pint():
    assert display.factor("force") == pytest.approx(1e12, rel=1e-15)  # N -> pN
    assert display.factor("torque") == pytest.approx(1e21, rel=1e-15)  # N m -> pN nm
    assert display.factor("turns") == 1.0  # counts of turns
    assert display.factor("torque", "rod") == pytest.approx(1e3, rel=1e-15)  # N m -> N mm
    x = np.array([1e-9, 2e-9])
    np.testing.assert_allclose(display.from_display(display.to_display(x, "extension"),
                                                    "extension"), x, rtol=1e-15)
    assert display.quantity(2e-9, "extension").m_as("nm") == pytest.approx(2, rel=1e-15, abs=0)
    for domain, table in display.DISPLAY.items():  # every display unit is a pint unit
        for kind, text in table.items():
            assert display.spec(text)[1] > 0, (domain, kind)
