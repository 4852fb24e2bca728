"""The free-energy DNA model (docs/theory/free-energy.md): thermodynamic consistency.

References used here, each independent of the quantity under test:

* the Maxwell relation dz/dN|_F = -2 pi dM/dF|_N (central differences of the
  returned extension and torque: no formula of the model is reused);
* z = -dG/dF and M = (1/2 pi) dG/dN against central differences of G;
* the coexistence as a minimum: the constrained free energy at a trial S,
  maximised over the shared torque by an independent root solve, is above G;
* li-zhao's athermal construction (supercoil.core.hat_curve), the package's
  Moroz-Nelson zeta_inf, and the plectoneme equations' own residuals.

Finite-difference steps: in N, h = 1e-4 turn (z is linear in N in the
plectoneme phase; in the stretched phase the truncation, measured by refining
h, is 3e-10 relative at h = 1e-4 and 3e-8 at 1e-3); in F, h = 1e-5 F (refining
to 1e-6 F changes the difference by < 1e-9). The worst measured deviation is
1.6e-8, at 0.02 N_b where both sides are small; the tests assert 1e-6.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.optimize import elementwise
from seed_kernels import equilibrium_of

import supercoil as sc
from supercoil.core.dna import free_energy as fe
from supercoil.core.dna import interface as iface
from supercoil.core.dna import li_zhao as hc
from supercoil.core.dna import moroz_nelson as mn
from supercoil.core.dna import plectoneme as pl
from supercoil.dna.interactions.hard_core import HardCore
from supercoil.exceptions import ModelError, NoEquilibriumError, ValidityError, ValidityWarning

FORCES = np.array([0.3, 0.4, 1.2, 3.0, 5.0, 10.0]) * 1e-12
H_N, H_F = 1e-4, 1e-5




def _points(si, N, F, thermal=True):
    L, B, C, kT, _ = si
    N, F = np.broadcast_arrays(np.asarray(N, float), np.asarray(F, float))
    return fe.hat_points(N, F, L, B, C, kT, equilibrium_of(si), thermal)


def _turns(si, F):
    """Turns in each phase at force F: stretched, plectoneme (to 98 % coiled), coiled."""
    L, B, C, kT, _ = si
    co = fe.coexistence(np.array([F]), L, B, C, kT, equilibrium_of(si))
    Nb = co.buckling_turns[0]
    Nf = Nb + L * co.linking_rate[0] / (2 * np.pi)
    st = np.array([0.02, 0.5, 0.99]) * Nb
    pc = Nb + np.array([0.01, 0.3, 0.7, 0.98]) * (Nf - Nb)
    return st, pc, Nf * np.array([1.05, 1.3])


def _maxwell_ratio(si, N, F, thermal=True):
    dz = (_points(si, N + H_N, F, thermal).extension
          - _points(si, N - H_N, F, thermal).extension) / (2 * H_N)
    dM = (_points(si, N, F * (1 + H_F), thermal).torque
          - _points(si, N, F * (1 - H_F), thermal).torque) / (2 * H_F * F)
    return dz / (-2 * np.pi * dM)


@pytest.mark.parametrize("F", FORCES)
def test_maxwell_relation_both_phases(si, F):
    st, pc, _ = _turns(si, F)
    N = np.concatenate((st, pc, -st, -pc))
    ratio = _maxwell_ratio(si, N, F)
    np.testing.assert_allclose(ratio, 1.0, rtol=1e-6, atol=0)


def test_li_zhao_violates_maxwell(si):
    """The issue's measurement on li-zhao (0.3-5 pN): 1.5-2.0 before buckling, 0.67-0.95 after."""
    L, B, C, kT, r0 = si
    for F in FORCES[:-1]:
        par = hc.hat_parameters(np.array([F]), L, B, C, kT, r0)
        Nb = par.buckling_turns[0]
        N = np.array([0.99 * Nb, Nb + 0.3 * L * par.linking_rate[0] / (2 * np.pi)])

        def pts(n, f):
            return hc.hat_curve_points(n, np.full_like(n, f), L, B, C, kT, r0)

        dz = (pts(N + H_N, F).extension - pts(N - H_N, F).extension) / (2 * H_N)
        dM = (pts(N, F * (1 + H_F)).torque - pts(N, F * (1 - H_F)).torque) / (2 * H_F * F)
        before, after = dz / (-2 * np.pi * dM)
        assert 1.45 < before < 2.0
        assert 0.67 < after < 0.95


