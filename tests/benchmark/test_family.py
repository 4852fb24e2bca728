"""The family work-precision rows: every registered construction, the reference at zero."""

import numpy as np
import pandas as pd
import pytest

import supercoil as sc
from supercoil.benchmark import family
from supercoil.dna.models import register_model, unregister_model
from supercoil.exceptions import ValidityError


def test_cases_follow_the_registries():
    keys = [k for k, _, _ in family.cases()]
    for name in sc.available_models():
        if sc.dna.models.get_model(name).uses_interaction:
            assert {f"{name}/{i}" for i in sc.dna.interactions.available_interactions()} \
                <= set(keys)
        else:
            assert name in keys


class _Broken(sc.dna.models.Marko2007):
    """A plug-in whose points fail: its row must name the error, not stop the chart."""

    name = "family-broken"

    def _points(self, *args, **kwargs):
        raise ValidityError("family-broken: no points at any force")


@pytest.fixture
def broken():
    register_model(_Broken, replace=True)
    yield
    unregister_model(_Broken.name)


def test_rows_measure_each_model_against_the_reference(broken):
    only = ["li-zhao/hard-core", "marko2007", "family-broken"]
    rows = pd.DataFrame(family.family_precision(turns_points=21, repeat=1, only=only,
                                                reference=("li-zhao", "hard-core")))
    assert list(rows["model"]) == ["family-broken", "li-zhao", "marko2007"]
    by = rows.set_index("model")
    # the reference against itself: zero difference, and a fit of its own data at the noise
    assert by.loc["li-zhao", "extension_error"] == 0.0
    assert by.loc["li-zhao", "fit_rms"] == pytest.approx(5.0, rel=0.3)
    # another construction differs, and both cost a positive CPU time
    assert by.loc["marko2007", "extension_error"] > 1.0
    assert (by.loc[["li-zhao", "marko2007"], ["hat_seconds", "fit_seconds"]] > 0).all().all()
    assert by.loc["family-broken", "status"].startswith("ValidityError: family-broken")
    assert np.isnan(by.loc["family-broken", "extension_error"])
