"""Twist-spinning (docs/theory/spinning.md, Appendix F): stationarity and the T' = 0 limit."""

import numpy as np
import pint
import pytest
from scipy.optimize import fsolve

import supercoil as sc
from supercoil.core.rod import spinning as ts

u = sc.ureg


def test_zero_head_tension_is_the_twist_slacking_helix(rubber_rod):
    for N in (10, 40, 120):
        sp = sc.twist_spinning(rubber_rod, N, 0 * u.N)
        assert sp.beta.m_as(u.rad) == pytest.approx(np.pi / 2, abs=0)
        # the first helix formed by twist-slacking: [eq ini] = smooth helix at S = 0
        a0 = sc.rough_helix(rubber_rod, N).alpha0.m_as(u.rad)
        assert sp.alpha.m_as(u.rad) == pytest.approx(a0, rel=1e-12, abs=0)
        sm = sc.smooth_helix(rubber_rod, N, 0 * u.m)
        assert sp.alpha.m_as(u.rad) == pytest.approx(sm.alpha.m_as(u.rad), rel=1e-12, abs=0)
        assert sp.pitch_increase.magnitude == pytest.approx(0, abs=1e-12)


def test_small_head_tension_is_continuous_and_pitch_grows(rubber_rod):
    T = np.array([0.0, 1e-9, 1e-3, 1e-2, 0.1, 0.5, 1.0]) * u.N
    sp = sc.twist_spinning(rubber_rod, 40, T)
    a, b, P = sp.alpha.m_as(u.rad), sp.beta.m_as(u.rad), sp.pitch.m_as(u.mm)
    assert a[1] == pytest.approx(a[0], rel=1e-8) and b[1] == pytest.approx(np.pi / 2, abs=1e-3)
    assert np.all(np.diff(P) > 0) and np.all(np.diff(b) < 0) and np.all(np.diff(a) < 0)
    assert np.all((b > 0) & (b <= np.pi / 2))


def test_f4_and_f5_hold(rubber_rod):
    r, L = rubber_rod.si.radius, rubber_rod.si.length
    B, C = rubber_rod.si.bending_rigidity, rubber_rod.si.torsional_rigidity
    T = np.array([0.01, 0.2, 1.0])
    sp = sc.twist_spinning(rubber_rod, 40, T * u.N)
    a, b = sp.alpha.m_as(u.rad), sp.beta.m_as(u.rad)
    n = 40 / L
    k, ka, t, ta = (np.sin(a) ** 2 / r, np.sin(2 * a) / r, np.sin(a) * np.cos(a) / r,
                    np.cos(2 * a) / r)
    f4 = B * k * ka - 2 * np.pi * C * n * ta + 0.5 * T * np.sin(a)
    f5 = B * k**2 - 4 * np.pi * C * n * t - T * (np.cos(a) - 1 / np.cos(b))
    scale = B * k * ka
    np.testing.assert_allclose(f4 / scale, 0, atol=1e-12)
    np.testing.assert_allclose(f5 / (B * k**2), 0, atol=1e-10)


def _exact_gradient(a, Sp, N, Tp, S, r, L, B, C):
    """(dE/d alpha / S', dE/dS') of ts.exact_energy, no S'/L -> 0 limit."""
    k, ka = np.sin(a) ** 2 / r, np.sin(2 * a) / r
    t, ta = np.sin(a) * np.cos(a) / r, np.cos(2 * a) / r
    om = (2 * np.pi * N - t * Sp) / L
    g_a = B * k * ka - C * om * ta + 0.5 * Tp * np.sin(a)
    tails = (L - Sp) / np.sqrt((L - Sp) ** 2 - (L - S) ** 2)  # = sec(beta)
    g_s = 0.5 * B * k**2 - C * om * t - 0.5 * Tp * (np.cos(a) - tails)
    return np.array([g_a, g_s])