@given(force=st.floats(0.3, 10.0), frac=st.floats(0.02, 0.98), plectoneme=st.booleans(),
       sign=st.sampled_from([-1.0, 1.0]))
def test_maxwell_relation_property(si, force, frac, plectoneme, sign):
    """Anywhere in 0.3-10 pN and in either phase (away from the boundary by 2 % of it)."""
    L, B, C, kT, _ = si
    F = force * 1e-12
    co = fe.coexistence(np.array([F]), L, B, C, kT, equilibrium_of(si))
    Nb = co.buckling_turns[0]
    N = Nb + frac * L * co.linking_rate[0] / (2 * np.pi) if plectoneme else frac * Nb
    ratio = _maxwell_ratio(si, np.array([sign * N]), F)
    assert abs(ratio[0] - 1.0) < 1e-6


@pytest.mark.parametrize("F", [0.4e-12, 3e-12])
def test_fully_coiled_is_consistent(si, F):
    """Beyond full coiling z = 0 and M depends on N only; M = (1/2 pi) dG/dN still holds."""
    _, _, coiled = _turns(si, F)
    p = _points(si, coiled, F)
    assert np.all(p.phase == iface.FULLY_COILED) and np.all(p.extension == 0.0)
    assert np.all(p.short_tail) and np.all(p.plectoneme_length == si[0])
    # tails shorter than 3 B/kT are flagged in the plectoneme phase too, longer ones not
    _, pc, _ = _turns(si, F)
    q = _points(si, pc, F)
    tail = si[0] - q.plectoneme_length
    np.testing.assert_array_equal(q.short_tail, tail < 3 * si[1] / si[3])
    assert q.short_tail[-1] and not q.short_tail[0]
    dM = _points(si, coiled, F * (1 + H_F)).torque - p.torque
    np.testing.assert_allclose(dM, 0.0, atol=1e-12 * p.torque.max())
    # the torque rises beyond full coiling (the plectoneme is twisted further)
    assert np.all(np.diff(p.torque) > 0) and p.torque[0] > fe.coexistence(
        np.array([F]), *si[:4], equilibrium_of(si)).torque[0]


@pytest.mark.parametrize("F", [0.3e-12, 1.2e-12, 10e-12])
def test_extension_and_torque_are_derivatives_of_G(si, F):
    st, pc, coiled = _turns(si, F)
    N = np.concatenate((st, pc, coiled[:1], -pc[1:2]))
    p = _points(si, N, F)
    dGdN = (_points(si, N + H_N, F).free_energy - _points(si, N - H_N, F).free_energy) / (
        2 * H_N)
    dGdF = (_points(si, N, F * (1 + H_F)).free_energy
            - _points(si, N, F * (1 - H_F)).free_energy) / (2 * H_F * F)
    np.testing.assert_allclose(dGdN / (2 * np.pi), p.torque, rtol=1e-7)
    z = p.extension
    ok = z > 0
    np.testing.assert_allclose(-dGdF[ok], z[ok], rtol=1e-6)
    # fully coiled: G does not depend on F (no tail), to rounding of G ~ F L
    assert np.all(np.abs(dGdF[~ok]) < 1e-9 * si[0])


def _constrained_G(si, N, F, S, eq):
    """max over M of (L - S) g_s(F, M) + S g_p(M) + 2 pi N M, M = M_p(T) over the tension T."""
    L, B, C, kT, _ = si

    def dG_dM(T):  # -(L - S) l_s - S l_p + 2 pi N, decreasing in T (M increases with T)
        st = eq(T)
        _, _, ls = fe.tail_free_energy(F, st.torque, B, C, kT)
        return -(L - S) * ls - S * (st.torque / C + st.torsion) + 2 * np.pi * N

    res = elementwise.find_root(dG_dM, (0.2 * F, 0.999 * F))
    st = eq(res.x)
    gs, _, _ = fe.tail_free_energy(F, st.torque, B, C, kT)
    gp = -res.x - st.torque**2 / (2 * C)
    return (L - S) * gs + S * gp + 2 * np.pi * N * st.torque


