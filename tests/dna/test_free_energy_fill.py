"""The run-by-run filler of one-force blocks (supercoil.core.dna.free_energy_fill).

Reference: the general path of :func:`supercoil.core.dna.free_energy.hat_points` (every
block through ``_assemble``, the filler switched off), whose physics the other
free-energy tests check. The filler does the same operations in the same order, so every
field must be equal bit for bit, in every phase and for every way the fully coiled
points are solved (the call's inverse table, Newton on the series, the secant).
"""

import numpy as np
import pytest
from seed_kernels import equilibrium_of

from supercoil.core.dna import coiled_table as ct
from supercoil.core.dna import free_energy as fe
from supercoil.core.dna import free_energy_fill as ff
from supercoil.core.dna.interface import FULLY_COILED, PLECTONEME, STRETCHED


def _both(monkeypatch, turns, force, si, thermal, memo=None):
    """``(filled, general)`` hat points of one call, and how many blocks the filler took."""
    L, B, C, kT, _ = si
    eq = equilibrium_of(si)
    taken = []
    fill = ff.fill

    def counting(*a, **k):
        done = fill(*a, **k)
        taken.append(done)
        return done

    with monkeypatch.context() as m:
        m.setattr(ff, "fill", counting)
        new = fe.hat_points(turns, force, L, B, C, kT, eq, thermal,
                            memo=None if memo is None else {})
    with monkeypatch.context() as m:
        m.setattr(ff, "fill", lambda *a, **k: False)
        old = fe.hat_points(turns, force, L, B, C, kT, eq, thermal,
                            memo=None if memo is None else {})
    return new, old, sum(taken)


def _assert_identical(new, old):
    for name, a, b in zip(new._fields, new, old, strict=True):
        assert a.dtype == b.dtype, name
        assert np.array_equal(a, b), (name, np.max(np.abs(a.astype(float) - b)))


def _coiled_turns(si, force):
    L, B, C, kT, _ = si
    co = fe.coexistence(np.array([force]), L, B, C, kT, equilibrium_of(si))
    return float(co.buckling_turns[0] + L * co.linking_rate[0] / (2 * np.pi))


@pytest.mark.parametrize("thermal", [True, False])
@pytest.mark.parametrize("force", [0.3e-12, 1.2e-12, 6e-12])
def test_one_force_hat_curve_bit_for_bit(monkeypatch, si, thermal, force):
    """All three phases, blocks of one phase and blocks that mix them (inverse table)."""
    n = 3 * fe.BLOCK + 17
    turns = np.linspace(-1.7 * _coiled_turns(si, force), 1.7 * _coiled_turns(si, force), n)
    new, old, taken = _both(monkeypatch, turns, np.full(n, force), si, thermal)
    assert taken == 4  # every block run by run
    assert {STRETCHED, PLECTONEME, FULLY_COILED} <= set(np.unique(new.phase))
    _assert_identical(new, old)


def test_one_force_broadcast_over_the_points_gives_the_same_points(si):
    """One force as a stride-0 view (as the public layer passes it, read once) and the
    same force written out: the same points, bit for bit; a broadcast NaN is named."""
    L, B, C, kT, _ = si
    eq = equilibrium_of(si)
    f = 1.2e-12
    turns = np.linspace(-1.3 * _coiled_turns(si, f), 1.3 * _coiled_turns(si, f), 5001)
    full = fe.hat_points(turns, np.full(turns.size, f), L, B, C, kT, eq, True)
    view = fe.hat_points(turns, np.broadcast_to(f, turns.shape), L, B, C, kT, eq, True)
    _assert_identical(view, full)
    with pytest.raises(ValueError, match="must be finite"):
        fe.hat_points(turns, np.broadcast_to(np.nan, turns.shape), L, B, C, kT, eq, True)


