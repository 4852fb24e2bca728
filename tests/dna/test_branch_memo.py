"""The C-free memo of the free-energy kernel (supercoil.core.dna.branch_memo).

References, independent of the memo's tables:

* the direct solve: the same kernel without a memo (coexistence by Newton on the
  equilibrium, fully coiled points by the per-call Chebyshev table or the secant);
* scipy ``brentq`` per point on ``M_p(T)/C + tau(T) = x`` on the real equilibrium;
* the fit without the memo (its fitted values) and central differences of the direct
  residual (its Jacobian).

Tolerances: 1e-8 relative in extension and torque at points of every phase, incl. fully
coiled, with one memo reused across calls at other C and wider turns (the table rebuilt).
"""

import numpy as np
import pytest
from scipy.optimize import brentq

import supercoil as sc
from supercoil.core.dna import branch_memo as bm
from supercoil.core.dna import free_energy as fe
from supercoil.core.dna.interface import FULLY_COILED, PLECTONEME, STRETCHED
from supercoil.dna.fitting import model as fit_model
from supercoil.dna.fitting.fit import FitOptions, prepare
from supercoil.dna.interactions import get_interaction

u = sc.ureg


@pytest.fixture(scope="module")
def screened():
    """``(dna SI, equilibrium)`` of ``dna_150mM_nacl`` with the screened interaction."""
    dna = sc.load_parameters("dna_150mM_nacl").si
    inter = get_interaction("screened")
    return dna, (lambda T: inter.equilibrium(T, dna))


def _points(dna, eq, turns, force, C, memo):
    return fe.hat_points(turns, force, dna.length, dna.bending_rigidity, C, dna.kT, eq,
                         memo=memo)


def _close(a, b, rtol=1e-8):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return np.max(np.abs(a - b) / np.maximum(np.abs(b), 1e-300))


@pytest.mark.filterwarnings("ignore::supercoil.exceptions.ValidityWarning")  # 260 turns
def test_memo_points_match_the_direct_solve_in_every_phase(screened):
    """Extension and torque within 1e-8 of the direct solve, one memo across five calls:
    three C (the table built at the first, used at the others), a wider turns range (the
    table rebuilt wider) and 3 % lower forces (a smaller pull: rebuilt from lower down)."""
    dna, eq = screened
    memo = {}
    C0 = dna.torsional_rigidity
    for C, top, scale in ((C0, 150.0, 1.0), (0.8 * C0, 150.0, 1.0), (1.25 * C0, 150.0, 1.0),
                          (C0, 260.0, 1.0), (C0, 260.0, 0.97)):
        force = np.repeat([0.5e-12, 1.0e-12, 2.0e-12], 61) * scale
        turns = np.tile(np.linspace(-top, top, 61), 3)
        got = _points(dna, eq, turns, force, C, memo)
        ref = _points(dna, eq, turns, force, C, None)
        assert set(np.unique(ref.phase)) == {STRETCHED, PLECTONEME, FULLY_COILED}
        np.testing.assert_array_equal(got.phase, ref.phase)
        assert _close(got.extension, ref.extension) <= 1e-8
        assert _close(got.torque, ref.torque) <= 1e-8
        assert _close(got.free_energy, ref.free_energy) <= 1e-8
        table = memo["coiled branch"]
        assert table.u_lo <= np.log(fe.coexistence(
            force[:1], dna.length, dna.bending_rigidity, C, dna.kT, eq).pull[0])
    assert table.error <= bm.HERMITE_RTOL
    assert np.exp(table.u_hi) > 2.0 * np.exp(table.u_lo)


def test_memo_table_roots_against_brentq(screened):
    """Fully coiled (M, T) from the table within 1e-12 of brentq on the equilibrium."""
    dna, eq = screened
    T_lo, T_hi = 0.3e-12, 6e-12
    table = bm.build(np.log(T_lo), np.log(T_hi), eq)
    C = 0.9 * dna.torsional_rigidity

    def lp(uu):
        st = eq(np.array([np.exp(uu)]))
        return float(st.torque[0] / C + st.torsion[0])

    x = np.linspace(lp(np.log(T_lo)) * 1.001, lp(np.log(T_hi)) * 0.999, 7)
    M, T = bm.solve(table, x, C)
    for xi, Mi, Ti in zip(x, M, T, strict=True):
        ur = brentq(lambda uu, xi=xi: lp(uu) - xi, np.log(T_lo), np.log(T_hi), xtol=1e-15,
                    rtol=1e-15)
        assert abs(Ti / np.exp(ur) - 1.0) <= 1e-12
        assert abs(Mi / eq(np.array([np.exp(ur)])).torque[0] - 1.0) <= 1e-12
    assert bm.solve(table, np.array([2.0 * x[-1]]), C) is None  # beyond the table


def _fit_data():
    dna = sc.load_parameters("dna_150mM_nacl")
    data = sc.simulate_rotation_curves(dna.replace(twist_persistence=95 * u.nm),
                                       np.array([0.5, 1.0, 2.0]) * u.pN, points_per_force=24,
                                       noise=5 * u.nm, seed=3, turns=np.linspace(-200, 200, 24),
                                       model="free-energy", interaction="screened")
    return dna, data


@pytest.mark.filterwarnings("ignore")
def test_fit_and_jacobian_unchanged_by_the_memo(monkeypatch):
    """The fitted values with the memo within 1e-8 of those without; the Jacobian at the
    fit within 1e-5 of central differences of the memo-free residual."""
    dna, data = _fit_data()
    kwargs = {"vary": ["twist_persistence"], "model": "free-energy", "interaction": "screened"}
    got = sc.fit_hat_curves(data, dna, **kwargs)
    with monkeypatch.context() as m:
        m.setattr(fit_model._CachedInteraction, "kernel_memo", lambda self, d: None)
        ref = sc.fit_hat_curves(data, dna, **kwargs)
    assert got.nfev == ref.nfev
    np.testing.assert_allclose(got.x, ref.x, rtol=1e-8)

    spec = prepare(data, dna, FitOptions(**kwargs))

    def problem():
        return fit_model.HatCurveModel(spec.data, spec.params, spec.dna, spec.model,
                                       spec.interaction, spec.thermal, spec.xi_is_bending)

    prob = problem()
    u0 = spec.params.vector()
    prob.residual(u0)  # the memo's table built: the Jacobian's columns use it
    J = prob.jacobian(u0)
    monkeypatch.setattr(fit_model._CachedInteraction, "kernel_memo", lambda self, d: None)
    bare = problem()
    for j in range(len(u0)):
        h = 1e-4 * max(1.0, abs(u0[j]))
        up, um = u0.copy(), u0.copy()
        up[j] += h
        um[j] -= h
        fd = (bare.residual(up) - bare.residual(um)) / (2 * h)
        assert np.max(np.abs(J[:, j] - fd)) <= 1e-5 * np.max(np.abs(fd))
