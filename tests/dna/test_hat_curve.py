"""Hat curves (docs/theory/li-zhao.md): phases, symmetry, continuity, slope, linking, athermal.
"""

import itertools
import warnings

import numpy as np
import pint
import pytest
from hypothesis import given
from hypothesis import strategies as st

import supercoil as sc
from supercoil.core import geometry as g
from supercoil.core.dna import interface as iface
from supercoil.core.dna import li_zhao as hc
from supercoil.core.dna import moroz_nelson as mn
from supercoil.core.dna import plectoneme as pl
from supercoil.dna.hat import buckling_turns, post_buckling_slope
from supercoil.units import BOLTZMANN

KT = BOLTZMANN * 300.0
R0 = 1.75e-9
B = 48e-9 * KT
C = 86e-9 * KT
L = 750e-9
ARGS = (L, B, C, KT, R0)


def points(turns, force, thermal=True, **kw):
    turns = np.asarray(turns, float)
    return hc.hat_curve_points(turns, np.full(turns.shape, force), *ARGS, thermal=thermal, **kw)


@given(st.floats(0.15, 15.0), st.lists(st.floats(0.0, 60.0), min_size=1, max_size=20),
       st.booleans())
def test_symmetric_in_turns(f_pN, n, thermal):
    n = np.array(n)
    p, m = points(n, f_pN * 1e-12, thermal), points(-n, f_pN * 1e-12, thermal)
    np.testing.assert_array_equal(p.extension, m.extension)
    np.testing.assert_array_equal(p.phase, m.phase)
    np.testing.assert_array_equal(p.plectoneme_length, m.plectoneme_length)
    np.testing.assert_array_equal(p.torque, -m.torque)
    assert np.all(p.torque >= 0)


@pytest.mark.parametrize("thermal", [True, False])
@pytest.mark.parametrize("f", [0.2e-12, 0.4e-12, 1.2e-12, 3e-12, 10e-12])
def test_continuous_at_buckling(f, thermal):
    nb = hc.buckling_turns(f, *ARGS, thermal=thermal)[()]
    eps = 1e-7
    p = points([nb - eps, nb + eps], f, thermal)
    assert list(p.phase) == [iface.STRETCHED, iface.PLECTONEME]
    assert abs(p.extension[1] - p.extension[0]) < 1e-12  # a jump would be > 1 nm
    assert p.torque[1] == pytest.approx(p.torque[0], rel=1e-6, abs=0)
    # the torques match at N_b: C_eff 2 pi N_b / L = C omega
    s = pl.equilibrium(f, B, C, KT, R0)
    assert p.torque[1] == pytest.approx(s.torque, rel=1e-12, abs=0)


@pytest.mark.parametrize("thermal", [True, False])
@pytest.mark.parametrize("f", [0.3e-12, 1.2e-12, 3e-12])
def test_slope_formula_equals_finite_difference(f, thermal):
    nb = hc.buckling_turns(f, *ARGS, thermal=thermal)[()]
    slope = hc.post_buckling_slope(f, *ARGS, thermal=thermal)[()]
    n = nb + 3.0
    h = 1e-3
    p = points([n - h, n + h, -n - h, -n + h], f, thermal)
    assert np.all(p.phase == iface.PLECTONEME)
    assert (p.extension[1] - p.extension[0]) / (2 * h) == pytest.approx(slope, rel=1e-7, abs=0)
    assert (p.extension[3] - p.extension[2]) / (2 * h) == pytest.approx(-slope, rel=1e-7, abs=0)
    if not thermal:
        s = pl.equilibrium(f, B, C, KT, R0)
        assert slope == pytest.approx(-2 * np.pi / s.torsion, rel=1e-12, abs=0)