@pytest.mark.parametrize("F", [0.4e-12, 3e-12])
def test_coexistence_is_a_minimum_in_S(si, F):
    _, pc, _ = _turns(si, F)
    N = pc[1]
    p = _points(si, N, F)
    S0, G0 = float(p.plectoneme_length), float(p.free_energy)
    eq = equilibrium_of(si)
    rel = np.array([-0.05, -0.01, 0.0, 0.01, 0.05])
    S = S0 * (1 + rel)
    G = np.array([_constrained_G(si, N, F, s, eq) for s in S])
    kT = si[3]
    assert abs(G[2] - G0) < 1e-9 * kT * 1e3  # the solved S is the stationary point
    excess = G - G0
    assert np.all(excess[[0, 1, 3, 4]] > 0)
    # a minimum, not just a higher value: the excess grows quadratically (25x for 5x)
    np.testing.assert_allclose(excess[[0, 4]] / excess[[1, 3]], 25.0, rtol=0.05)


def test_athermal_limit_equals_li_zhao_athermal(si):
    L, B, C, kT, r0 = si
    N = np.linspace(-40, 40, 801)
    for F in FORCES:
        f = np.full_like(N, F)
        p = _points(si, N, f, thermal=False)
        q = hc.hat_curve_points(N, f, L, B, C, kT, r0, thermal=False)
        for name in ("extension", "plectoneme_length", "phase", "short_tail", "zeta"):
            np.testing.assert_array_equal(getattr(p, name), getattr(q, name), err_msg=name)
        # torque equal except beyond full coiling, where li-zhao keeps M_p by convention
        keep = q.phase != iface.FULLY_COILED
        np.testing.assert_array_equal(p.torque[keep], q.torque[keep])
        # closed form of the athermal stretched phase: twist energy minus F z
        st = p.phase == iface.STRETCHED
        np.testing.assert_allclose(p.free_energy[st],
                                   -F * L + (2 * np.pi * N[st]) ** 2 * C / (2 * L), rtol=1e-13)
    co = fe.coexistence(FORCES, L, B, C, kT, equilibrium_of(si), thermal=False)
    par = hc.hat_parameters(FORCES, L, B, C, kT, r0, thermal=False)
    np.testing.assert_array_equal(co.buckling_turns, par.buckling_turns)
    np.testing.assert_array_equal(co.slope, par.slope)
    np.testing.assert_array_equal(co.torque, par.torque)


def test_free_energy_at_zero_turns_is_the_moroz_nelson_chain(si):
    """G(0, F) = L (-F + (kT^2/B) sqrt(B F/kT^2 - 1/32)): the untwisted fluctuating chain."""
    L, B, _, kT, _ = si
    G = _points(si, np.zeros(FORCES.size), FORCES).free_energy
    np.testing.assert_allclose(G, L * (-FORCES + kT**2 / B * np.sqrt(B * FORCES / kT**2
                                                                      - 1 / 32)), rtol=1e-14)


def test_symmetry_in_turns(si):
    for F in (0.4e-12, 5e-12):
        st, pc, coiled = _turns(si, F)
        N = np.concatenate((st, pc, coiled))
        a, b = _points(si, N, F), _points(si, -N, F)
        for name in ("extension", "plectoneme_length", "phase", "free_energy", "zeta"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name))
        np.testing.assert_array_equal(a.torque, -b.torque)


def test_coexistence_reduces_to_plectoneme_equations_at_effective_pull(si):
    """(GE1), (GE2) and T = -B kappa^2/2 + C omega tau - w hold with T = T_eff, and
    g_s(F, M*) = g_p(M*) (equal free energy at equal torque)."""
    L, B, C, kT, r0 = si
    co = fe.coexistence(FORCES, L, B, C, kT, equilibrium_of(si))
    st = pl.equilibrium(co.pull, B, C, kT, r0)
    for r in pl.hard_core_residuals(co.pull, st.alpha, st.radius, co.torque / C,
                                      B, C, kT, r0):
        assert np.max(np.abs(r)) < 1e-11
    np.testing.assert_allclose(co.torsion, st.torsion, rtol=1e-12)
    gs, zinf, ls = fe.tail_free_energy(FORCES, co.torque, B, C, kT)
    np.testing.assert_allclose(gs, -co.pull - co.torque**2 / (2 * C), rtol=1e-13)
    # the pull is F minus the tail's fluctuation term, below F and above F - sqrt(kT F / A)
    np.testing.assert_allclose(co.pull, FORCES - kT**2 / B * np.sqrt(co.bracket), rtol=1e-12)
    assert np.all(co.pull < FORCES) and np.all(co.pull > FORCES - np.sqrt(kT * FORCES * kT / B))
    # zeta_inf is the package's Moroz-Nelson long-tail factor at M*
    np.testing.assert_allclose(zinf, mn.long_tail_factor(FORCES, co.torque, B, kT), rtol=1e-14)
    np.testing.assert_allclose(co.buckling_turns, ls * L / (2 * np.pi), rtol=1e-14)