@pytest.mark.parametrize("T_head", [0.05, 0.5])
def test_stationary_point_of_the_exact_energy_tends_to_f4_f5(rubber_rod, T_head):
    """Stationarity of E_p(alpha, S') without the S'/L -> 0 limit converges to [f4, f5]."""
    r = rubber_rod.si.radius
    B, C = rubber_rod.si.bending_rigidity, rubber_rod.si.torsional_rigidity
    n = 40 / rubber_rod.si.length
    Sp = 0.01  # 1 cm of helix
    err_a, err_b = [], []
    for L in (10.0, 100.0):
        N = n * L
        st = ts.spinning_state(N, T_head, r, L, B, C)
        S = L - (L - Sp) * np.sin(st["beta"])  # the slack that gives this beta at S'
        a1 = float(st["alpha"])
        if L == 10.0:  # the analytic gradient is that of the stated energy
            h = 1e-7
            E = lambda a, sp: ts.exact_energy(a, sp, N, T_head, S, r, L, B, C)  # noqa: B023, E731
            g = _exact_gradient(a1, Sp, N, T_head, S, r, L, B, C)
            fd_a = (E(a1 + h, Sp) - E(a1 - h, Sp)) / (2 * h) / Sp
            fd_s = (E(a1, Sp + h) - E(a1, Sp - h)) / (2 * h)
            scale = B * np.sin(a1) ** 4 / r**2
            assert abs(fd_a - g[0]) < 1e-4 * scale and abs(fd_s - g[1]) < 1e-4 * scale
        a_ex, sp_ex = fsolve(lambda x, N=N, S=S, L=L: _exact_gradient(
            x[0], x[1], N, T_head, S, r, L, B, C), [a1, Sp], xtol=1e-13)
        beta_ex = np.arcsin((L - S) / (L - sp_ex))
        err_a.append(abs(a_ex - a1))
        err_b.append(abs(beta_ex - float(st["beta"])))
    # alpha and beta of [f4, f5] are the S'/L -> 0 limit: errors shrink like S'/L
    # (S' itself, a difference of two O(L) lengths, is not pinned down by that limit)
    for err in (err_a, err_b):
        assert err[0] < 0.5 * Sp / 10.0
        assert err[1] < err[0] / 5


def test_negative_turns_and_broadcasting(rubber_rod):
    sp = sc.twist_spinning(rubber_rod, np.array([[-40], [40]]), [0.0, 0.1, 0.2] * u.N)
    assert sp.alpha.shape == (2, 3)
    np.testing.assert_array_equal(sp.alpha[0].magnitude, sp.alpha[1].magnitude)
    assert np.all(sp.omega[0].magnitude < 0) and np.all(sp.omega[1].magnitude > 0)
    t = sp.to_table()
    assert len(t) == 6 and t.attrs["units"]["beta"] == "rad"


def test_failure_regions_are_named(rubber_rod):
    with pytest.raises(sc.NoHelixError, match="N = 0"):
        sc.twist_spinning(rubber_rod, 0, 0.1 * u.N)
    with pytest.raises(sc.NoHelixError, match="T'"):
        sc.twist_spinning(rubber_rod, 40, -0.1 * u.N)
    # a huge head tension straightens the helix but never closes the tails (see core doc)
    big = sc.twist_spinning(rubber_rod, 40, 1e4 * u.N)
    assert 0 < big.beta.m_as(u.rad) < 0.01 and big.pitch.m_as(u.m) > 1
    with pytest.raises(pint.DimensionalityError, match="head_tension"):
        sc.twist_spinning(rubber_rod, 40, 0.1 * u.m)


def test_unit_invariance(rubber_rod):
    a = sc.twist_spinning(rubber_rod, 40, 0.25 * u.N)
    b = sc.twist_spinning(rubber_rod, 80 * np.pi * u.rad, 250 * u.mN)
    assert a.beta.magnitude == pytest.approx(b.beta.magnitude, rel=1e-13, abs=0)
    assert a.pitch.magnitude == pytest.approx(b.pitch.magnitude, rel=1e-13)


# --- audit fixes: named errors for bad turns, no raw warnings at edge values -------------


def test_turns_must_be_finite(rubber_rod):
    with pytest.raises(ValueError, match="turns must be finite"):
        sc.twist_spinning(rubber_rod, np.nan, 0.1 * u.N)
    with pytest.raises(TypeError, match="turns"):
        sc.twist_spinning(rubber_rod, None, 0.1 * u.N)


def test_edge_values_give_the_limits_not_warnings_or_errors(rubber_rod):
    # T' -> 0+: 2 T_s / T' overflows, beta is the T' = 0 limit pi/2
    sp = sc.twist_spinning(rubber_rod, 40, 5e-324 * u.N)
    assert sp.beta.m_as(u.rad) == np.pi / 2
    assert sp.alpha == sc.twist_spinning(rubber_rod, 40, 0 * u.N).alpha
    # |N| -> 0 at finite T': T_s underflows; sec(beta) >= 1 (proved) -> beta -> 0, no error
    sp = sc.twist_spinning(rubber_rod, 1e-300, 0.1 * u.N)
    assert 0 <= sp.beta.m_as(u.rad) < 1e-100 and sp.alpha.m_as(u.rad) > 0
    with pytest.raises(sc.ValidityError, match="pitch"):
        sc.twist_spinning(rubber_rod, 40, 1e308 * u.N)