@pytest.mark.parametrize("excess, branch", [(1.0, "secant"), (1.05, "series")])
def test_few_coiled_points_bit_for_bit(monkeypatch, si, excess, branch):
    """Few fully coiled points (the secant) and fewer than the inverse needs (Newton)."""
    force = 1.2e-12
    top = excess * _coiled_turns(si, force)
    n = {"secant": 20001, "series": 40001}[branch]
    turns = np.linspace(-top, top, n)
    new, old, taken = _both(monkeypatch, turns, np.full(n, force), si, True)
    coiled = np.count_nonzero(new.phase == FULLY_COILED)
    if branch == "secant":
        assert 0 < coiled < ct.MIN_POINTS
    else:
        assert ct.MIN_POINTS <= coiled < ct.INVERSE_MIN_POINTS
    assert taken == -(-n // fe.BLOCK)
    _assert_identical(new, old)


def test_force_major_table_and_memo_bit_for_bit(monkeypatch, si):
    """Several forces: one-force blocks run by run, the seams by the general path; with a
    fit's memo (its C-free branch table) too."""
    forces = np.array([0.5e-12, 1.2e-12, 3e-12])
    per = 40000
    turns = np.tile(np.linspace(-45, 45, per), forces.size)
    force = np.repeat(forces, per)
    for memo in (None, {}):
        new, old, taken = _both(monkeypatch, turns, force, si, True, memo)
        assert taken == 2  # the first and last blocks; the two with a seam: general path
        _assert_identical(new, old)
    shuffled = np.random.default_rng(3).permutation(turns.size)
    new, old, taken = _both(monkeypatch, turns[shuffled], force[shuffled], si, True)
    assert taken == 0
    _assert_identical(new, old)


def test_shuffled_one_force_falls_back(monkeypatch, si):
    """Phases not contiguous: the general path fills the block (same points)."""
    turns = np.random.default_rng(7).uniform(-40, 40, 5000)
    new, old, taken = _both(monkeypatch, turns, np.full(turns.size, 1.2e-12), si, True)
    assert taken == 0
    _assert_identical(new, old)


def test_first_coiled_is_the_general_paths_test(si):
    """The fully coiled threshold on |N| (free_energy_fill.first_coiled) classifies every
    point as the general path's ``(|N| - N_b) 2 pi / D >= L`` does, at the 40 floats on
    either side of it, for the seed set's forces and 300 random (N_b, 2 pi / D, L)."""
    L, B, C, kT, _ = si
    co = fe.coexistence(np.array([0.3e-12, 1.2e-12, 6e-12]), L, B, C, kT, equilibrium_of(si))
    rng = np.random.default_rng(11)
    cases = [(nb, 2 * np.pi / D, L) for nb, D in zip(co.buckling_turns, co.linking_rate,
                                                      strict=True)]
    cases += list(zip(rng.uniform(0, 100, 300), 10.0 ** rng.uniform(-12, -6, 300),
                      10.0 ** rng.uniform(-7, -4, 300), strict=True))
    for Nb, per_turn, length in cases:
        top = ff.first_coiled(Nb, per_turn, length)
        n = np.full(81, top)
        for k in range(40):  # the floats next to the threshold, below and above
            n[39 - k] = np.nextafter(n[40 - k], -np.inf)
            n[41 + k] = np.nextafter(n[40 + k], np.inf)
        S = np.subtract(n, Nb) * per_turn
        assert np.array_equal(S >= length, n >= top), (Nb, per_turn, length)
        assert S[40] >= length > S[39]


def test_runs():
    """A mask's True points as at most two slices (one at each end), or False."""
    m = np.zeros(10, bool)
    assert ff.runs(m) == []
    m[3:7] = True
    assert ff.runs(m) == [slice(3, 7)]
    m[9] = True
    assert ff.runs(m) is False
    m[3:7] = False
    m[:2] = True
    assert ff.runs(m) == [slice(0, 2), slice(9, 10)]
    m[5] = True
    assert ff.runs(m) is False
    assert ff.runs(np.ones(4, bool)) == [slice(0, 4)]


def test_tail_torque_in_place_is_the_newton(si):
    """The in-place Newton is :func:`free_energy.tail_torque`, bit for bit, up to the
    bracket's edge (v -> 1, where the stopping bound is loosest)."""
    L, B, C, kT, _ = si
    up_to_buckling = np.linspace(0.0, 0.99, 5001) * 2 * np.pi * 8 / L
    for x in (up_to_buckling, np.geomspace(1e3, 5e7, 301)):
        work = [np.empty(x.size) for _ in range(4)]
        ref = fe.tail_torque(x, 1.2e-12, B, C, kT)
        got = ff.tail_torque(x, 1.2e-12, B, C, kT, np.empty(x.size), work)
        assert np.array_equal(got, ref)


def test_stacked_series_evaluate_bit_for_bit():
    """Two series in one Clenshaw recurrence (numerics.stacked), of unequal degrees, give
    each series' chebval exactly."""
    from numpy.polynomial import chebyshev as ch

    from supercoil.core.numerics import stacked

    rng = np.random.default_rng(5)
    t = np.concatenate([np.linspace(-1, 1, 2001), [-1.0, 0.0, 1.0]])
    for na, nb in ((33, 32), (17, 17), (2, 1), (1, 5), (65, 3), (3, 2)):
        a, b = rng.normal(size=na), rng.normal(size=nb)
        got = ch.chebval(t, stacked(a, b))
        assert np.array_equal(got[0], ch.chebval(t, a))
        assert np.array_equal(got[1], ch.chebval(t, b))


@pytest.mark.parametrize("degree", [0, 1, 2, 8, 32, 64, 128])
def test_chebval_rows_equals_clenshaw(degree):
    """The polynomial rows and one matrix product (numerics.chebval_rows) give numpy's
    Clenshaw sums of every stacked series, at the domain's ends too: a decaying series (as
    the branch's) to 16 ulp of its largest value, any series within the sums' rounding
    bound (degree + 1) eps sum|c| (measured: at most 7 ulp, and 20 ulp of sum|c|)."""
    from numpy.polynomial import chebyshev as ch

    from supercoil.core.numerics import chebval_rows, stacked

    rng = np.random.default_rng(degree)
    t = np.concatenate([np.linspace(-1, 1, 2049), [-1.0, 0.0, 1.0]])
    # a decaying series (as the branch's) and a flat one (the worst case for the sum)
    series = [rng.normal(size=degree + 1) * 0.7 ** np.arange(degree + 1),
              rng.normal(size=degree + 1), rng.normal(size=max(degree // 2, 1))]
    got = chebval_rows(t, stacked(*series))
    assert got.shape == (3, t.size)
    eps = np.finfo(float).eps
    for k, (g, c) in enumerate(zip(got, series, strict=True)):
        err = np.max(np.abs(g - ch.chebval(t, c)))
        assert err <= (degree + 1) * eps * np.sum(np.abs(c)), (degree, k)
        if k == 0:
            assert err <= 16 * eps * np.max(np.abs(ch.chebval(t, c))), degree


@pytest.mark.parametrize("thermal", [True, False])
def test_few_coiled_points_solved_once_bit_for_bit(monkeypatch, si, thermal):
    """A one-force call with a few fully coiled points in several blocks: their secant
    runs once for the call (coiled_points.Few), with the states the secant of each block
    gives (the reference: Few switched off)."""
    from supercoil.core.dna import coiled_points as cp

    L, B, C, kT, _ = si
    eq = equilibrium_of(si)
    co = fe.coexistence(np.array([1.2e-12]), L, B, C, kT, eq, thermal)
    top = 1.00003 * float(co.buckling_turns[0] + L * co.linking_rate[0] / (2 * np.pi))
    turns = np.linspace(-top, top, 2 * fe.BLOCK + 5)
    force = np.full(turns.size, 1.2e-12)
    secant, calls = ct.secant, []
    monkeypatch.setattr(ct, "secant", lambda *a, **k: calls.append(1) or secant(*a, **k))
    new = fe.hat_points(turns, force, L, B, C, kT, eq, thermal)
    once = len(calls)
    with monkeypatch.context() as m:
        m.setattr(cp, "_few", lambda *a: None)
        old = fe.hat_points(turns, force, L, B, C, kT, eq, thermal)
    coiled = np.count_nonzero(new.phase == FULLY_COILED)
    assert 2 <= coiled < ct.MIN_POINTS
    assert once == 1 and len(calls) == 3  # once for the call; the two end blocks' own
    _assert_identical(new, old)


@pytest.mark.parametrize("force", [0.15e-12, 0.3e-12, 1.2e-12, 6e-12, 40e-12])
def test_one_force_pull_on_floats_is_the_array_newton(si, force):
    """free_energy._pull at one force runs on floats (_pull_one): the array Newton's
    pull, torque, torsion and bracket bit for bit (the array path: two equal forces)."""
    _, B, C, kT, _ = si
    eq = equilibrium_of(si)
    one = fe._pull(np.array([force]), B, C, kT, eq)
    two = fe._pull(np.array([force, force]), B, C, kT, eq)
    for a, b in zip(one, two, strict=True):
        assert a.shape == (1,) and np.array_equal(a, b[:1]), (a, b)


def test_one_force_pull_errors_are_the_array_ones(si):
    """Where a check fails the float pull hands over to the array one, which names it."""
    from supercoil.exceptions import ValidityError

    L, B, C, kT, _ = si
    eq = equilibrium_of(si)
    for f, text in ((0.05e-12, "no positive tension"), (60e-12, "bracket")):
        with pytest.raises(ValidityError, match=text):
            fe.coexistence(np.array([f]), L, B, C, kT, eq)