def test_tail_free_energy_derivatives(si):
    """-dg_s/dF = zeta_inf and -dg_s/dM = l_s (central differences), and at M -> 0 and
    large force l_s/M tends to the Moroz-Nelson 1/C_eff (the -1/32 is then negligible)."""
    _, B, C, kT, _ = si
    F = np.array([0.3e-12, 2e-12, 10e-12])
    M = np.array([5e-21, 15e-21, 40e-21])
    _, zinf, ls = fe.tail_free_energy(F, M, B, C, kT)
    hF, hM = 1e-6 * F, 1e-6 * M
    dF = (fe.tail_free_energy(F + hF, M, B, C, kT)[0]
          - fe.tail_free_energy(F - hF, M, B, C, kT)[0]) / (2 * hF)
    dM = (fe.tail_free_energy(F, M + hM, B, C, kT)[0]
          - fe.tail_free_energy(F, M - hM, B, C, kT)[0]) / (2 * hM)
    np.testing.assert_allclose(-dF, zinf, rtol=1e-8)
    np.testing.assert_allclose(-dM, ls, rtol=1e-7)
    small = 1e-25
    ls0 = fe.tail_free_energy(F, small, B, C, kT)[2] / small
    ceff = mn.effective_twist_rigidity(F, B, C, kT)
    assert abs(ls0[-1] * ceff[-1] - 1) < 1e-3


def test_tail_torque_inverts_linking(si):
    _, B, C, kT, _ = si
    F = np.full(5, 1.2e-12)
    x = np.array([0.0, 1e-6, 1e3, 1e6, 5e7])
    M = fe.tail_torque(x, F, B, C, kT)
    assert M[0] == 0.0
    _, _, ls = fe.tail_free_energy(F[1:], M[1:], B, C, kT)
    np.testing.assert_allclose(ls, x[1:], rtol=4e-16 * 8)


def test_validity_errors_name_the_force(si):
    L, B, C, kT, _ = si
    eq = equilibrium_of(si)
    with pytest.raises(ValidityError, match=r"0\.05 pN.*no positive tension"):
        fe.coexistence(np.array([0.05e-12]), L, B, C, kT, eq)
    with pytest.raises(ValidityError, match=r"60 pN.*bracket .* not positive"):
        fe.coexistence(np.array([60e-12]), L, B, C, kT, eq)
    with pytest.raises(ValidityError, match="bracket"):
        fe.tail_free_energy(1e-12, 1e-19, B, C, kT)
    with pytest.raises(NoEquilibriumError):  # the athermal model needs only the plectoneme
        fe.coexistence(np.array([-1e-12]), L, B, C, kT, eq, thermal=False)
    with pytest.raises(ValueError, match="finite"):
        _points(si, np.nan, 1e-12)


# ---------------------------------------------------------------------------
# the model class on the DNA model interface
# ---------------------------------------------------------------------------


def test_model_class_wraps_the_kernel(si):
    import pickle

    from supercoil.dna.models.free_energy import FreeEnergy

    dna = sc.load_parameters("dna").si
    model = pickle.loads(pickle.dumps(FreeEnergy()))
    assert model.name == "free-energy" and model.has_free_energy(True)
    assert model.has_free_energy(False)
    F = np.repeat(FORCES[:3], 5)
    N = np.tile(np.linspace(-12, 12, 5), 3)
    p = model.points(N, F, dna, True, HardCore(), None)
    q = _points(si, N, F)
    for name in q._fields:
        np.testing.assert_array_equal(getattr(p, name), getattr(q, name))
    np.testing.assert_array_equal(model.free_energy(N, F, dna, True, HardCore()), q.free_energy)
    b = model.buckling(FORCES, dna, True, HardCore())
    co = fe.coexistence(FORCES, *si[:4], equilibrium_of(si))
    np.testing.assert_array_equal(b.turns, co.buckling_turns)
    np.testing.assert_array_equal(b.slope, co.slope)
    assert model._validity(N, F, p, dna, True) == []