@pytest.mark.parametrize("f", [0.4e-12, 1.2e-12, 3e-12])
def test_linking_number_is_twist_plus_writhe_in_plectoneme_phase(f):
    s = pl.equilibrium(f, B, C, KT, R0)
    nb = hc.buckling_turns(f, *ARGS, thermal=False)[()]
    n = np.linspace(nb + 0.5, nb + 10, 7)
    p = points(n, f, thermal=False)
    assert np.all(p.phase == iface.PLECTONEME)
    S = p.plectoneme_length
    tw = g.twist_uniform(s.omega, s.omega, S, L)
    wr = g.writhe_uniform(s.alpha, s.radius, S)
    np.testing.assert_allclose(tw + wr, n, rtol=1e-12)
    # thermal: the tail holds (C/C_eff) omega of linking per length (twist + tail writhe)
    nb = hc.buckling_turns(f, *ARGS, thermal=True)[()]
    n = np.linspace(nb + 0.5, nb + 10, 7)
    p = points(n, f, thermal=True)
    assert np.all(p.phase == iface.PLECTONEME)
    ratio = mn.twist_rigidity_ratio(f, B, C, KT)
    S = p.plectoneme_length
    tw = g.twist_uniform(s.omega, ratio * s.omega, S, L)
    np.testing.assert_allclose(tw + g.writhe_uniform(s.alpha, s.radius, S), n, rtol=1e-12)


@pytest.mark.parametrize("f", [0.4e-12, 1.2e-12, 3e-12])
def test_athermal_equals_closed_formulas(f):
    s = pl.equilibrium(f, B, C, KT, R0)
    nb = C * s.omega * L / (2 * np.pi * C)
    n = np.linspace(-40, 40, 801)
    p = points(n, f, thermal=False)
    an = np.abs(n)
    S = np.clip(2 * np.pi * (an - nb) / s.torsion, 0, L)
    np.testing.assert_allclose(p.plectoneme_length, S, rtol=1e-12, atol=1e-20)
    np.testing.assert_allclose(p.extension, L - S, rtol=1e-12, atol=1e-20)
    torque = np.where(an <= nb, C * 2 * np.pi * n / L, np.sign(n) * s.torque)
    np.testing.assert_allclose(p.torque, torque, rtol=1e-12)
    np.testing.assert_array_equal(p.zeta, np.where(S >= L, 0.0, 1.0))
    assert hc.buckling_turns(f, *ARGS, thermal=False)[()] == pytest.approx(nb, rel=1e-14, abs=0)


def test_athermal_computes_no_thermal_terms(monkeypatch):
    def boom(*a, **k):
        raise AssertionError("thermal term computed")

    for name in ("twist_rigidity_ratio", "zeta_bracket", "long_tail_factor", "extension_factor"):
        monkeypatch.setattr(mn, name, boom)
    p = points(np.linspace(-30, 30, 61), 1e-12, thermal=False)
    assert np.all(p.extension >= 0)
    with pytest.raises(AssertionError):
        points([0.0], 1e-12, thermal=True)


def test_thermal_stretched_phase_is_zeta_times_length(dna, ureg):
    f = 1.2e-12
    ratio = mn.twist_rigidity_ratio(f, B, C, KT)
    n = np.array([0.0, 1.0, 3.0])
    p = points(n, f)
    M = (C / ratio) * 2 * np.pi * n / L
    z = sc.extension_factor(dna, 1.2 * ureg.pN, M * ureg.N * ureg.m, L * ureg.m).magnitude
    np.testing.assert_allclose(p.extension, z * L, rtol=1e-12)
    assert np.all(p.phase == iface.STRETCHED)


@pytest.mark.parametrize("f", [0.4e-12, 3e-12])
def test_fully_coiled_and_short_tail(f):
    nb = hc.buckling_turns(f, *ARGS)[()]
    D = hc.hat_parameters(np.array([f]), *ARGS).linking_rate[0]
    n_full = nb + L * D / (2 * np.pi)  # S = L
    n = np.array([n_full - 1e-3, n_full + 1e-9, n_full + 1, n_full + 50])
    p = points(n, f)
    assert list(p.phase) == [iface.PLECTONEME] + [iface.FULLY_COILED] * 3
    np.testing.assert_array_equal(p.extension[1:], 0.0)
    np.testing.assert_array_equal(p.plectoneme_length[1:], L)
    assert np.all(p.short_tail)
    # just before S = L the formula is kept as written: z -> B kT/(B T - M^2/4), not 0
    M = pl.equilibrium(f, B, C, KT, R0).torque
    tail = L - p.plectoneme_length[0]
    assert 0 < tail < 1e-10
    limit = B * KT / (B * f - M**2 / 4)
    zinf = mn.long_tail_factor(f, M, B, KT)
    assert p.extension[0] == pytest.approx(zinf * tail + limit, rel=1e-9, abs=0)
    assert limit > (10e-9 if f < 1e-12 else 1e-9)
    # the flag is exactly "tail shorter than 3 A", and its threshold is an argument
    n = np.linspace(nb, n_full, 400)
    p = points(n, f)
    np.testing.assert_array_equal(p.short_tail, (L - p.plectoneme_length) < 3 * B / KT)
    p2 = points(n, f, short_tail_length=50e-9)
    np.testing.assert_array_equal(p2.short_tail, (L - p2.plectoneme_length) < 50e-9)
    assert p2.short_tail.sum() < p.short_tail.sum()


