"""The phase-ensemble model: phases, Maxwell relation, limits, recovery of parameters.

References independent of the kernel's code path: finite differences of the phases'
Gibbs free energies and of the total G(N, F); the marko2007 kernel (the limit);
the package's end-loop formulas (docs/theory/end-loop.md); Bouchiat's published
interpolation F(x).
"""

import pickle

import numpy as np
import pytest
from scipy.optimize import least_squares
from seed_kernels import KT, NM, PN, PNNM, ensemble_parameters

import supercoil
from supercoil.core.dna import end_loop as el
from supercoil.core.dna import ensemble as en
from supercoil.core.dna import marko2007 as mk
from supercoil.core.dna import phases as ph
from supercoil.dna.models import get_model
from supercoil.dna.models.ensemble import Ensemble
from supercoil.exceptions import ModelError

TWO_PI = 2 * np.pi


def _par(**kw):
    return ensemble_parameters(**kw)


def _fd(f, x, h):
    """Fourth-order central difference."""
    return (8 * (f(x + h) - f(x - h)) - (f(x + 2 * h) - f(x - 2 * h))) / (12 * h)


# ---- phases ---------------------------------------------------------------------------
def test_bouchiat_inversion_and_g_prime():
    F = np.array([0.05, 0.3, 1.0, 5.0]) * PN
    A = 45 * NM
    _, x = ph.wlc_exact_free_energy_gain(F, A, KT)
    # Bouchiat et al. (1999) eq. 11 with their a_i, evaluated independently
    a = [-0.5164228, -2.737418, 16.07497, -38.87607, 39.49944, -14.17718]
    fa = x + 0.25 / (1 - x) ** 2 - 0.25 + sum(c * x ** (i + 2) for i, c in enumerate(a))
    np.testing.assert_allclose(fa * KT / A, F, rtol=1e-10)
    dg = _fd(lambda f: ph.wlc_exact_free_energy_gain(f, A, KT)[0], F, 1e-6 * F)
    np.testing.assert_allclose(dg, x, rtol=1e-7)


@pytest.mark.parametrize("phase", ["stretched", "stretched-marko", "stretched-tension",
                                   "stretched-tension-marko", "plectoneme", "melted", "tail",
                                   "tail-tension", "loop", "loop-constant"])
def test_phase_derivatives_match_finite_differences(phase):
    F = np.array([0.3, 1.0, 2.0]) * PN
    M = np.array([-9.0, 4.0, 12.0]) * PNNM
    par = _par()

    def gibbs(F, M):
        if phase == "stretched":
            return ph.stretched_gibbs(F, M, 45 * NM, 100 * NM, KT, 2.5)
        if phase == "stretched-marko":
            return ph.stretched_gibbs(F, M, 45 * NM, 100 * NM, KT, 1.0, False, False)
        if phase.startswith("stretched-tension"):
            return ph.stretched_gibbs(F, M, 45 * NM, 100 * NM, KT, 2.5, "marko" not in phase,
                                      effective_tension=True)
        if phase == "plectoneme":
            return ph.plectoneme_gibbs(F, M, 13 * NM, 0.3, 10 * PNNM, KT)
        if phase == "melted":
            return ph.simple_melted_gibbs(F, M, 3e-12, 0.2, -1.76e9)
        if phase == "tail-tension":
            return en.tail_gibbs(F, M, par._replace(effective_tension=True))[0]
        t = en.tail_gibbs(F, M, par)[0]
        if phase == "tail":
            return t
        e = ph.end_loop_gibbs(t, M, par.A, par.C, KT, 1.0, 1.0, 2 * KT, phase == "loop")
        return ph.PhaseGibbs(e[0], e[1], e[2],
                             ph.end_loop_torque_slope(t, M, par.A, par.C, KT, phase == "loop"))

    g = gibbs(F, M)
    np.testing.assert_allclose(_fd(lambda f: gibbs(f, M).phi, F, 1e-6 * F), g.dphi_dF,
                               rtol=1e-6, atol=1e-6 * np.max(np.abs(g.dphi_dF)) + 1e-30)
    dM = _fd(lambda m: gibbs(F, m).phi, M, 1e-6 * np.abs(M))
    np.testing.assert_allclose(dM, g.dphi_dM, rtol=1e-6)
    d2 = _fd(lambda m: gibbs(F, m).dphi_dM, M, 1e-6 * np.abs(M))
    np.testing.assert_allclose(d2, g.d2phi_dM2, rtol=1e-6, atol=1e-12 * np.max(np.abs(d2)))