@pytest.mark.parametrize(("force", "words"), [(0.105e-12, "<= 0"), (0.15e-12, "not converged")])
def test_model_validity_messages(force, words):
    from supercoil.dna.models.free_energy import FreeEnergy

    dna = sc.load_parameters("dna").si
    N = np.array([0.0, 3.0, 8.0])  # stretched, stretched, plectoneme
    F = np.full(3, force)
    p = FreeEnergy().points(N, F, dna, True, HardCore(), None)
    msgs = FreeEnergy()._validity(N, F, p, dna, True)
    assert len(msgs) == 1 and words in msgs[0] and f"{force * 1e12:.6g} pN" in msgs[0]
    assert FreeEnergy()._validity(N, F, p, dna, False) == []


def test_model_through_the_public_functions(dna):
    """Same columns for both models plus free_energy; named error where there is none."""
    u = sc.ureg
    F = [0.4, 3.0] * u.pN
    turns = np.linspace(0, 30, 7)  # positive (no denaturation warning), to full coiling
    fe_df = sc.hat_curve(dna, F, turns, model="free-energy", thermal=False)
    lz_df = sc.hat_curve(dna, F, turns, model="li-zhao", thermal=False)
    assert "free_energy" in fe_df.columns and "free_energy" not in lz_df.columns
    assert [c for c in fe_df.columns if c != "free_energy"] == list(lz_df.columns)
    keep = lz_df["phase"] != "fully coiled"
    for col in ("extension", "torque", "plectoneme_length"):
        np.testing.assert_array_equal(fe_df[col][keep], lz_df[col][keep])
    G = sc.free_energy(dna, F, turns, model="free-energy", thermal=False)
    np.testing.assert_allclose(G.to("pN nm").magnitude, fe_df["free_energy"], rtol=1e-15)
    with pytest.raises(ModelError, match=r"li-zhao.*thermal=True is not derived"):
        sc.free_energy(dna, F, turns, model="li-zhao")
    with pytest.raises(ModelError, match="exactly model='free-energy', thermal=False"):
        sc.free_energy(dna, F, turns, model="li-zhao", thermal=False)
    nb_fe = sc.buckling_turns(dna, F, model="free-energy")
    nb_lz = sc.buckling_turns(dna, F, model="li-zhao")
    assert np.all(nb_fe < nb_lz)  # the tail's effective pull lowers the buckling torque
    with pytest.warns(ValidityWarning, match="free-energy model: Moroz-Nelson expansion"):
        sc.post_buckling_slope(dna, 0.15 * u.pN, model="free-energy")
    with pytest.warns(ValidityWarning, match="not converged at force 0.15 pN, turns 8"):
        sc.hat_curve(dna, 0.15 * u.pN, [0.0, 8.0], model="free-energy")


def test_fully_coiled_state_does_not_depend_on_force(si):
    """With no tail left, F drops out: the same torque and G at 0.3 and 5 pN, far past
    full coiling; beyond the plectoneme's range the error names the turns."""
    N = np.array([50.0, 200.0, 800.0])
    a, b = _points(si, N, 0.3e-12), _points(si, N, 5e-12)
    assert np.all(a.phase == iface.FULLY_COILED) and np.all(b.phase == iface.FULLY_COILED)
    np.testing.assert_allclose(a.torque, b.torque, rtol=1e-12)
    np.testing.assert_allclose(a.free_energy, b.free_energy, rtol=1e-12)
    with pytest.raises(NoEquilibriumError, match=r"fully coiled plectoneme for \|N\| up to 20000"):
        _points(si, [20000.0], 1e-12)


def test_state_recorder_sees_final_fully_coiled_states_only(si):
    """The public layer's recorder gets the coexistence solves and one final solve at the
    extreme tensions of the fully coiled points (here their two), not the secant's trials
    (which could trip R < r0 spuriously)."""
    from supercoil.dna.models.free_energy import FreeEnergy
    from supercoil.dna.validity import StateRecorder

    dna = sc.load_parameters("dna").si
    rec = StateRecorder(HardCore())
    N = np.array([2.0, 10.0, 40.0, 60.0])
    F = np.full(4, 1.2e-12)
    p = FreeEnergy().points(N, F, dna, True, rec, None)
    coiled = p.phase == iface.FULLY_COILED
    assert coiled.sum() == 2
    assert len(rec.states) == 4  # three Newton solves of the pull, one final coiled solve
    assert np.all(rec.states[-1].force > 1.2e-12) and rec.states[-1].force.size == 2
    np.testing.assert_array_equal(rec.states[-1].torque, p.torque[coiled])


@pytest.mark.parametrize(("name", "sets"), [("hard-core", ["dna", "dna_150mM_nacl"]),
                                            ("screened", ["dna_10mM_nacl", "dna_1M_nacl"])])