def test_trends_over_forces():
    F = np.linspace(0.3e-12, 10e-12, 40)
    for thermal in (True, False):
        par = hc.hat_parameters(F, *ARGS, thermal=thermal)
        assert np.all(np.diff(par.buckling_turns) > 0)
        assert np.all(np.diff(par.torque) > 0)
    assert np.all(np.diff(pl.equilibrium(F, B, C, KT, R0).radius) < 0)


def test_paired_points_solve_once_per_force_and_match(monkeypatch):
    calls = []
    real = hc.equilibrium

    def counting(force, *a, **k):
        calls.append(np.size(force))
        return real(force, *a, **k)

    monkeypatch.setattr(hc, "equilibrium", counting)
    F = np.array([0.4, 3.0, 1.2, 0.4, 3.0, 1.2]) * 1e-12
    N = np.array([5.0, -12.0, 20.0, -1.0, 0.0, 7.5])
    p = hc.hat_curve_points(N, F, *ARGS)
    assert calls == [3]
    for i in range(F.size):
        q = points([N[i]], F[i])
        for a, b_ in zip(p[:6], q[:6], strict=True):
            assert a[i] == pytest.approx(b_[0], rel=1e-13, abs=1e-30)
    assert p.phase.dtype == np.int8
    assert p.short_tail.dtype == bool


def test_core_failures():
    with pytest.raises(sc.NoEquilibriumError, match="-1 pN"):
        hc.hat_curve_points([1.0], [-1e-12], *ARGS)
    with pytest.raises(sc.ValidityError, match=r"0\.09 pN.*torque"):
        hc.hat_curve_points([10.0], [0.09e-12], *ARGS)
    hc.hat_curve_points([10.0], [0.09e-12], *ARGS, thermal=False)  # athermal is defined
    with pytest.raises(ValueError, match="turns"):
        hc.hat_curve_points([np.nan], [1e-12], *ARGS)
    with pytest.raises(ValueError, match="length"):
        hc.hat_curve_points([1.0], [1e-12], -1.0, B, C, KT, R0)


# ----------------------------------------------------------------- public API


def test_hat_curve_table(dna, ureg):
    df = sc.hat_curve(dna, [0.4, 1.2] * ureg.pN, np.linspace(0, 30, 31))
    assert list(df.columns) == ["force", "turns", "extension", "phase", "torque",
                                "plectoneme_length", "supercoiling_density", "eta",
                                "short_tail"]
    assert df.attrs["units"]["extension"] == "nm"
    assert df.attrs["units"]["torque"] == "pN nm"
    assert df.attrs["units"]["force"] == "pN"
    assert df.attrs["provenance"]["thermal"] is True
    assert set(df["phase"]) == {"stretched", "plectoneme", "fully coiled"}
    assert len(df) == 62
    row = df[(df.force == 1.2) & (df.turns == 10)].iloc[0]
    assert row.supercoiling_density == pytest.approx(10 * 3.57 / 750)
    assert row.eta == pytest.approx(2 * np.pi * 10 * 52 / 750)
    assert (df.loc[df.phase == "fully coiled", "extension"] == 0).all()


