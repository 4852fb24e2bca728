"""Stretched phase with twist-bend coupling (docs/theory/melting.md#stretched-phase)."""

import numpy as np
import pytest

from supercoil.core.dna import moroz_nelson as mn
from supercoil.core.dna import phases as ph
from supercoil.core.dna import twist_bend as tb
from supercoil.exceptions import ValidityError

KT = 1.380649e-23 * 296.15
A, C = 50e-9, 100e-9
F = np.array([0.05, 0.3, 1.0, 2.0, 6.5, 30.0])[:, None] * 1e-12
M = np.array([-15.0, -3.0, 0.0, 4.0, 12.0])[None, :] * 1e-21


def _fd(fun, x, h):
    return (fun(x + h) - fun(x - h)) / (2 * h)


def test_one_bouchiat_inversion_for_both_kernels():
    # the stretched phases of twist_bend and of phases invert the interpolation once
    x = tb.wlc_extension(F[:, 0], A, KT)[0]
    g, x2 = ph.wlc_exact_free_energy_gain(F[:, 0], A, KT)
    assert np.array_equal(x, x2)
    assert np.array_equal(tb.wlc_gibbs_gain(F[:, 0], A, KT)[0], g)


def test_bouchiat_inversion_solves_the_interpolation():
    x, dx = tb.wlc_extension(F[:, 0], A, KT)
    h, hp = ph._bouchiat_reduced_force(x), ph._bouchiat_reduced_stiffness(x)
    np.testing.assert_allclose(h, F[:, 0] * A / KT, rtol=1e-13)
    np.testing.assert_allclose(dx, A / (KT * hp), rtol=1e-14)
    assert np.all((x > 0) & (x < 1)) and np.all(np.diff(x) > 0)


def test_wlc_gain_is_the_integral_of_the_extension():
    # dg/dF = x by construction; check against quadrature of x from 0
    from scipy.integrate import quad
    for f in (0.1e-12, 1e-12, 5e-12):
        ref = quad(lambda s: tb.wlc_extension(s, A, KT)[0], 1e-30, f, epsabs=0, epsrel=1e-12)[0]
        g = tb.wlc_gibbs_gain(f, A, KT)[0]
        assert g == pytest.approx(ref, rel=1e-9, abs=0)


def test_high_force_limit_of_the_wlc():
    # x -> 1 - sqrt(kT/(A F))/2 at high force (Marko-Siggia asymptote, which the
    # interpolation keeps)
    f = np.array([50e-12, 200e-12])
    x = tb.wlc_extension(f, A, KT)[0]
    np.testing.assert_allclose(1 - x, 0.5 * np.sqrt(KT / (A * f)), rtol=0.02)


def test_wlc_inversion_at_reduced_forces_beyond_the_bracket():
    # f = F A / kT > 1e25: the large-force start 1 - 1/(2 sqrt f) rounds to 1.0, outside
    # the bracket [0, 1 - 1e-13] (a divide by zero before the start was clipped); the
    # root is then the bracket's top, whose h(x) = 2.5e25 < f
    f = np.array([1e24, 1e26, 1e300])
    with np.errstate(all="raise", under="ignore"):
        x, dx = ph.wlc_extension(f * KT / A, A, KT)
    np.testing.assert_allclose(1 - x[0], 0.5 / np.sqrt(1e24), rtol=1e-3)
    assert np.all(x[1:] == 1.0 - 1e-13) and np.all(np.isfinite(dx) & (dx > 0))


@pytest.mark.parametrize("G", [0.0, 25e-9, 40e-9])
def test_derivatives_against_finite_differences(G):
    p = tb.stretched_gibbs(F, M, A, C, G, KT)
    hF = 1e-5 * F
    dF = _fd(lambda f: tb.stretched_gibbs(f, M, A, C, G, KT).phi, F, hF)
    np.testing.assert_allclose(p.dphi_dF, dF, rtol=1e-6, atol=1e-9)
    hM = 1e-23
    dM = _fd(lambda m: tb.stretched_gibbs(F, m, A, C, G, KT).phi, M, hM)
    np.testing.assert_allclose(p.dphi_dM, dM, rtol=1e-6, atol=1e-6 * np.abs(p.dphi_dM).max())
    d2 = _fd(lambda m: tb.stretched_gibbs(F, m, A, C, G, KT).dphi_dM, M, hM)
    np.testing.assert_allclose(p.d2phi_dM2, d2, rtol=1e-6)
    assert np.all(p.d2phi_dM2 < 0)