def test_the_superhelix_radius_does_not_grow_with_the_tension(name, sets):
    """What record_extremes rests on: along the plectoneme branch R(T) is non-increasing
    (A = 10-200 nm, 0.01-60 pN), so R < r0 holds on a set of the largest tensions."""
    import warnings

    from supercoil.dna.interactions import get_interaction

    inter = get_interaction(name)
    for s in sets:
        for A in (10.0, 50.0, 200.0):
            dna = sc.load_parameters(s).replace(bending_persistence=A * sc.ureg.nm).si
            with warnings.catch_warnings():  # the screened near-field validity warning
                warnings.simplefilter("ignore", sc.SupercoilWarning)
                R = inter.equilibrium(np.geomspace(0.01e-12, 60e-12, 400), dna).radius
            assert np.all(np.diff(R) <= 0.0), (s, A)


def test_public_radius_warning_of_many_fully_coiled_points_is_the_exhaustive_one():
    """The R < r0 warning of a public free-energy hat curve whose fully coiled points reach
    the strands' contact (150 mM, hard-core: R < r0 = 1 nm at the highest tensions) is
    the one plectoneme_messages gives on the states of every fully coiled point, solved
    here independently."""
    import warnings

    from supercoil.dna.interactions import HardCore
    from supercoil.dna.validity import plectoneme_messages

    dna = sc.load_parameters("dna_150mM_nacl").replace(length=1 * sc.ureg.um)
    si = dna.si
    N = np.linspace(0.0, 0.99 * si.length / 3.57e-9, 3000)  # to |sigma| = 0.99
    with warnings.catch_warnings(record=True) as rec:
        warnings.simplefilter("always")
        df = sc.hat_curve(dna, 1.0 * sc.ureg.pN, N, model="free-energy")
    coiled = (df["phase"] == "fully coiled").to_numpy()
    assert coiled.sum() > 1000
    p = fe.hat_points(N, np.full(N.size, 1e-12), si.length, si.bending_rigidity,
                      si.torsional_rigidity, si.kT, lambda T: HardCore().equilibrium(T, si))
    M = np.asarray(p.torque)[coiled]
    T = -(np.asarray(p.free_energy)[coiled] - 2 * np.pi * N[coiled] * M) / si.length \
        - M * M / (2 * si.torsional_rigidity)
    want = plectoneme_messages(HardCore().equilibrium(np.sort(T), si), si)
    assert want, "the case must reach R < r0"
    got = [str(w.message) for w in rec if "superhelix radius" in str(w.message)]
    assert got == want


@pytest.mark.parametrize("block", [1, 2, 1 << 15])
def test_validity_shortcut_agrees_with_the_messages(block):
    """The block-by-block reduction (Q >= 1 wherever not fully coiled) is True exactly where
    the message function finds nothing, at forces on both sides of the limits."""
    from supercoil.dna.models import free_energy as fem

    dna = sc.load_parameters("dna").si
    N = np.array([0.0, 3.0, 8.0, 30.0])
    for force in (0.105e-12, 0.15e-12, 0.5e-12, 3e-12):
        F = np.full(N.size, force)
        p = fem.FreeEnergy().points(N, F, dna, True, HardCore(), None)
        quiet = fem._converged_everywhere(F, np.asarray(p.torque), np.asarray(p.phase), dna,
                                          block=block)
        Q = fe.tail_bracket(F, np.asarray(p.torque), dna.bending_rigidity, dna.kT)
        full = fem._messages(F, Q, np.asarray(p.phase) != fe.FULLY_COILED, str)  # all masks
        assert quiet == (full == [])
        assert quiet == (force >= 0.5e-12)


def test_no_tail_bracket_at_zero_torque_is_a_named_error():
    """Below F = kT^2 / (32 B) even the untwisted tail has no Moroz-Nelson free energy: a
    ValidityError naming the bracket (it was a numpy RuntimeWarning from sqrt, found by the
    family stability map at A = 10 nm, 0.01 pN)."""
    import warnings

    import supercoil as sc
    from supercoil.exceptions import ValidityError

    u = sc.ureg
    dna = sc.load_parameters("dna_150mM_nacl").replace(bending_persistence=10 * u.nm)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(ValidityError, match=r"force 0.01 pN, torque 0 pN nm: its bracket"):
            sc.hat_curve(dna, 0.01 * u.pN, [0.0, 5.0], model="free-energy")