def test_hat_curve_unit_invariance(dna, ureg):
    n = np.linspace(-5, 30, 36)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.ValidityWarning)
        a = sc.hat_curve(dna, 1.2 * ureg.pN, n)
        b_ = sc.hat_curve(dna, 1.2e-12 * ureg.N, n * ureg.turn)
        c = sc.hat_curve(dna, 1200 * ureg.fN, 2 * np.pi * n * ureg.rad)
        dna_um = dna.replace(length=0.75 * ureg.um, radius=1750 * ureg.pm)
        d = sc.hat_curve(dna_um, 1.2 * ureg.pN, n)
    for other in (b_, c, d):
        for col in ("extension", "torque", "plectoneme_length", "eta", "turns"):
            np.testing.assert_allclose(other[col], a[col], rtol=1e-10, atol=1e-9)
        assert (other["phase"] == a["phase"]).all()


def test_hat_curve_matches_kernel_and_public_helpers(dna, ureg):
    F = [0.4, 1.2, 3.0] * ureg.pN
    nb = buckling_turns(dna, F)
    slope = post_buckling_slope(dna, F)
    np.testing.assert_allclose(nb.magnitude, hc.buckling_turns(F.m * 1e-12, *ARGS), rtol=1e-12)
    np.testing.assert_allclose(slope.m_as("nm/turn"),
                               hc.post_buckling_slope(F.m * 1e-12, *ARGS) * 1e9, rtol=1e-12)
    assert np.all(np.diff(nb.magnitude) > 0)
    athermal = buckling_turns(dna, F, thermal=False).magnitude
    assert np.all(athermal < nb.magnitude)  # C_eff < C: the tail buckles later


