"""Plectoneme equilibrium (docs/theory/plectoneme.md#equations).

Residuals, branch, trends, units, failures.
"""

import warnings

import numpy as np
import pint
import pytest
from hypothesis import given
from hypothesis import strategies as st

import supercoil as sc
from supercoil.core import geometry as g
from supercoil.core.dna import hard_core_equations as pr
from supercoil.core.dna import marko_siggia as ms
from supercoil.core.dna import plectoneme as pl
from supercoil.units import BOLTZMANN

KT = BOLTZMANN * 300.0
R0 = 1.75e-9
B = 48e-9 * KT
C = 86e-9 * KT
b = B / (KT * R0)


def test_residuals_below_1e_10_at_many_forces():
    F = np.geomspace(0.05e-12, 20e-12, 300)
    s = pl.equilibrium(F, B, C, KT, R0)
    for res in pl.hard_core_residuals(F, s.alpha, s.radius, s.omega, B, C, KT, R0):
        assert np.max(np.abs(res)) < 1e-10


@given(st.floats(0.03, 200.0), st.floats(20.0, 100.0), st.floats(30.0, 150.0),
       st.floats(1.0, 3.0))
def test_residuals_for_other_parameters(f_pN, A_nm, Ct_nm, r0_nm):
    B_, C_, r0 = A_nm * 1e-9 * KT, Ct_nm * 1e-9 * KT, r0_nm * 1e-9
    f = f_pN * 1e-12
    s = pl.equilibrium(f, B_, C_, KT, r0)
    res = pl.hard_core_residuals(f, s.alpha, s.radius, s.omega, B_, C_, KT, r0)
    assert max(abs(float(r)) for r in res) < 1e-10
    assert 0 < s.alpha < np.pi / 4


def test_residuals_detect_a_wrong_solution():
    s = pl.equilibrium(1e-12, B, C, KT, R0)
    res = pl.hard_core_residuals(1e-12, s.alpha * (1 + 1e-6), s.radius, s.omega, B, C, KT, R0)
    assert max(abs(float(r)) for r in res) > 1e-8


def test_reduced_forms_equal_general_equations():
    a = np.linspace(0.2, 0.75, 9)[:, None]
    rho = np.linspace(0.8, 4.0, 7)[None, :]
    R = rho * R0
    k, t = g.curvature(a, R), g.torsion(a, R)
    k_a, k_r = g.curvature_partials(a, R)
    t_a, t_r = g.torsion_partials(a, R)
    w = ms.interaction(a, R, B, KT, R0)
    w_a, w_r = ms.interaction_partials(a, R, B, KT, R0)
    X, Y = B * k * k_a + w_a, B * k * k_r + w_r
    ge2 = t_r * X - t_a * Y
    np.testing.assert_allclose(pl.reduced_ge2(a, rho, b), -(rho**4) * ge2 * R0**3 / KT,
                               rtol=1e-10, atol=1e-12)
    M = X / t_a  # (GE1)
    T = -0.5 * B * k * k + M * t - w
    np.testing.assert_allclose(pl.reduced_tension(a, rho, b), T * R0 / KT, rtol=1e-10)
    np.testing.assert_allclose(pl.reduced_torque(a, rho, b), M / KT, rtol=1e-12)


@given(st.floats(0.2, 0.78), st.floats(0.6, 5.0))
def test_reduced_derivatives_match_finite_differences(a, rho):
    _, h_a, h_r = pl.reduced_ge2(a, rho, b, derivatives=True)
    _, T_a, T_r = pl.reduced_tension(a, rho, b, derivatives=True)
    da, dr = 1e-7, 1e-7 * rho
    for f, fa, fr in ((pl.reduced_ge2, h_a, h_r), (pl.reduced_tension, T_a, T_r)):
        fd_a = (f(a + da, rho, b) - f(a - da, rho, b)) / (2 * da)
        fd_r = (f(a, rho + dr, b) - f(a, rho - dr, b)) / (2 * dr)
        scale = abs(f(a, rho, b)) + abs(fa) + abs(fr) * rho
        assert fa == pytest.approx(fd_a, rel=1e-5, abs=1e-7 * scale)
        assert fr == pytest.approx(fd_r, rel=1e-5, abs=1e-7 * scale)


def test_ge2_has_one_root_in_alpha_for_every_radius():
    rho = np.geomspace(0.5, 1e3, 200)
    a = np.linspace(1e-6, np.pi / 4, 4001)[:, None]
    h = pl.reduced_ge2(a, rho[None, :], b)
    changes = np.sum(np.diff(np.sign(h), axis=0) != 0, axis=0)
    assert np.all(changes == 1)
    assert np.all(pl.reduced_ge2(np.linspace(np.pi / 4, 1.5, 50)[:, None], rho, b) > 0)