def test_stretched_is_marko_first_order_when_not_resummed():
    F, M = 1.3 * PN, 7 * PNNM
    A, C = 45 * NM, 100 * NM
    s = ph.stretched_gibbs(F, M, A, C, KT, 1.0, False, False)
    g, _ = mk.wlc_free_energy_gain(F, A, KT)
    cs, _ = mk.stretched_twist_stiffness(F, A, C, KT)
    assert s.phi == pytest.approx(-g - M**2 / (2 * KT * cs), rel=1e-14, abs=0)
    assert -s.dphi_dF == pytest.approx(mk.stretched_extension_factor(M / (cs * KT), F, A, C, KT),
                                       rel=1e-14, abs=0)


def test_physical_loop_is_the_end_loop_excess_at_marko_coexistence():
    """At the Marko coexistence torque the loop's Gibbs energy is end_loop's eps*."""
    par = _par(softening=1.0, exponent=0.0, exact_wlc=False, resummed=False,
               melt_energy=np.inf, P0=20 * NM)
    F = np.array([0.5, 1.0, 2.0]) * PN
    mp = mk.marko_parameters(F, par.length, par.A, par.C, par.P0, KT)
    t = en.tail_gibbs(F, mp.torque, par)[0]
    eps = ph.end_loop_gibbs(t, mp.torque, par.A, par.C, KT, 1.0, 1.0)[0]
    gl = el.loop_tension(mp.gamma, mp.torque, par.C * KT)
    np.testing.assert_allclose(eps, el.loop_excess_free_energy(gl, mp.torque, par.A * KT, 1.0),
                               rtol=1e-12)


# ---- ensemble: Maxwell and derivatives of G ----------------------------------------------
CASES = {  # (turns, force): stretched, positive coexistence, negative (melting + plectoneme)
    "stretched": (3.0, 1.0), "coexistence": (14.0, 1.0), "low-force": (10.0, 0.3),
    "melted": (-20.0, 2.0), "negative-coexistence": (-24.0, 0.75),
}


@pytest.mark.parametrize("case", list(CASES))
@pytest.mark.parametrize(("finite_size", "effective_tension"),
                         [(True, False), (False, False), (True, True), (False, True)])
def test_extension_torque_are_derivatives_of_G_and_maxwell_holds(case, finite_size,
                                                                 effective_tension):
    """Every phase and coexistence, with the stretched phase as shipped and at the
    Moroz-Nelson effective tension (ensemble.md#211-effective-tension)."""
    N0, F0 = CASES[case]
    par = _par(finite_size=finite_size, effective_tension=effective_tension)
    hN, hF = 1e-3, 1e-4 * F0 * PN
    # one call for the point and the eight stencil points of the two differences
    steps = np.array([0.0, 1.0, -1.0, 2.0, -2.0])
    n = np.concatenate([N0 + hN * steps, np.full(4, N0)])
    f = np.concatenate([np.full(5, F0 * PN), F0 * PN + hF * steps[1:]])
    pts = en.points(n, f, par)

    def fd(values, h):  # fourth-order central difference over the stencil (+1, -1, +2, -2)
        return (8 * (values[0] - values[1]) - (values[2] - values[3])) / (12 * h)

    def along_n(name):
        return fd(getattr(pts, name)[1:5], hN)

    def along_f(name):
        return fd(getattr(pts, name)[5:9], hF)

    torque, extension = pts.torque[0], pts.extension[0]
    np.testing.assert_allclose(torque, along_n("free_energy") / TWO_PI, rtol=1e-6,
                               atol=1e-6 * PNNM)
    np.testing.assert_allclose(extension, -along_f("free_energy"), rtol=1e-6, atol=1e-6 * NM)
    dzdN, dMdF = along_n("extension"), along_f("torque")
    scale = max(abs(dzdN), 1e-9)  # m per turn
    assert abs(dzdN + TWO_PI * dMdF) <= 1e-6 * scale + 1e-6 * NM


def test_phases_present_in_the_cases():
    par = _par()
    pts = {k: en.points(np.array([n]), np.array([f * PN]), par) for k, (n, f) in CASES.items()}
    assert pts["stretched"].stretched_probability[0] > 0.99
    assert pts["coexistence"].domains[0] > 0.9
    assert pts["melted"].melted_length[0] > 50 * NM
    neg = pts["negative-coexistence"]
    assert neg.domains[0] > 0.1 and neg.melted_length[0] > 10 * NM  # both at once


# ---- limits ---------------------------------------------------------------------------
def test_limit_is_marko2007():
    """Every term off + the thermodynamic limit: marko2007 to 1e-12 (z bit-identical here)."""
    par = _par(softening=1.0, exponent=0.0, exact_wlc=False, resummed=False,
               melt_energy=np.inf, finite_size=False, P0=20 * NM)
    N = np.linspace(-60, 60, 97)
    for f in (0.5, 1.0, 2.0):
        F = np.full(N.shape, f * PN)
        a = en.points(N, F, par)
        b = mk.points(N, F, par.length, par.A, par.C, par.P0, KT)
        np.testing.assert_allclose(a.extension, b.extension, rtol=1e-12, atol=1e-12 * par.length)
        np.testing.assert_allclose(a.torque, b.torque, rtol=1e-12, atol=1e-12 * b.torque.max())
        np.testing.assert_allclose(a.free_energy, b.free_energy, rtol=1e-12,
                                   atol=1e-12 * np.abs(b.free_energy).max())
        assert np.array_equal(a.plectoneme_length > 0, b.tail_length < par.length)


