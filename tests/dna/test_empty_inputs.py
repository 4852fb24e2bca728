"""Issue 20, item 3: empty force or turns arrays give empty results for every model.

On main the models reduced over zero-size arrays (``zero-size array to
reduction operation minimum``, an IndexError for ``"free-energy"``); 0.1
returned an empty table. One path now (``supercoil.dna.hat``): no point, no
model call, an empty result of the same columns, dtypes and units.
"""

import numpy as np
import pytest

import supercoil as sc

u = sc.ureg
EMPTY = np.array([]) * u.pN
CASES = [("li-zhao", "hard-core"), ("li-zhao", "screened"), ("free-energy", "hard-core"),
         ("free-energy", "screened"), ("marko2007", "hard-core")]


@pytest.fixture(scope="module")
def salty():
    return sc.load_parameters("dna_150mM_nacl")


@pytest.mark.parametrize(("model", "interaction"), CASES)
@pytest.mark.parametrize("which", ["force", "turns", "both"])
def test_an_empty_hat_curve_has_the_columns_and_units_of_a_full_one(salty, model,
                                                                    interaction, which):
    force = EMPTY if which in ("force", "both") else 1.0 * u.pN
    turns = [] if which in ("turns", "both") else [0, 5]
    ref = sc.hat_curve(salty, 1.0 * u.pN, [0, 5], model=model, interaction=interaction)
    t = sc.hat_curve(salty, force, turns, model=model, interaction=interaction)
    assert len(t) == 0
    assert list(t.columns) == list(ref.columns)
    assert (t.dtypes == ref.dtypes).all()
    assert t.attrs["units"] == ref.attrs["units"]
    assert t.attrs["provenance"]["model"] == model


@pytest.mark.parametrize(("model", "interaction"), CASES)
def test_empty_forces_give_empty_buckling_turns_and_slopes(salty, model, interaction):
    kw = dict(model=model, interaction=interaction)
    b = sc.buckling_turns(salty, EMPTY, **kw)
    s = sc.post_buckling_slope(salty, EMPTY, **kw)
    assert b.shape == (0,) and str(b.units) == "turn"
    assert s.shape == (0,) and s.units == u.nm / u.turn
    assert sc.plectoneme_equilibrium(salty, EMPTY, interaction=interaction).radius.shape == (0,)


@pytest.mark.parametrize("model", ["free-energy", "marko2007"])
def test_empty_free_energy_is_empty_but_li_zhao_still_has_none(salty, model):
    assert sc.free_energy(salty, EMPTY, [0, 5], model=model).shape == (0,)
    assert sc.free_energy(salty, 1 * u.pN, [], model=model).units == u.pN * u.nm
    with pytest.raises(sc.ModelError, match="free energy"):
        sc.free_energy(salty, EMPTY, [0, 5], model="li-zhao")  # asking the wrong model