def test_positive_force_has_exactly_one_solution_on_the_ge2_curve():
    """Scan the whole (GE2) curve: T' - T has one sign change, at the solution."""
    rho = np.geomspace(0.5, 1e4, 20000)
    a = pl.reduced_tilt(rho, b)
    T_curve = pl.reduced_tension(a, rho, b)
    for f in (0.05e-12, 0.4e-12, 3e-12, 20e-12):
        d = T_curve - f * R0 / KT
        idx = np.flatnonzero(np.diff(np.sign(d)) != 0)
        assert idx.size == 1
        s = pl.equilibrium(f, B, C, KT, R0)
        assert rho[idx[0]] <= s.radius / R0 <= rho[idx[0] + 1]
    # the entropic branch (large R) carries only negative tensions
    assert np.all(T_curve[rho > 2.0] < 0)


def test_solution_is_a_minimum_of_the_energy_at_fixed_torque():
    """Stable branch: f = B kappa^2/2 + w - M tau has a local minimum in (alpha, R)."""
    for f in (0.1e-12, 1.2e-12, 10e-12):
        s = pl.equilibrium(f, B, C, KT, R0)
        M = s.torque

        def energy(a, R, M=M):
            k, t = g.curvature(a, R), g.torsion(a, R)
            return 0.5 * B * k * k + ms.interaction(a, R, B, KT, R0) - M * t

        a0, R0_ = s.alpha, s.radius
        f0 = energy(a0, R0_)
        assert -f0 == pytest.approx(f, rel=1e-9, abs=0)  # T = -min f
        for th in np.linspace(0, 2 * np.pi, 16, endpoint=False):
            da, dR = 1e-3 * np.cos(th), 1e-3 * R0_ * np.sin(th)
            assert energy(a0 + da, R0_ + dR) > f0


def test_geometry_independent_of_C_and_omega_is_torque_over_C():
    s1 = pl.equilibrium(1e-12, B, C, KT, R0)
    s2 = pl.equilibrium(1e-12, B, 2 * C, KT, R0)
    assert s1.alpha == pytest.approx(s2.alpha, rel=1e-13, abs=0)
    assert s1.torque == pytest.approx(s2.torque, rel=1e-13, abs=0)
    assert s1.omega == pytest.approx(2 * s2.omega, rel=1e-13)
    assert s1.pitch == pytest.approx(2 * np.pi * s1.radius / np.tan(s1.alpha), rel=1e-6, abs=0)


def test_vectorised_equals_scalar():
    F = np.array([[0.1, 0.5], [2.0, 15.0]]) * 1e-12
    s = pl.equilibrium(F, B, C, KT, R0)
    assert s.alpha.shape == (2, 2)
    for i in range(2):
        for j in range(2):
            sj = pl.equilibrium(F[i, j], B, C, KT, R0)
            assert sj.radius == pytest.approx(s.radius[i, j], rel=1e-12, abs=0)


def test_trends_radius_falls_torque_rises_with_force():
    F = np.linspace(0.3e-12, 10e-12, 60)
    s = pl.equilibrium(F, B, C, KT, R0)
    assert np.all(np.diff(s.radius) < 0)
    assert np.all(np.diff(s.torque) > 0)
    assert np.all(np.diff(s.alpha) > 0)
    assert np.all(np.diff(s.pitch) < 0)


def test_seed_values(dna, ureg):
    """Values reported in the issue (regression guard, 1e-6)."""
    eq = sc.plectoneme_equilibrium(dna, [0.4, 1.2, 3.0] * ureg.pN)
    np.testing.assert_allclose(eq.radius.m_as("nm"), [2.493320, 2.299074, 2.134184], rtol=1e-6)
    np.testing.assert_allclose(eq.torque.m_as("pN nm"), [10.94896, 16.30922, 26.57575],
                               rtol=1e-6)
    np.testing.assert_allclose(np.degrees(eq.alpha.m_as("rad")), [21.45410, 23.71374, 26.71275],
                               rtol=1e-6)


def test_public_wrapper_units_and_invariance(dna, ureg):
    a = sc.plectoneme_equilibrium(dna, 1.2 * ureg.pN)
    b_ = sc.plectoneme_equilibrium(dna, 1.2e-12 * ureg.N)
    c = sc.plectoneme_equilibrium(dna, 1200 * ureg.fN)
    for x, y, z in zip(a, b_, c, strict=True):
        assert x.to(y.units).magnitude == pytest.approx(y.magnitude, rel=1e-12, abs=0)
        assert x.to(z.units).magnitude == pytest.approx(z.magnitude, rel=1e-12, abs=0)
    assert a.torque.check("[energy]")
    assert a.radius.check("[length]")
    assert a.omega.check("1/[length]")
    assert a.bending_energy.check("[force]")
    # (GE1): torque = C omega
    assert a.torque.to("pN nm").magnitude == pytest.approx(
        (dna.torsional_rigidity * a.omega).to("pN nm").magnitude, rel=1e-12)
    # energy densities consistent with the tension equation
    T = -a.bending_energy + a.torque * a.torsion - a.interaction_energy
    assert T.to("pN").magnitude == pytest.approx(1.2, rel=1e-10)


