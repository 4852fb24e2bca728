"""The screened branch solved on part of its grid (core.dna.equilibrium.branch_table's
``grid_end``, and the interaction's memory of the last branch's end).

Reference: the table on the whole grid. Each radius's tilt is its own bracketed solve and
the branch ends at the first radius where T stops decreasing, so a partial grid that holds
the end gives the same table bit for bit; one that does not falls back to the whole grid.
"""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import supercoil as sc
from supercoil.core.dna import equilibrium as eq
from supercoil.dna.interactions import get_interaction
from supercoil.dna.interactions import screened as scr


def _setup(salt_mM, **options):
    dna = sc.load_parameters("dna_150mM_nacl").replace(salt=salt_mM * sc.ureg.mM).si
    inter = get_interaction("screened", **options)
    si, lam, pref = inter.screening_functions(dna)
    args = (si.kT, lam, pref, inter.values["confinement"], inter.values["hard_core_radius"])
    return si.bending_rigidity, args


def _same(a, b):
    return (all(np.array_equal(x, y) for x, y in zip(a[:3], b[:3], strict=True))
            and a[3:] == b[3:])


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize(("salt", "options"), [(150, {}), (5, {}), (1000, {}),
                                               (150, {"confinement": 0.0})])
def test_a_partial_grid_gives_the_whole_grids_table(salt, options):
    """At the end the grid needs, short of it (the fallback), past the grid, and for the
    fold of low salt (5 mM) and the cut at 1 fN without confinement."""
    B, args = _setup(salt, **options)
    a = args[-1]
    part = scr.partials_function(B, *args[:-1])
    ref = eq.branch_table(B, part, a, 1000 * a)
    end = eq.grid_end_of(ref, a, 1000 * a)
    if options:  # cut where T fell below 1 fN: only the whole grid tells (no hint)
        assert not ref.ends_at_zero and end is None
        end = 60
    for grid_end in (end, end - 8, 3, 2, eq._TABLE_POINTS, 10_000):
        assert _same(eq.branch_table(B, part, a, 1000 * a, grid_end=grid_end), ref), grid_end
    if salt == 5:
        assert ref.fold  # the refined maximum of T is reproduced too


@pytest.mark.filterwarnings("ignore")
def test_the_interaction_reuses_the_last_end_for_a_new_bending_rigidity(monkeypatch):
    """A fit's new B: the grid up to the last branch's end (plus 8 radii), the same table as
    a cold build."""
    B, args = _setup(150)
    a = args[-1]
    seen, built = [], eq.branch_table

    def spy(*p, **k):
        seen.append(k.get("grid_end"))
        return built(*p, **k)

    monkeypatch.setattr(scr._eq, "branch_table", spy)
    monkeypatch.setattr(scr, "_GRID_ENDS", {})
    first = scr.stable_branch.__wrapped__(B, *args)
    for factor in (1.001, 1.05, 0.9):
        got = scr.stable_branch.__wrapped__(B * factor, *args)
        part = scr.partials_function(B * factor, *args[:-1])
        assert _same(got, built(B * factor, part, a, 1000 * a))
    assert seen[0] is None and seen[1] == eq.grid_end_of(first, a, 1000 * a)
    assert all(e is not None and e < eq._TABLE_POINTS // 2 for e in seen[1:])


@pytest.mark.filterwarnings("ignore")
@pytest.mark.parametrize(("salt", "options"), [(150, {}), (10, {}),
                                               (150, {"confinement": 0.0})])
def test_contact_tables_reuse_the_b_free_electrostatics_bit_for_bit(salt, options):
    """The interaction's contact table for each B takes the electrostatic partials on the
    table's tilts from one B-free evaluation: the same table as with the plain partials."""
    from supercoil.core.dna import contact as ct

    B, args = _setup(salt, **options)
    a = args[-1]
    scr._contact_electrostatics.cache_clear()
    for factor in (1.0, 1.05, 0.8):
        got = scr._contact.__wrapped__(B * factor, *args)
        ref = ct.contact_table(B * factor, scr.partials_function(B * factor, *args[:-1]), a)
        assert (got is None) == (ref is None)
        if ref is not None:
            assert got.radius == ref.radius
            for x, y in zip(got[1:], ref[1:], strict=True):
                assert np.array_equal(x, y)
    assert scr._contact_electrostatics.cache_info().misses == 1


@pytest.mark.filterwarnings("ignore")
@settings(max_examples=8)
@given(salt=st.sampled_from([5.0, 30.0, 150.0, 1000.0]), factor=st.floats(0.5, 2.0),
       grid_end=st.integers(2, 260))
def test_any_grid_end_gives_the_whole_grids_table(salt, factor, grid_end):
    """Property: whatever part of the grid is tried first, the table is the whole grid's."""
    B, args = _setup(salt)
    a = args[-1]
    part = scr.partials_function(B * factor, *args[:-1])
    ref = eq.branch_table(B * factor, part, a, 1000 * a)
    assert _same(eq.branch_table(B * factor, part, a, 1000 * a, grid_end=grid_end), ref)
