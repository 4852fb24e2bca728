"""The plectoneme end loop (docs/theory/end-loop.md): a jump at buckling, G continuous.

Independent references: a numerical minimisation of the loop's excess free
energy over its radius, finite differences of each branch's free energy for
the extension jump, the crossing of the two free-energy branches, and the
L^(-1/2) scaling of the torque overshoot.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

import supercoil
from supercoil.core.dna import end_loop as el
from supercoil.core.dna import marko2007 as mk
from supercoil.dna.models.marko2007 import Marko2007
from supercoil.exceptions import ValidityError

TWO_PI = 2 * np.pi


def _dna(A=48.0, C=86.0, L=750.0):
    u = supercoil.ureg
    return supercoil.DNA(length=L * u.nm, bending_persistence=A * u.nm,
                         twist_persistence=C * u.nm, radius=1.75 * u.nm,
                         temperature=300 * u.K).si


def test_loop_radius_minimises_the_excess_free_energy():
    """Minimise bending + gamma l + twist energy - 2 pi M (w + t) over R and t numerically."""
    B, C, gamma, M = 48e-9 * 4.14e-21, 86e-9 * 4.14e-21, 2.3e-12, 21e-21

    def eps(R):
        ell = TWO_PI * R
        inner = minimize_scalar(  # twist turns t stored in the loop
            lambda t: 0.5 * C * (TWO_PI * t / ell) ** 2 * ell - TWO_PI * M * t,
            bounds=(0.0, 5.0), method="bounded", options={"xatol": 1e-14})
        return np.pi * B / R + ell * gamma + inner.fun - TWO_PI * M

    res = minimize_scalar(eps, bounds=(1e-10, 1e-7), method="bounded",
                          options={"xatol": 1e-16})
    gl = el.loop_tension(gamma, M, C)
    assert el.loop_radius(gl, B) == pytest.approx(res.x, rel=1e-4, abs=0)
    assert el.loop_excess_free_energy(gl, M, B) == pytest.approx(res.fun, rel=1e-8, abs=0)
    assert el.loop_length(gl, B) == pytest.approx(TWO_PI * res.x, rel=1e-4)
    ell = el.loop_length(gl, B)
    assert el.loop_twist(M, ell, C) == pytest.approx(M * ell / (TWO_PI * C), rel=1e-14, abs=0)


def test_loop_off_by_default_gives_no_jump():
    par = Marko2007().parameters_at(np.array([2e-12]), _dna(), True)
    assert par.extension_jump[0] == 0 and par.torque_overshoot[0] == 0
    assert par.jump_turns[0] == par.buckling_turns[0]


@pytest.mark.parametrize("thermal", [True, False])
@pytest.mark.parametrize("F", [1e-12, 2e-12, 4e-12])
def test_jump_at_buckling_documented_and_G_continuous(F, thermal):
    dna = _dna()
    m = Marko2007(end_loop=True)
    par = m.parameters_at(np.array([F]), dna, thermal)
    Ns, jump, dM = par.jump_turns[0], par.extension_jump[0], par.torque_overshoot[0]
    d = 1e-9
    pt = m.points(np.array([Ns - d, Ns + d]), np.full(2, F), dna, thermal)
    assert list(pt.phase) == [0, 1]
    # z drops by the documented jump, the torque by the documented overshoot
    assert jump > 0 and dM > 0
    np.testing.assert_allclose(pt.extension[0] - pt.extension[1], jump, rtol=1e-6)
    np.testing.assert_allclose(pt.torque[0] - pt.torque[1], dM, rtol=1e-6)
    # G continuous: the change is only the slope times 2d
    dG = abs(pt.free_energy[1] - pt.free_energy[0])
    assert dG <= 2 * d * TWO_PI * (par.torque[0] + dM) * 1.01
    # overshoot closed form: sqrt(2 eps c_s kT / L)
    cs = par.twist_stiffness[0] * dna.kT
    assert dM == pytest.approx(np.sqrt(2 * par.loop_excess[0] * cs / dna.length), rel=1e-12, abs=0)


@pytest.mark.parametrize("thermal", [True, False])
def test_jump_equals_difference_of_branch_derivatives(thermal):
    """Delta z = -dG_s/dF + dG_c/dF at N*, each branch differentiated numerically."""
    dna = _dna()
    L, A, Ct, kT = dna.length, dna.bending_persistence, dna.twist_persistence, dna.kT
    F = 2.5e-12
    par = Marko2007(end_loop=True).parameters_at(np.array([F]), dna, thermal)
    Ns = par.jump_turns[0]

    def G_stretched(f):
        g, _ = mk.wlc_free_energy_gain(f, A, kT, thermal)
        cs, _ = mk.stretched_twist_stiffness(f, A, Ct, kT, thermal)
        return L * (-g + 0.5 * cs * kT * (TWO_PI * Ns / L) ** 2)

    def G_looped(f):
        p = mk.marko_parameters(np.array([f]), L, A, Ct, 24e-9, kT, thermal, True)
        return (-(L - p.loop_length) * p.gamma + TWO_PI * p.torque * (Ns - p.loop_linking)
                + p.loop_energy)[0]

    h = 1e-5 * F
    zs = -(G_stretched(F + h) - G_stretched(F - h)) / (2 * h)
    zc = -(G_looped(F + h) - G_looped(F - h)) / (2 * h)
    assert G_stretched(F) == pytest.approx(G_looped(F), rel=1e-12, abs=0)  # N* is the crossing
    assert zs - zc == pytest.approx(par.extension_jump[0], rel=1e-6, abs=0)


def test_overshoot_scales_as_inverse_root_length_and_shift_as_root_length():
    F = np.array([2e-12])
    a = Marko2007(end_loop=True).parameters_at(F, _dna(L=1000.0), True)
    b = Marko2007(end_loop=True).parameters_at(F, _dna(L=4000.0), True)
    assert b.torque_overshoot[0] / a.torque_overshoot[0] == pytest.approx(0.5, rel=1e-12, abs=0)
    shift = lambda p: p.jump_turns[0] - p.buckling_turns[0]  # noqa: E731
    assert shift(b) / shift(a) == pytest.approx(2.0, rel=1e-12)
    # the loop itself does not depend on L
    assert b.loop_excess[0] == pytest.approx(a.loop_excess[0], rel=1e-14, abs=0)


def test_fully_coiled_with_loop_is_continuous():
    dna = _dna()
    m = Marko2007(end_loop=True)
    F = np.array([1.5e-12])
    par = m.parameters_at(F, dna, True)
    B, K, C = dna.bending_rigidity, 24e-9 * dna.kT, dna.torsional_rigidity
    twist = (par.loop_linking - par.loop_writhe)[0]
    n_full = (par.omega_plectoneme * (dna.length - par.loop_length) / TWO_PI)[0] + twist
    # the coiled state's loop radius and torque at the boundary equal the coexistence's
    _, M, R = el.coiled_state(n_full, dna.length, B, K, C)
    assert TWO_PI * R == pytest.approx(par.loop_length[0], rel=1e-12, abs=0)
    assert M == pytest.approx(par.torque[0], rel=1e-12, abs=0)
    N = n_full + par.loop_writhe[0] + np.array([-1e-8, 1e-8])
    pt = m.points(N, np.full(2, F[0]), dna, True)
    assert list(pt.phase) == [1, 2]
    # G continuous: it changes by no more than the slope 2 pi M_b times the 2e-8 turns
    dG = abs(pt.free_energy[1] - pt.free_energy[0])
    assert dG <= 2e-8 * TWO_PI * par.torque[0] * 1.001
    np.testing.assert_allclose(pt.torque[0], pt.torque[1], rtol=1e-7)
    assert abs(pt.extension[0]) < 1e-15 and pt.extension[1] == 0


def test_loop_failures_are_named():
    with pytest.raises(ValidityError, match="too short"):
        Marko2007(end_loop=True).parameters_at(np.array([1e-12]), _dna(L=60.0), True)
    # seed set, P = 24 nm, 1 pN: L_min = 290.8 nm (docs/theory/end-loop.md#3-jump)
    with pytest.raises(ValidityError, match=r"curl.*L >= 290.8 nm"):
        Marko2007(end_loop=True).parameters_at(np.array([1e-12]), _dna(L=280.0), True)
    Marko2007(end_loop=True).parameters_at(np.array([1e-12]), _dna(L=300.0), True)
    # eps* = 2 pi M_b (sqrt(A/P - A/C) - 1) <= 0 once P >= 1/(1/A + 1/C) = 30.81 nm (seed)
    with pytest.raises(ValidityError, match=r"needs P < 1/\(w\^2/A \+ 1/C\) = 30.81 nm"):
        Marko2007(end_loop=True, plectoneme_twist_persistence=31e-9).parameters_at(
            np.array([2e-12]), _dna(), True)
    # just below the limit eps* is small and the jump needs a long molecule (L_min ~ 1/eps*)
    Marko2007(end_loop=True, plectoneme_twist_persistence=30.7e-9).parameters_at(
        np.array([2e-12]), _dna(L=1e5), True)
    with pytest.raises(ValidityError, match="not positive"):  # the shared kernel's own check
        el.loop_excess_free_energy(1e-12, 30e-21, 48e-9 * 4.14e-21)
    with pytest.raises(ValidityError, match="gamma"):
        el.loop_radius(-1.0, 1e-28)


@pytest.mark.parametrize("thermal", [True, False])
def test_excess_free_energy_ratio_is_force_independent(thermal):
    """eps / (2 pi M_b) = sqrt(A/P - A/C) - w with Marko's gamma: a closed-form limit."""
    dna = _dna()
    par = Marko2007(end_loop=True).parameters_at(np.array([1, 2, 3, 4]) * 1e-12, dna, thermal)
    np.testing.assert_allclose(par.loop_excess / (TWO_PI * par.torque),
                               np.sqrt(48.0 / 24.0 - 48.0 / 86.0) - 1.0, rtol=1e-12)