def test_denaturation_warning(dna, ureg):
    with pytest.warns(sc.ValidityWarning, match="denature"):
        sc.hat_curve(dna, 1.2 * ureg.pN, [-5.0, 5.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc.hat_curve(dna, 0.4 * ureg.pN, [-5.0, 5.0])  # below 0.8 pN: no warning
        sc.hat_curve(dna, 3.0 * ureg.pN, [0.0, 5.0])  # positive turns: no warning


def test_low_force_zeta_regions(dna, ureg):
    # 0.09 pN: the bracket is negative at the plectoneme torque
    with pytest.raises(sc.ValidityError, match=r"0\.09 pN"):
        sc.hat_curve(dna, 0.09 * ureg.pN, [0.0, 10.0])
    # still defined in the stretched phase, but the Moroz-Nelson expansion has not converged
    with pytest.warns(sc.ValidityWarning, match="not converged"):
        sc.hat_curve(dna, 0.09 * ureg.pN, [0.0, 0.5])
    # 0.11 pN: bracket positive but the long-tail factor is negative in the
    # plectoneme phase: z would grow with turns
    with pytest.warns(sc.ValidityWarning, match="long-tail factor"):
        df = sc.hat_curve(dna, 0.11 * ureg.pN, [5.0, 6.0])
    assert df.extension.iloc[1] > df.extension.iloc[0]
    # 0.1 pN: zeta itself is negative just past buckling
    with pytest.warns(sc.ValidityWarning, match="outside"):
        sc.hat_curve(dna, 0.1 * ureg.pN, [5.0])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc.hat_curve(dna, 0.25 * ureg.pN, np.linspace(0, 40, 81))


def test_hat_curve_bad_inputs(dna, ureg):
    with pytest.raises(pint.DimensionalityError, match="force"):
        sc.hat_curve(dna, 1.0 * ureg.nm, [1.0])
    with pytest.raises(ValueError, match="turns"):
        sc.hat_curve(dna, 1.0 * ureg.pN, np.ones((2, 2)))
    with pytest.raises(ValueError, match="finite"):
        sc.hat_curve(dna, 1.0 * ureg.pN, [np.inf])
    with pytest.raises(sc.NoEquilibriumError, match="0 pN"):
        sc.hat_curve(dna, 0.0 * ureg.pN, [1.0])
    with pytest.raises(TypeError):
        sc.hat_curve(sc.load_parameters("silicone_rubber_rod"), 1.0 * ureg.pN, [1.0])


def test_turns_valued_outputs_carry_the_turn_unit(dna, ureg):
    """Counts of turns are in pint's ``turn``: no 2 pi trap when converting."""
    nb = buckling_turns(dna, 1.0 * ureg.pN)
    assert nb.to("turn").magnitude == pytest.approx(nb.magnitude)
    assert nb.to("rad").magnitude == pytest.approx(2 * np.pi * nb.magnitude)
    slope = post_buckling_slope(dna, 1.0 * ureg.pN)
    assert slope.to("nm/turn").magnitude == pytest.approx(slope.magnitude)
    df = sc.hat_curve(dna, 1.0 * ureg.pN, [0.0, 10.0])
    assert df.attrs["units"]["turns"] == "turn"
    assert sc.tables.column_quantity(df, "turns").to("turn").magnitude[1] == pytest.approx(10.0)


def test_post_buckling_slope_warns_where_zeta_long_tail_factor_fails(dna, ureg):
    with pytest.warns(sc.ValidityWarning, match="long-tail factor .* <= 0"):
        s = post_buckling_slope(dna, 0.1 * ureg.pN)
    assert s.magnitude[0] > 0  # the unphysical positive slope the warning is about
    with pytest.warns(sc.ValidityWarning, match="not converged"):
        post_buckling_slope(dna, 0.15 * ureg.pN)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        post_buckling_slope(dna, [0.3, 1.0, 3.0] * ureg.pN)


def test_blocked_points_equal_one_block(monkeypatch):
    """Blocked evaluation (bounded temporaries) gives bit-identical points."""
    F = np.repeat(np.array([0.4, 1.2, 3.0]) * 1e-12, 301)
    N = np.tile(np.linspace(-60, 60, 301), 3)
    for thermal in (True, False):
        whole = hc.hat_curve_points(N, F, *ARGS, thermal=thermal)
        monkeypatch.setattr(hc, "BLOCK", 7)
        small = hc.hat_curve_points(N, F, *ARGS, thermal=thermal)
        monkeypatch.setattr(hc, "BLOCK", 1 << 15)
        for a, b in zip(whole, small, strict=True):
            if a is None:
                assert b is None
            else:
                np.testing.assert_array_equal(a, b)


def test_blocked_points_equal_one_block_with_interleaved_forces(monkeypatch):
    """Mixed-force blocks (per-point constants) and one-force blocks give the same points."""
    rng = np.random.default_rng(7)
    F = np.repeat(np.array([0.4, 1.2, 3.0]) * 1e-12, 301)
    N = np.tile(np.linspace(-60, 60, 301), 3)
    order = rng.permutation(F.size)
    whole = hc.hat_curve_points(N, F, *ARGS)
    monkeypatch.setattr(hc, "BLOCK", 5)
    shuffled = hc.hat_curve_points(N[order], F[order], *ARGS)
    for a, b in zip(whole, shuffled, strict=True):
        if a is None:
            assert b is None
        elif isinstance(a, iface.PointSummary):  # reductions over the same points
            np.testing.assert_equal(tuple(b), tuple(a))
        else:
            np.testing.assert_array_equal(a[order], b)


@pytest.mark.parametrize("fast", [False, True])
@pytest.mark.parametrize("thermal", [True, False])
def test_summary_is_the_reductions_of_the_points(thermal, fast):
    """The kernel's block-by-block summary equals the reductions over the whole arrays.

    Blocks of 229 points: 7 full blocks that straddle the forces' boundaries (401 points
    each) and a last block of a single point (1604 = 7 x 229 + 1)."""
    F = np.repeat(np.array([0.15, 0.4, 1.2, 3.0]) * 1e-12, 401)
    N = np.tile(np.linspace(-60, 60, 401), 4)
    for block, short in ((229, None), (hc.BLOCK, None), (229, 0.0)):
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(hc, "BLOCK", block)
            p = hc.hat_curve_points(N, F, *ARGS, thermal=thermal, fast=fast,
                                    short_tail_length=short)
        s = p.summary
        assert s.finite
        assert (s.extension_min, s.extension_max) == (p.extension.min(), p.extension.max())
        assert (s.torque_min, s.torque_max) == (p.torque.min(), p.torque.max())
        assert s.torque_min < 0 < s.torque_max
        assert (s.turns_min, s.turns_max) == (N.min(), N.max())
        over = bool(np.any((p.zeta > 1) & ~p.short_tail))
        assert s.zeta_over_long_tail == over
        if thermal:
            assert s.bracket_min == p.bracket.min()
            # no tail counts as short: zeta > 1 near full coiling (finite-length term)
            assert over == (short == 0.0)
        else:
            assert np.isnan(s.bracket_min) and not over


def test_plectoneme_phase_extension_is_moroz_nelson_at_the_tail(dna, ureg):
    """z = zeta(M_p, L - S) (L - S) against the independent Moroz-Nelson function."""
    f = 1.2e-12
    n = np.array([10.0, 15.0, 20.0])
    p = points(n, f)
    assert np.all(p.phase == iface.PLECTONEME)
    tail = L - p.plectoneme_length
    z = sc.extension_factor(dna, 1.2 * ureg.pN, p.torque * ureg.N * ureg.m,
                            tail * ureg.m).magnitude
    np.testing.assert_allclose(p.zeta, z, rtol=1e-13)
    np.testing.assert_allclose(p.extension, z * tail, rtol=1e-13)
    np.testing.assert_allclose(p.bracket, mn.zeta_bracket(f, p.torque, B, KT), rtol=1e-13)


def test_public_table_is_the_kernel_in_display_units_and_owns_its_columns(dna, ureg):
    """Columns scaled in place from the kernel's arrays: equal to the kernel, no aliasing."""
    si = dna.si
    turns = np.linspace(-30, 30, 241)
    force = np.array([0.4, 3.0])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.ValidityWarning)
        df = sc.hat_curve(dna, force * ureg.pN, turns)
        one = sc.hat_curve(dna, 0.4 * ureg.pN, turns)
    F, N = np.repeat(force * 1e-12, turns.size), np.tile(turns, force.size)
    p = hc.hat_curve_points(N, F, si.length, si.bending_rigidity, si.torsional_rigidity,
                            si.kT, si.radius)
    for col, si_values, factor in (("force", F, 1e12), ("extension", p.extension, 1e9),
                                   ("torque", p.torque, 1e21),
                                   ("plectoneme_length", p.plectoneme_length, 1e9)):
        np.testing.assert_allclose(df[col].to_numpy(), si_values * factor, rtol=1e-15)
    np.testing.assert_array_equal(df["turns"].to_numpy(), N)
    np.testing.assert_array_equal(df["phase"].cat.codes.to_numpy(), p.phase)
    np.testing.assert_array_equal(df["short_tail"].to_numpy(), p.short_tail)
    for table in (df, one):
        arrays = [table[c].to_numpy() for c in table.columns if c != "phase"]
        assert not any(np.shares_memory(a, turns) for a in arrays)
        for i, a in enumerate(arrays):
            assert not any(np.shares_memory(a, b) for b in arrays[i + 1:])
    before = one["turns"].to_numpy().copy()
    turns *= 2.0  # the caller's array is not a column (one force: the no-tile path)
    np.testing.assert_array_equal(one["turns"].to_numpy(), before)
    listed = sc.hat_curve(dna, 0.4 * ureg.pN, [0.0, 5.0, 10.0])  # a fresh array: used as is
    assert list(listed["turns"]) == [0.0, 5.0, 10.0]


def test_scaling_in_place_copies_shared_or_foreign_arrays():
    from supercoil.dna.hat import _Owned

    turns = np.arange(3.0)
    own = _Owned(turns)
    a = np.ones(3)
    assert own.scaled(a, 2.0) is a and a[0] == 2.0  # fresh: in place
    b = own.scaled(a, 3.0)  # the same array for a second field: a copy
    assert b is not a and a[0] == 2.0 and b[0] == 6.0
    assert own.scaled(turns, 2.0) is not turns and turns[1] == 1.0  # the turns column
    view = np.ones(4)[:3]
    assert own.scaled(view, 2.0) is not view and view[0] == 1.0  # not owning its data
    ro = np.ones(3)
    ro.flags.writeable = False
    assert own.scaled(ro, 2.0)[0] == 2.0 and ro[0] == 1.0


def test_peak_memory_of_the_public_table_is_bounded(dna, ureg):
    """Peak traced memory <= 1.5 x the returned table, at 2e5 points."""
    import tracemalloc

    turns = np.linspace(0.0, 25.0, 200_000)
    sc.hat_curve(dna, 1.2 * ureg.pN, turns[:100])  # caches outside the trace
    tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        df = sc.hat_curve(dna, 1.2 * ureg.pN, turns)
        held, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert len(df) == turns.size
    assert df.memory_usage(deep=False, index=False).sum() <= held - base
    assert peak - base <= 1.5 * (held - base)


def test_shared_checks_find_what_their_reductions_skip():
    from supercoil.dna import validity as v

    class Model:
        name = "toy"

    x = np.array([1.0, np.inf, 2.0])
    v.check_finite_output(Model, [1e-12] * 3, {"buckling turns": x}, allow_inf=True)
    with pytest.raises(sc.ValidityError, match=r"toy.*extension = inf.*turns 5"):
        v.check_finite_output(Model, [1e-12] * 3, {"extension": x}, [4.0, 5.0, 6.0])
    with pytest.raises(sc.ValidityError, match="nan"):
        v.check_finite_output(Model, [1e-12] * 3, {"buckling turns": x * np.nan},
                              allow_inf=True)
    si = sc.load_parameters("dna").si
    for z in ([0.0, si.length * 1.01], [-1e-12, 1e-7]):
        pts = iface.HatPoints(np.array(z), *(np.zeros(2),) * 5)
        assert "outside [0, L" in v.extension_messages([1e-12] * 2, [1.0, 2.0], pts, si)[0]
    pts = iface.HatPoints(np.array([0.0, si.length]), *(np.zeros(2),) * 5)
    assert v.extension_messages([1e-12] * 2, [1.0, 2.0], pts, si) == []
    with pytest.raises(ValueError, match="finite"):
        v.checked_turns([1.0, np.nan], si)
    with pytest.raises(ValueError, match="finite"):
        v.checked_turns([-np.inf, 1.0], si)
    with pytest.raises(sc.ValidityError, match="-300"):
        v.checked_turns([1.0, -300.0], si)  # Lk0 = 750 nm / 3.57 nm = 210


def _validity_by_masks(turns, force, p, dna):
    """li-zhao's validity messages by the full masks (the reference of the shortcuts)."""
    from supercoil.dna.models.li_zhao import long_tail_messages

    zeta_bad = ~p.short_tail & ~((p.zeta > 0) & (p.zeta <= 1)) & (p.phase != iface.FULLY_COILED)
    if np.any(zeta_bad):
        i = np.flatnonzero(zeta_bad)[0]
        return [f"Moroz-Nelson zeta = {p.zeta[i]:.4g} lies outside (0, 1] at force "
                f"{force[i] * 1e12:.6g} pN, turns {turns[i]:.6g}: the extension is not "
                "valid there"]
    return long_tail_messages(force, p.bracket, p.phase != iface.FULLY_COILED, turns)


@pytest.mark.parametrize("short", [None, 0.0, 400e-9])
@pytest.mark.parametrize("f_pN", [0.1, 0.13, 0.15, 0.19, 0.3, 1.2, 10.0])
def test_validity_shortcuts_give_the_messages_of_the_full_masks(dna, f_pN, short):
    """The kernel-summary and min-based shortcuts of li-zhao's validity change no message.

    The forces cross the seed set's limits (long-tail factor <= 0 below 0.1218 pN,
    zeta > 1 at a 3 A tail below 0.1354 pN, Q < 1 below 0.201 pN); a short-tail length
    of 0 makes zeta > 1 near full coiling count.
    """
    from supercoil.dna.models import get_model

    model = get_model("li-zhao")
    si = dna.si
    n = np.linspace(-40.0, 40.0, 801)
    f = np.full(n.shape, f_pN * 1e-12)
    with np.errstate(all="ignore"):
        p = hc.hat_curve_points(n, f, si.length, si.bending_rigidity, si.torsional_rigidity,
                                si.kT, si.radius, short_tail_length=short)
        lean = hc.hat_curve_points(n, f, si.length, si.bending_rigidity,
                                   si.torsional_rigidity, si.kT, si.radius,
                                   short_tail_length=short, diagnostics=False)
    assert lean.zeta is None and lean.bracket is None
    for a, b in zip(p[:5], lean[:5], strict=True):  # the same points without the two arrays
        np.testing.assert_array_equal(b, a)
    np.testing.assert_equal(tuple(lean.summary), tuple(p.summary))
    expected = _validity_by_masks(n, f, p, si)
    for q in (p, p._replace(summary=None), lean, lean._replace(summary=None)):
        assert model._validity(n, f, q, si, True) == expected
    if f_pN >= 1.2 and short is None:
        assert expected == []
    if f_pN <= 0.15 or (short == 0.0 and f_pN <= 1.2):
        assert expected != []  # the failure regions are reached


@pytest.mark.parametrize("thermal", [True, False])
def test_one_phase_blocks_equal_the_general_path(monkeypatch, thermal):
    """Blocks all stretched, all plectoneme or all fully coiled (one force, decided on their
    extreme turns) take the hoisted fillers; their points equal the general per-point
    formulas bit for bit, for both signs of N, across the phase boundaries (blocks of 7:
    most uniform, some mixed), at three forces."""
    from supercoil.core.dna import li_zhao_numpy as hb

    F = np.repeat(np.array([0.4, 1.2, 3.0]) * 1e-12, 1201)
    N = np.tile(np.linspace(-60.0, 60.0, 1201), 3)
    monkeypatch.setattr(hc, "BLOCK", 7)
    kinds = []
    one_phase = hb.one_phase
    monkeypatch.setattr(hb, "one_phase", lambda *a: kinds.append(one_phase(*a)) or kinds[-1])
    fast = hc.hat_curve_points(N, F, *ARGS, thermal=thermal, fast=False)
    assert {iface.STRETCHED, iface.PLECTONEME, iface.FULLY_COILED, None} <= set(kinds)
    monkeypatch.setattr(hb, "one_phase", lambda *a: None)
    general = hc.hat_curve_points(N, F, *ARGS, thermal=thermal, fast=False)
    for name, a, b in zip(general._fields, general, fast, strict=True):
        if isinstance(a, np.ndarray):
            assert a.dtype == b.dtype, name
            np.testing.assert_array_equal(b, a, err_msg=name)
    np.testing.assert_equal(tuple(fast.summary), tuple(general.summary))


@pytest.mark.parametrize("block", [37, 229, 1 << 15])
def test_points_without_diagnostics_and_on_broadcast_forces_are_the_same(block, monkeypatch):
    """``diagnostics=False`` (no zeta/bracket kept: the one-phase fillers skip their
    fills and take zeta's largest value from the shortest tail) and one force broadcast
    over the points (stride 0, read once) give the same points and summary, bit for bit,
    with and without short tails (zeta > 1 near full coiling when none counts as short)."""
    monkeypatch.setattr(hc, "BLOCK", block)
    seen_over = 0
    for f in (0.15e-12, 0.4e-12, 1.2e-12, 3.0e-12):
        par = hc.hat_parameters(np.array([f]), *ARGS)
        n_coiled = (par.buckling_turns + L * par.linking_rate / (2 * np.pi))[0]
        # the whole curve, and plectoneme points only, down to a tail of ~0
        near_coiled = n_coiled - np.geomspace(1.0, 1e-9, 800)
        for N, short in itertools.product((np.linspace(-60, 60, 4001), near_coiled),
                                          (None, 0.0)):
            ref = hc.hat_curve_points(N, np.full(N.shape, f), *ARGS, short_tail_length=short)
            lean = hc.hat_curve_points(N, np.broadcast_to(f, N.shape), *ARGS,
                                       short_tail_length=short, diagnostics=False)
            assert lean.zeta is None and lean.bracket is None
            for name in ("extension", "torque", "plectoneme_length", "phase", "short_tail"):
                np.testing.assert_array_equal(getattr(lean, name), getattr(ref, name))
            np.testing.assert_equal(tuple(lean.summary), tuple(ref.summary))
            over = bool(np.any((ref.zeta > 1) & ~ref.short_tail))
            assert lean.summary.zeta_over_long_tail == ref.summary.zeta_over_long_tail == over
            if N is near_coiled:
                assert np.all(ref.phase == iface.PLECTONEME)
                seen_over += over
    assert seen_over >= 2, "plectoneme blocks with zeta > 1 at a long tail: not exercised"
    with pytest.raises(ValueError, match="force must be finite"):
        hc.hat_curve_points(N, np.broadcast_to(np.nan, N.shape), *ARGS)
