"""The joint Newton of the hard-core equilibrium against the nested Newton it precedes.

The equilibrium first solves (GE2) and the tension together
(``hard_core_equations.joint_solve`` / ``scalar_joint_solve``) and leaves the tensions
it does not settle to the safeguarded nested Newton (``plectoneme._nested_reduced``,
``plectoneme._nested_newton``). The nested solve is the reference: the two must give
the same root, the joint one must refuse where it cannot settle (tiny tensions, the
strands at contact), and the public solve must be the root there as well.
"""

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from supercoil.core.dna import hard_core_equations as hc
from supercoil.core.dna import plectoneme as pl

B, KT, R0 = 50e-9 * 4.11e-21, 4.11e-21, 1.0e-9
b = B / (KT * R0)


def _nested(T, b_):
    return pl._nested_reduced(T, b_, pl.EQUILIBRIUM_RTOL, *pl._reduced_start(T, b_))


@given(st.floats(0.1, 10.0), st.floats(-3.0, 1.5))
def test_joint_and_nested_newton_give_the_same_root(b_factor, log_t):
    b_ = b * b_factor
    T = np.array([10.0 ** log_t, 10.0 ** (log_t + 0.37)])
    start = pl._reduced_start(T, b_)
    a, rho, ok = hc.joint_solve(T, start[3], start[0], b_, pl.EQUILIBRIUM_RTOL, pl._U_BRANCH)
    a_n, rho_n = _nested(T, b_)
    assert ok.all()  # the physical range (T' 1e-3 to 30) settles jointly
    np.testing.assert_allclose(rho, rho_n, rtol=4e-15)
    np.testing.assert_allclose(a, a_n, rtol=4e-15)
    # the result is a root: (GE2) at rounding, the tension to 1e-12
    np.testing.assert_allclose(hc.reduced_tension(a, rho, b_), T, rtol=hc.JOINT_RESIDUAL)
    for i, t in enumerate(T):  # the scalar path: the same root
        beta = b_ ** (-1.0 / 3.0)
        one = hc.scalar_joint_solve(float(t), float(start[3][i]), float(start[0][i]), b_,
                                    beta, pl.EQUILIBRIUM_RTOL, pl._U_BRANCH)
        assert one is not None
        assert one[1] == pytest.approx(rho_n[i], rel=4e-15, abs=0)
        assert one[0] == pytest.approx(a_n[i], rel=4e-15, abs=0)


def test_joint_newton_refuses_where_it_cannot_settle_and_the_solve_still_finds_the_root():
    """At tiny tensions (rho far out on the branch: here below T' = 5e-5) the joint steps
    leave the branch: ``ok`` is False there, alpha and rho are the start's (finite), and
    ``solve_reduced`` returns the nested solve's root, as at the tensions that settle
    (0.5 and next to the largest held one)."""
    T_max = pl.reduced_branch_table(b)[2][0]
    T = np.array([1e-5, 2e-6, 0.5, 0.9999 * T_max])
    start = pl._reduced_start(T, b)
    a, rho, ok = hc.joint_solve(T, start[3], start[0], b, pl.EQUILIBRIUM_RTOL, pl._U_BRANCH)
    assert ok.tolist() == [False, False, True, True]
    assert np.array_equal(a[~ok], start[3][~ok]) and np.array_equal(rho[~ok],
                                                                     np.exp(start[0][~ok]))
    beta = b ** (-1.0 / 3.0)
    assert hc.scalar_joint_solve(1e-5, float(start[3][0]), float(start[0][0]), b, beta,
                                 pl.EQUILIBRIUM_RTOL, pl._U_BRANCH) is None
    a_s, rho_s = pl.solve_reduced(T, b)
    a_n, rho_n = _nested(T, b)
    # next to contact (rho = 0.500004) the root is ill-conditioned: 4.4e-15 apart here
    np.testing.assert_allclose(rho_s, rho_n, rtol=2e-14)
    np.testing.assert_allclose(a_s, a_n, rtol=2e-14)
    for i, t in enumerate(T):  # the scalar solve falls back likewise
        r1 = pl._solve_scalar(float(t), b)[1]
        assert r1[0] == pytest.approx(rho_n[i], rel=1e-12, abs=0)


def test_a_joint_step_that_leaves_the_branch_or_is_not_finite_is_refused():
    beta = b ** (-1.0 / 3.0)
    u_hi = pl._U_BRANCH[1]
    # a start far outside the branch's alpha: the first step cannot land inside
    assert hc.scalar_joint_solve(0.5, 0.7853981, u_hi, b, beta, 1e-8, (u_hi - 1e-9, u_hi)) \
        is None
    assert hc.scalar_joint_solve(0.5, 0.3, math.nan, b, beta, 1e-8, pl._U_BRANCH) is None
    ok = hc.joint_solve(np.array([0.5, 0.5]), np.array([0.3, math.nan]),
                        np.array([0.0, 0.0]), b, 1e-8, pl._U_BRANCH)[2]
    assert ok[0] and not ok[1]


def test_equilibrium_of_few_and_many_forces_agree():
    """The scalar path (up to 12 forces) and the vector path (more) run different joint
    solvers and build the state by different code (floats, arrays): the same states."""
    forces = np.geomspace(0.2e-12, 15e-12, 40)
    many = pl.equilibrium(forces, B, 100e-9 * KT, KT, R0)
    few = [pl.equilibrium(forces[i:i + 4], B, 100e-9 * KT, KT, R0) for i in range(0, 40, 4)]
    for name in many._fields:
        np.testing.assert_allclose(np.concatenate([getattr(s, name) for s in few]),
                                   getattr(many, name), rtol=1e-14, err_msg=name)


@given(st.floats(0.1, 10.0), st.floats(0.02, 0.78), st.floats(-1.0, 2.0))
def test_scalar_state_is_the_vector_formulas(b_factor, alpha, log_rho):
    """hard_core_equations.scalar_state on floats: the reduced torque and interaction of
    the vector functions (reduced_torque, marko_siggia.reduced_interaction) to 4 ulp."""
    from supercoil.core.dna import marko_siggia as ms

    b_, rho = b * b_factor, 10.0**log_rho
    beta = b_ ** (-1.0 / 3.0)
    torque, s, c, tan, w = hc.scalar_state(alpha, rho, b_, beta)
    a, r = np.array([alpha]), np.array([rho])
    np.testing.assert_allclose(torque, hc.reduced_torque(a, r, b_)[0], rtol=1e-15)
    np.testing.assert_allclose(w, ms.reduced_interaction(a, r, beta)[0], rtol=1e-15)
    np.testing.assert_allclose((s, c, tan), (np.sin(a[0]), np.cos(a[0]), np.tan(a[0])),
                               rtol=4.5e-16)


def test_a_tensions_root_does_not_depend_on_the_other_tensions_of_the_call():
    """Each tension is held once its own steps settle (and the final tilt solve leaves a
    settled tilt as it is): a call on a slice gives the whole call's bits."""
    T = np.geomspace(0.01, 30, 40)
    a, rho = pl.solve_reduced(T, b)
    for i in range(0, 40, 3):
        a2, rho2 = pl.solve_reduced(T[i:i + 5], b)
        assert np.array_equal(a2, a[i:i + 5]) and np.array_equal(rho2, rho[i:i + 5]), i