def test_no_melting_is_the_stretched_phase_exactly():
    par = _par(melt_energy=np.inf)
    F, M = np.array([1e-12]), np.array([-15e-21])
    t, theta = en.tail_gibbs(F, M, par)
    s = ph.stretched_gibbs(F, M, par.A, par.C, KT, par.softening)
    assert all(np.array_equal(a, b) for a, b in zip(t, s, strict=True)) and theta[0] == 0.0


def test_melting_saturates_the_negative_torque():
    par = _par()
    N = np.array([-25.0, -30.0])
    p = en.points(N, np.full(2, 2 * PN), par)
    assert abs(p.torque[0] - p.torque[1]) < 0.1 * PNNM
    assert p.melted_length[1] > p.melted_length[0]


# ---- the model class ------------------------------------------------------------------
def _dna(L=1500.0):
    u = supercoil.ureg
    return supercoil.DNA(length=L * u.nm, bending_persistence=45 * u.nm,
                         twist_persistence=100 * u.nm, radius=1 * u.nm, temperature=296 * u.K).si


def test_model_registered_picklable_and_athermal_raises():
    m = get_model("ensemble")
    assert isinstance(m, Ensemble)
    assert pickle.loads(pickle.dumps(m)).values == m.values
    with pytest.raises(ModelError, match="athermal"):
        m.points(np.array([1.0]), np.array([1e-12]), _dna(), False)
    assert not m.has_free_energy(False) and m.has_free_energy(True)


def test_model_points_and_buckling_agree_with_the_limit():
    m = Ensemble(finite_size=False)
    dna = _dna()
    b = m.buckling(np.array([1e-12]), dna, True)
    N = np.array([b.turns[0] + 2.0, b.turns[0] + 4.0])
    pts = m.points(N, np.full(2, 1e-12), dna, True)
    assert pts.torque[0] == pytest.approx(b.torque[0], rel=1e-9, abs=0)
    assert (pts.extension[1] - pts.extension[0]) / 2.0 == pytest.approx(b.slope[0], rel=1e-9, abs=0)
    g = m.free_energy(N, np.full(2, 1e-12), dna, True)
    np.testing.assert_array_equal(g, pts.free_energy)


def test_fit_to_synthetic_data_recovers_parameters():
    true = dict(P0=13 * NM, exponent=0.25, softening=2.0)
    par = _par(max_domains=1, nodes=30, melt_energy=np.inf)
    N = np.concatenate([np.linspace(0, 30, 16), np.linspace(0, 20, 11)])
    F = np.concatenate([np.full(16, 1.5 * PN), np.full(11, 0.5 * PN)])
    ref = en.points(N, F, par._replace(**true))

    def res(x):
        p = en.points(N, F, par._replace(P0=x[0] * NM, exponent=x[1], softening=x[2]))
        return np.concatenate([(p.extension - ref.extension) / (10 * NM),
                               (p.torque - ref.torque) / (0.5 * PNNM)])

    fit = least_squares(res, [16.0, 0.1, 1.5], bounds=([5, -0.5, 0.5], [40, 0.9, 6]),
                        x_scale=[5, 0.2, 1], diff_step=1e-5)
    np.testing.assert_allclose(fit.x, [13.0, 0.25, 2.0], rtol=1e-3)


def test_forces_outside_the_evaluated_range_are_named_errors():
    """At 0.01 pN and 1e30 pN the coexistence solve left the float range with raw numpy
    warnings (found by the property sweep): now a ValidityError naming the force and range."""
    import warnings

    import supercoil as sc
    from supercoil.exceptions import ValidityError

    u = sc.ureg
    dna = sc.load_parameters("dna_150mM_nacl")
    for F in (0.01, 1e30):
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            with pytest.raises(ValidityError, match=r"ensemble model at force .* outside \[kT/"):
                sc.hat_curve(dna, F * u.pN, [0.0, 10.0], model="ensemble")


def test_no_finite_state_is_a_named_error():
    """A = 10 nm at 0.178 pN and -106 turns: every configuration failed and the ensemble
    subtracted inf from inf (a raw numpy warning, found by the family stability map)."""
    import warnings

    import supercoil as sc
    from supercoil.exceptions import ValidityError

    u = sc.ureg
    dna = sc.load_parameters("dna_150mM_nacl").replace(bending_persistence=10 * u.nm)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValidityError, match="no state of finite free energy"):
            sc.hat_curve(dna, 0.178 * u.pN, [-105.672, 0.0], model="ensemble")
