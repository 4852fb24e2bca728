"""The ensemble's plectoneme derived from the screened superhelix at fixed torque.

References independent of the tabulated phase's code path: finite differences of its
Gibbs free energy; the constant-P plectoneme of Marko (2007), which a quadratic table
must reproduce exactly (cubic Hermite interpolation is exact on cubics); the screened
interaction's own equilibrium at fixed tension (``Screened.equilibrium``); finite
differences of the ensemble's G(N, F).
"""

import numpy as np
import pytest

import supercoil as sc
from supercoil.core.dna import ensemble as en
from supercoil.core.dna import phases as ph
from supercoil.dna.interactions import get_interaction
from supercoil.dna.models import get_model
from supercoil.dna.models.ensemble import superhelix_table
from supercoil.exceptions import ParameterError

KT = 4.09e-21
PN, NM, PNNM = 1e-12, 1e-9, 1e-21
TWO_PI = 2 * np.pi


def _dna(salt=150.0):
    u = sc.ureg
    return sc.load_parameters("dna_150mM_nacl").replace(length=1500 * u.nm, salt=salt * u.mM)


def _fd(f, x, h):
    return (8 * (f(x + h) - f(x - h)) - (f(x + 2 * h) - f(x - 2 * h))) / (12 * h)


def test_tabulated_phase_derivatives_match_finite_differences():
    si = _dna().si
    table = superhelix_table(si, 1.0, 0.0)
    F = np.full(5, 1 * PN)
    M = np.array([-14.0, -0.03, 3.0, 9.5, 150.0]) * PNNM  # below, inside, beyond the table

    def g(m):
        return ph.tabulated_plectoneme_gibbs(F, m, table, 100 * NM, KT)

    p = g(M)
    h = 1e-5 * np.abs(M)
    np.testing.assert_allclose(_fd(lambda m: g(m).phi, M, h), p.dphi_dM, rtol=1e-6)
    np.testing.assert_allclose(_fd(lambda m: g(m).dphi_dM, M, h), p.d2phi_dM2, rtol=1e-6)
    assert np.all(p.d2phi_dM2 < 0.0) and np.all(p.dphi_dF == 0.0)


def test_quadratic_table_is_the_constant_P_plectoneme():
    """T = M^2 (1/P - 1/C) / (2 kT) tabulated: phi_p = -M^2 / (2 kT P) to round-off."""
    P, C = 20 * NM, 100 * NM
    Mk = np.geomspace(0.5, 80, 30) * PNNM
    k = (1 / P - 1 / C) / KT
    table = (Mk, 0.5 * k * Mk**2, k * Mk)
    M = np.array([-30.0, 0.2, 4.4, 17.0, 79.0]) * PNNM
    a = ph.tabulated_plectoneme_gibbs(np.ones(5) * PN, M, table, C, KT)
    b = ph.plectoneme_gibbs(np.ones(5) * PN, M, P, 0.0, 10 * PNNM, KT)
    for x, y in zip(a, b, strict=True):
        np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * np.max(np.abs(y)) + 1e-300)


def test_table_is_the_screened_equilibrium_at_fixed_tension():
    """Each tabulated (M, T) is the screened superhelix's equilibrium at tension T, and
    dT/dM = tau (the envelope theorem) along it."""
    si = _dna().si
    Mk, Tk, tk = superhelix_table(si, 1.0, 0.0)
    inter = type(get_interaction("screened"))(confinement=0.0)
    sel = (Tk > 0.1 * PN) & (Tk < 5 * PN)
    state = inter.equilibrium(Tk[sel], si)
    np.testing.assert_allclose(state.torque, Mk[sel], rtol=1e-9)
    np.testing.assert_allclose(state.torsion, tk[sel], rtol=1e-9)
    dT = np.gradient(Tk, Mk)
    np.testing.assert_allclose(dT[sel], tk[sel], rtol=2e-3)


@pytest.mark.parametrize("effective_tension", [False, True])
@pytest.mark.parametrize(("N0", "F0"), [(14.0, 1.0), (-24.0, 0.75)])
def test_ensemble_with_derived_plectoneme_obeys_maxwell(N0, F0, effective_tension):
    m = get_model("ensemble").replace(screened_plectoneme=True,
                                      effective_tension=effective_tension)
    par = m.kernel_parameters(_dna().si)._replace(nodes=16, max_domains=1)
    N, F = np.array([N0]), np.array([F0 * PN])

    def at(n, f):
        return en.points(np.atleast_1d(n), np.atleast_1d(f), par)

    p = at(N, F)
    assert p.domains[0] > 0.1  # plectonemes present
    dGdN = _fd(lambda n: at(n, F).free_energy, N, 1e-3)
    dGdF = _fd(lambda f: at(N, f).free_energy, F, 1e-4 * F)
    np.testing.assert_allclose(p.torque, dGdN / TWO_PI, rtol=1e-6)
    np.testing.assert_allclose(p.extension, -dGdF, rtol=1e-6)


def test_derived_plectoneme_needs_the_salt_and_is_off_by_default():
    u = sc.ureg
    no_salt = sc.DNA(length=1500 * u.nm, bending_persistence=45 * u.nm,
                     twist_persistence=100 * u.nm, radius=1 * u.nm, temperature=296 * u.K)
    m = get_model("ensemble")
    assert m.kernel_parameters(no_salt.si).plectoneme_table is None
    with pytest.raises(ParameterError, match="salt"):
        m.replace(screened_plectoneme=True).kernel_parameters(no_salt.si)


def test_derived_stiffness_grows_with_torque_and_falls_with_salt():
    """P(M) = M / (kT Omega_p): rises with torque (the superhelix tightens) and is lower
    at higher salt (a tighter superhelix writhes more per length)."""
    def P(salt, M):
        t = superhelix_table(_dna(salt).si, 1.0, 0.0)
        om = -ph.tabulated_plectoneme_gibbs(PN, M, t, 100 * NM, KT).dphi_dM
        return M / (KT * om)

    M = np.array([4.0, 8.0, 16.0]) * PNNM
    p150, p300 = P(150.0, M), P(300.0, M)
    assert np.all(np.diff(p150) > 0) and np.all(p300 < p150)