def test_no_equilibrium_is_named(dna, ureg):
    with pytest.raises(sc.NoEquilibriumError, match="0 pN"):
        sc.plectoneme_equilibrium(dna, 0 * ureg.pN)
    with pytest.raises(sc.NoEquilibriumError, match="-1 pN"):
        sc.plectoneme_equilibrium(dna, [1.0, -1.0] * ureg.pN)
    with pytest.raises(sc.NoEquilibriumError, match="1e\\+06 pN"):
        sc.plectoneme_equilibrium(dna, 1e6 * ureg.pN)


def test_bad_inputs(dna, ureg):
    with pytest.raises(pint.DimensionalityError, match="force"):
        sc.plectoneme_equilibrium(dna, 1.0 * ureg.nm)
    with pytest.raises(pint.DimensionalityError):
        sc.plectoneme_equilibrium(dna, 1.0)
    with pytest.raises(ValueError, match="finite"):
        sc.plectoneme_equilibrium(dna, np.nan * ureg.pN)
    with pytest.raises(TypeError, match="DNA"):
        sc.plectoneme_equilibrium(sc.load_parameters("silicone_rubber_rod"), 1 * ureg.pN)


@given(st.floats(0.2, 0.78), st.floats(0.6, 5.0), st.floats(10.0, 60.0))
def test_scalar_fast_path_equals_vector_formulas(a, rho, b_):
    beta = b_ ** (-1 / 3)
    out = pr.scalar_ge2_tension(a, rho, b_, beta)
    vec = pl.reduced_ge2(a, rho, b_, True) + pl.reduced_tension(a, rho, b_, True)
    for x, y in zip(out, vec, strict=True):
        assert x == pytest.approx(float(y), rel=1e-12, abs=1e-12 * (abs(out[0]) + abs(out[3])))


def test_scalar_and_vector_solvers_agree():
    T = np.geomspace(0.01, 50, 40)
    a_v, r_v = pl.solve_reduced(T, b)
    for i, t in enumerate(T):
        a_s, r_s = pl._solve_scalar(float(t), b)
        assert a_s[0] == pytest.approx(a_v[i], rel=1e-12, abs=0)
        assert r_s[0] == pytest.approx(r_v[i], rel=1e-12, abs=0)


@pytest.mark.parametrize("ratio", [1.0, 1.0 + 1e-7, 0.97, 1.049, 0.951])
def test_scalar_solve_started_from_a_nearby_table_is_the_root(ratio):
    """A scalar solve starts from the table of b rounded to 10 % in log b, bracketed by the
    whole branch: the root of the vectorised solve on b's own table, over the whole held
    range of tensions (down to 1e-4 and up to just below the largest one, R -> r0/2)."""
    b2 = b * ratio
    T_max = pl.reduced_branch_table(b2)[2][0]
    T = np.concatenate([np.geomspace(1e-4, 50, 25), [0.5 * T_max, 0.999 * T_max]])
    a_v, r_v = pl.solve_reduced(T, b2)
    for i, t in enumerate(T):
        a, r = pl._solve_scalar(float(t), b2)
        assert a[0] == pytest.approx(a_v[i], rel=1e-13, abs=0)
        assert r[0] == pytest.approx(r_v[i], rel=1e-13, abs=0)


def test_scalar_solve_does_not_depend_on_earlier_calls():
    """The start table is a function of b alone: the same bits whatever was solved before
    (a fit on a process pool gives the serial fit's numbers)."""
    b2 = 1.03 * b
    first = pl._solve_scalar(2.0, b2)
    pl.reduced_branch_table.cache_clear()
    for other in (0.96 * b, 1.07 * b, b2):
        pl.reduced_branch_table(other)
    again = pl._solve_scalar(2.0, b2)
    assert first[0][0] == again[0][0] and first[1][0] == again[1][0]
    assert pl._start_table(b2) is pl._start_table(1.01 * b)  # one table serves 10 % of b


def test_largest_tension_without_a_table_is_the_tables_first_entry():
    b2 = 1.1 * b
    T_scalar = pl._largest_tension(b2)  # one scalar tilt solve, no table
    T_table = pl.reduced_branch_table(b2)[2][0]
    assert T_scalar == pytest.approx(T_table, rel=1e-13)
    # above it: the named error; just below: held
    r2 = B / (KT * b2)
    f_max = T_table * KT / r2
    with pytest.raises(sc.NoEquilibriumError, match="below r0/2"):
        pl.equilibrium(1.001 * f_max, B, 1e-28, KT, r2)
    pl.equilibrium(0.999 * f_max, B, 1e-28, KT, r2)


def test_overstretching_and_hard_core_warnings(dna, ureg):
    with pytest.warns(sc.ValidityWarning, match="hard-core radius"):
        e = sc.plectoneme_equilibrium(dna, 40 * ureg.pN)
    assert e.radius.m_as("nm") < 1.75
    with pytest.warns(sc.ValidityWarning) as record:
        sc.plectoneme_equilibrium(dna, [1.0, 70.0] * ureg.pN)
    messages = " ".join(str(w.message) for w in record)
    assert "70 pN is above 65 pN, where B-DNA overstretches" in messages
    assert "hard-core radius" in messages
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc.plectoneme_equilibrium(dna, [0.1, 1.0, 20.0] * ureg.pN)