@given(f=st.floats(0.5, 6.0), P=st.floats(15.0, 30.0), L=st.floats(200.0, 5000.0))
def test_jump_property(f, P, L):
    """Across forces, P and L: z and M drop by the documented amounts, G stays continuous."""
    dna = _dna(L=L)
    m = Marko2007(end_loop=True, plectoneme_twist_persistence=P * 1e-9)
    F = f * 1e-12
    # minimum length for a plectoneme at the jump (docs: L >= c (2 pi (w+t) - W_s l)^2/(2 eps))
    ref = m.parameters_at(np.array([F]), _dna(L=1e5), True)  # loop and eps do not depend on L
    c = ref.twist_stiffness[0] * dna.kT
    Lmin = c * (TWO_PI * ref.loop_linking[0] - ref.omega_stretched[0] * ref.loop_length[0]) ** 2 \
        / (2 * ref.loop_excess[0])
    if L * 1e-9 < Lmin:
        with pytest.raises(ValidityError, match="curl"):
            m.parameters_at(np.array([F]), dna, True)
        return
    par = m.parameters_at(np.array([F]), dna, True)
    d = 1e-9
    pt = m.points(par.jump_turns[0] + np.array([-d, d]), np.full(2, F), dna, True)
    assert list(pt.phase) == [0, 1]
    np.testing.assert_allclose(pt.extension[0] - pt.extension[1], par.extension_jump[0],
                               rtol=1e-5)
    np.testing.assert_allclose(pt.torque[0] - pt.torque[1], par.torque_overshoot[0], rtol=1e-5)
    assert abs(pt.free_energy[1] - pt.free_energy[0]) <= 2 * d * TWO_PI * pt.torque[0] * 1.01
