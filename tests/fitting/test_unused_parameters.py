"""Issue 22 item 4: a model varies only what it uses; undetermined parameters are named and
not counted in AIC/BIC."""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil.dna.interactions import get_interaction
from supercoil.dna.models import get_model
from supercoil.exceptions import FitWarning

FORCES = np.array([1.0, 1.5, 2.0])  # pN: above 4 kT/A, where marko2007 is valid
VARY = ["twist_persistence", "plectoneme_twist_persistence"]
TURNS = np.linspace(0.5, 12.0, 40)  # positive only: no denaturation above 0.8 pN


@pytest.fixture(scope="module")
def marko_data(base):
    return sc.simulate_rotation_curves(base, FORCES * sc.ureg.pN, turns=TURNS,
                                       noise=3 * sc.ureg.nm, model="marko2007", seed=3)


def test_default_vary_drops_the_radius_marko2007_does_not_use(marko_data, base):
    r = sc.fit_hat_curves(marko_data, base, model="marko2007")
    assert "radius" not in r.names and "twist_persistence" in r.names
    assert "radius" in r.fixed
    assert any("radius not varied" in n and "marko2007" in n for n in r.notes)
    assert "[[Notes]]" in r.report() and not r.undetermined


def test_li_zhao_uses_the_radius(base):
    from supercoil.dna.fitting.start import unused_parameters

    si = base.si
    force = np.full(30, 1e-12)
    li, inter = get_model("li-zhao"), get_interaction("hard-core")
    assert unused_parameters(["radius", "twist_persistence"], force, si, li, inter,
                             True) == []
    mk = get_model("marko2007")
    assert unused_parameters(["radius", "end_loop_writhe", "twist_persistence"], force,
                             si, mk, inter, True) == ["radius", "end_loop_writhe"]


def test_explicit_unused_parameter_is_undetermined_and_not_counted(marko_data, base):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        r = sc.fit_hat_curves(marko_data, base, vary=[*VARY, "radius"], model="marko2007")
    fit = [str(w.message) for w in caught if issubclass(w.category, FitWarning)]
    assert any("do not determine radius" in m for m in fit), fit
    assert r.undetermined == ["radius"]
    # its Jacobian column is exactly zero: it stays at its start, no implausible value
    assert r.parameters["radius"].m_as("nm") == pytest.approx(base.radius.m_as("nm"))
    assert not any("radius = " in m and "plausible" in m for m in fit), fit
    assert r.n_determined == r.nvarys - 1
    ref = sc.fit_hat_curves(marko_data, base, vary=VARY, model="marko2007")
    # the same optimum, the same information criteria: the flat direction costs nothing
    assert r.aic == pytest.approx(ref.aic, abs=1e-6)
    assert r.bic == pytest.approx(ref.bic, abs=1e-6)


def test_compare_models_drops_the_unused_loop_writhe(marko_data, base):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        comparison = sc.compare_models(marko_data, base, ["marko2007", "li-zhao"])
    table, res = comparison.table, comparison.results
    mk = res["marko2007"]
    assert "end_loop_writhe" not in mk.names and "radius" not in mk.names
    assert "plectoneme_twist_persistence" in mk.names
    row = table.set_index("model").loc["marko2007"]
    assert row["nparams"] == mk.n_determined == len(mk.names)
    assert np.isnan(row["radius"])