def test_zero_coupling_is_the_moroz_nelson_resummation():
    c, _ = tb.effective_twist_stiffness(F, A, C, 0.0, KT)
    ref = mn.effective_twist_rigidity(F, A * KT, C * KT, KT) / KT
    np.testing.assert_allclose(c, ref, rtol=1e-14)
    assert tb.twist_bend_renormalisation(A, C, 0.0) == (A, C)


def test_coupling_renormalises_the_stiffnesses():
    for G in (10e-9, 40e-9, 80e-9):
        Ab, Ct = tb.twist_bend_renormalisation(A, C, G)
        u = G * G / C
        assert 2 / A == pytest.approx(1 / Ab + 1 / (Ab - u), rel=1e-14)
        assert Ct == pytest.approx(C - G * G / Ab, rel=1e-15, abs=0)
        assert Ab > A and 0 < Ct < C
    # C_eff falls monotonically with |G| at every force, tends to C~ at high force
    Gs = np.array([0.0, 20e-9, 40e-9])
    c = np.array([tb.effective_twist_stiffness(6.5e-12, A, C, g, KT)[0] for g in Gs])
    assert np.all(np.diff(c) < 0)
    Ct = tb.twist_bend_renormalisation(A, C, 40e-9)[1]
    assert tb.effective_twist_stiffness(1e-6, A, C, 40e-9, KT)[0] == pytest.approx(Ct, rel=2e-3)


def test_ceff_at_6p5_pN_numbers():
    # C = 100 nm, A = 50 nm: Moroz-Nelson 94.7 nm (G = 0), lower with coupling
    c0 = tb.effective_twist_stiffness(6.5e-12, A, C, 0.0, KT)[0]
    c40 = tb.effective_twist_stiffness(6.5e-12, A, C, 40e-9, KT)[0]
    assert c0 * 1e9 == pytest.approx(94.69, abs=0.01)
    assert c40 * 1e9 == pytest.approx(70.12, abs=0.01)


def test_writhe_factor_scales_the_writhe_term():
    c1 = tb.effective_twist_stiffness(F, A, C, 0.0, KT, 1.0)[0]
    c2 = tb.effective_twist_stiffness(F, A, C, 0.0, KT, 2.5)[0]
    np.testing.assert_allclose(1 / c2 - 1 / C, 2.5 * (1 / c1 - 1 / C), rtol=1e-12)


def test_broadcasting():
    p = tb.stretched_gibbs(F, M, A, C, 30e-9, KT)
    assert all(np.shape(a) == (F.size, M.size) for a in p)
    one = tb.stretched_gibbs(F[2, 0], M[0, 3], A, C, 30e-9, KT)
    assert one.phi == pytest.approx(p.phi[2, 3], rel=1e-15, abs=0)


@pytest.mark.parametrize("bad", [0.0, -1e-12, np.nan, np.inf])
def test_nonpositive_force_is_a_named_error(bad):
    with pytest.raises(ValidityError, match="force"):
        tb.stretched_gibbs(np.array([1e-12, bad]), 0.0, A, C, 0.0, KT)


def test_bad_stiffness_is_a_named_error():
    with pytest.raises(ValidityError, match="C must be"):
        tb.twist_bend_renormalisation(A, -1.0, 0.0)


def test_mixed_partials_agree():
    # dx/dM = dOmega/dF (Maxwell relation of one phase): d(dphi_dF)/dM = d(dphi_dM)/dF
    G = 30e-9
    f, mq = F[1:5], M[:, [0, 1, 3, 4]]
    a = _fd(lambda m: tb.stretched_gibbs(f, m, A, C, G, KT).dphi_dF, mq, 1e-23)
    b = _fd(lambda x: tb.stretched_gibbs(x, mq, A, C, G, KT).dphi_dM, f, 1e-5 * f)
    np.testing.assert_allclose(a, b, rtol=1e-6)


def test_only_the_square_of_the_coupling_enters():
    p = tb.stretched_gibbs(F, M, A, C, 35e-9, KT)
    q = tb.stretched_gibbs(F, M, A, C, -35e-9, KT)
    for u, v in zip(p, q, strict=True):
        np.testing.assert_array_equal(u, v)
