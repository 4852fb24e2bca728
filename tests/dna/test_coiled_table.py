"""Fully coiled free-energy points by the Chebyshev table (supercoil.core.dna.coiled_table).

References, independent of the table:

* scipy ``brentq`` per point on the real equilibrium, to 1e-15 in u = log T;
* the per-point safeguarded secant the table replaced (copied below as it was), which
  stops within 1e-13 of the root in u.

The table must agree with brentq to 1e-13 relative in M and T (measured: <= 6e-14,
typically 5e-15) and with the old secant to 2e-13 (the secant's own tolerance). Where
the table cannot resolve the branch (few points, a kink, a capped degree) the result
is the old secant's, bit for bit.
"""

import numpy as np
import pytest
from scipy.optimize import brentq
from seed_kernels import equilibrium_of

import supercoil as sc
from supercoil.core.dna import coiled_table as ct
from supercoil.core.dna import end_loop as el
from supercoil.core.dna import free_energy as fe
from supercoil.exceptions import NoEquilibriumError, ValidityError


def _old_secant(x, pull, helix_linking, C, equilibrium, loop=None):
    """plectoneme_torque_at_linking before the table (commit 4a3bbe7), verbatim in substance."""
    ua = np.log(pull)
    ra = helix_linking - x
    ub = ua + np.maximum(2.0 * np.log(x / helix_linking), 1e-6)
    lo, hi = ua.copy(), np.full(x.shape, np.inf)
    act = np.ones(x.shape, bool)
    M_out, T_out = np.empty(x.shape), np.empty(x.shape)
    for _ in range(60):
        T_out[act] = np.exp(ub[act])
        st = equilibrium(T_out[act])
        M, tau = st.torque, st.torsion
        M_out[act] = M
        rb = np.zeros(x.shape)
        if loop is None:
            rb[act] = M / C + tau - x[act]
        else:
            rb[act] = M / C + tau * (1.0 - el.loop_length(T_out[act], loop[0]) / loop[1]) \
                - x[act]
        lo = np.where(act & (rb < 0.0), ub, lo)
        hi = np.where(act & (rb >= 0.0), np.minimum(hi, ub), hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            un = ub - rb * (ub - ua) / (rb - ra)
        bad = ~np.isfinite(un) | (un < lo) | (un > hi)
        un = np.where(bad & np.isfinite(hi), 0.5 * (lo + hi), un)
        un = np.where(bad & ~np.isfinite(hi), ub + 1.0, un)
        un = np.where(np.isfinite(hi), un, np.minimum(un, ub + 2.0))
        un = np.where(act, un, ub)
        ua, ra = np.where(act, ub, ua), np.where(act, rb, ra)
        act &= np.abs(un - ub) > 1e-13
        ub = un
        if not np.any(act):
            return M_out, T_out
    raise AssertionError("old secant did not converge")


def _brentq(x, C, equilibrium, loop):
    def f(u):
        T = np.array([np.exp(u)])
        s = equilibrium(T)
        return ct.branch_linking(s.torque, s.torsion, T, C, loop)[0] - x

    u = brentq(f, np.log(1e-14), np.log(1e-8), xtol=1e-15, rtol=1e-15)
    return equilibrium(np.array([np.exp(u)])).torque[0], np.exp(u)


def _problem(si, F, end_loop):
    """(pull, l_p at the pull, loop, linking at full coiling) at force F."""
    L, B, C, kT, _ = si
    co = fe.coexistence(np.array([F]), L, B, C, kT, equilibrium_of(si))
    if end_loop:
        lc = fe.loop_constants(co, L, B, C, kT)
        start = co.torque[0] / C + co.torsion[0] * (1.0 - lc.length[0] / L)
        return co.pull[0], start, (B, L), start
    start = co.torque[0] / C + co.torsion[0]
    return co.pull[0], start, None, start


CASES = [(F, loop) for F in (0.3e-12, 1.2e-12, 3e-12, 10e-12) for loop in (False, True)
         if not (loop and F < 1e-12)]  # the loop does not delay buckling below ~1 pN


@pytest.mark.parametrize(("F", "end_loop"), CASES)
@pytest.mark.parametrize("turns", ["to 3x full coiling", "60-800"])
def test_table_matches_brentq_and_the_old_secant(si, F, end_loop, turns):
    L, _, C, _, _ = si
    pull, start, loop, x_full = _problem(si, F, end_loop)
    x = (np.linspace(1.0 + 1e-6, 3.0, 400) * x_full if turns != "60-800"
         else 2 * np.pi * np.linspace(60.0, 800.0, 400) / L)
    p, s = np.full(x.size, pull), np.full(x.size, start)
    M, T = fe.plectoneme_torque_at_linking(x, p, s, C, equilibrium_of(si), loop)
    M0, T0 = _old_secant(x, p, s, C, equilibrium_of(si), loop)
    np.testing.assert_allclose(M, M0, rtol=2e-13)
    np.testing.assert_allclose(T, T0, rtol=2e-13)
    idx = np.linspace(0, x.size - 1, 7).astype(int)
    ref = np.array([_brentq(x[i], C, equilibrium_of(si), loop) for i in idx])
    np.testing.assert_allclose(M[idx], ref[:, 0], rtol=1e-13)
    np.testing.assert_allclose(T[idx], ref[:, 1], rtol=1e-13)
    # the table itself resolves these points (no fallback to the secant), also on a
    # domain 1 % wider than the largest root (another table: within 3e-13)
    got = ct.torque_at_linking(x, (pull, T.max() * 1.01), C, equilibrium_of(si), loop)
    assert got is not None
    np.testing.assert_allclose(got[0], M, rtol=3e-13)
    np.testing.assert_allclose(got[1], T, rtol=3e-13)


@pytest.mark.parametrize("n", [1, ct.MIN_POINTS - 1, ct.MIN_POINTS, 12, 2000])
def test_small_and_large_calls(si, n):
    """Below MIN_POINTS the secant on all points (bit-identical to the old one), above the
    table; both agree with brentq."""
    _, _, C, _, _ = si
    pull, start, loop, x_full = _problem(si, 1.2e-12, False)
    x = np.linspace(1.0 + 1e-6, 1.5, n) * x_full
    p, s = np.full(n, pull), np.full(n, start)
    M, T = fe.plectoneme_torque_at_linking(x, p, s, C, equilibrium_of(si), loop)
    M0, T0 = _old_secant(x, p, s, C, equilibrium_of(si), loop)
    if n < ct.MIN_POINTS:
        np.testing.assert_array_equal(M, M0)
        np.testing.assert_array_equal(T, T0)
    np.testing.assert_allclose(M, M0, rtol=2e-13)
    np.testing.assert_allclose(T, T0, rtol=2e-13)
    m, t = _brentq(x[-1], C, equilibrium_of(si), loop)
    np.testing.assert_allclose([M[-1], T[-1]], [m, t], rtol=1e-13)


def test_several_forces_in_one_call(si):
    """One table over the smallest T_eff serves every force (l_p does not depend on F)."""
    L, B, C, kT, _ = si
    F = np.repeat([0.3e-12, 1.2e-12, 10e-12], 50)
    N = np.tile(np.linspace(50.0, 150.0, 50), 3)
    p = fe.hat_points(N, F, L, B, C, kT, equilibrium_of(si))
    assert np.all(p.phase == fe.FULLY_COILED)
    for f in (0.3e-12, 1.2e-12, 10e-12):
        q = fe.hat_points(N[F == f], F[F == f], L, B, C, kT, equilibrium_of(si))
        np.testing.assert_allclose(p.torque[F == f], q.torque, rtol=1e-13)
        np.testing.assert_allclose(p.free_energy[F == f], q.free_energy, rtol=1e-13)
    # the same torque at each force: it depends on N only
    np.testing.assert_allclose(p.torque[:50], p.torque[100:], rtol=1e-13)


def test_unresolved_table_falls_back_to_the_secant(si, monkeypatch):
    """A table that does not converge (here: degree capped at 8) returns None; the points
    are then solved by the secant exactly as before."""
    _, _, C, _, _ = si
    pull, start, loop, x_full = _problem(si, 0.3e-12, False)
    x = np.linspace(1.0 + 1e-6, 3.0, 50) * x_full
    p, s = np.full(x.size, pull), np.full(x.size, start)
    monkeypatch.setattr(ct, "MAX_DEGREE", 8)
    M, T = fe.plectoneme_torque_at_linking(x, p, s, C, equilibrium_of(si), loop)
    M0, T0 = _old_secant(x, p, s, C, equilibrium_of(si), loop)
    np.testing.assert_array_equal(M, M0)
    np.testing.assert_array_equal(T, T0)


def test_out_of_range_still_names_the_turns(si):
    """Beyond the plectoneme's range the error comes from the top point's secant."""
    L, B, C, kT, _ = si
    N = np.concatenate([np.linspace(30.0, 60.0, 20), [20000.0]])
    with pytest.raises(NoEquilibriumError, match=r"fully coiled plectoneme for \|N\| up to 20000"):
        fe.hat_points(N, np.full(N.size, 1e-12), L, B, C, kT, equilibrium_of(si))


def test_kinked_branch_falls_back_to_the_secant():
    """A branch with a kink in l_p (as where the screened interaction's strands reach hard
    contact, R = a): the coefficients decay as a power, the table gives up by degree 64
    (its first doubling) and the secant solves, bit-identical to the old one."""
    from types import SimpleNamespace

    C, Tk = 4e-28, 2e-11

    def equilibrium(T):
        T = np.asarray(T, float)
        M = 1e-20 * np.sqrt(T / 1e-12)
        tau = 1e8 * (T / 1e-12) ** 0.3 * np.where(T > Tk, 0.5 + 0.5 * (T / Tk) ** 0.5, 1.0)
        return SimpleNamespace(torque=M, torsion=tau)

    T0 = 1e-12
    l0 = 1e-20 / C + 1e8
    x = np.linspace(1.001, 4.0, 40) * l0
    p, s = np.full(x.size, T0), np.full(x.size, l0)
    _, T_hi = ct.secant(x[-1:], p[-1:], s[-1:], C, equilibrium, None)
    assert T_hi[0] > Tk  # the kink lies inside the domain
    calls = []

    def counted(T):
        calls.append(np.size(T))
        return equilibrium(T)

    assert ct.torque_at_linking(x, (T0, T_hi[0] * 1.01), C, counted, None) is None
    assert calls == [ct.START_DEGREE + 1, ct.START_DEGREE]  # gave up at 64, not 128
    M, T = fe.plectoneme_torque_at_linking(x, p, s, C, equilibrium)
    M0, T0_ = _old_secant(x, p, s, C, equilibrium)
    np.testing.assert_array_equal(M, M0)
    np.testing.assert_array_equal(T, T0_)


def _jumping_branch(Tj=2e-11, C=4e-28):
    """A branch whose torsion jumps up by half at Tj (strands snapping into contact)."""
    from types import SimpleNamespace

    def equilibrium(T):
        T = np.asarray(T, float)
        M = 1e-20 * np.sqrt(T / 1e-12)
        tau = 1e8 * (T / 1e-12) ** 0.3 * np.where(T > Tj, 1.5, 1.0)
        return SimpleNamespace(torque=M, torsion=tau)

    def linking(T):
        return 1e-20 * np.sqrt(T / 1e-12) / C + 1e8 * (T / 1e-12) ** 0.3 * np.where(
            T > Tj, 1.5, 1.0)

    return equilibrium, linking, C


def test_a_jump_of_the_branch_is_named_and_roots_beside_it_are_found():
    """Targets inside a jump of l_p have no root: a named ValidityError (was: the secant
    crept towards the jump until its 60 steps ran out), found by bisection within a few
    dozen steps; targets below and above the jump still solve to 1e-13."""
    equilibrium, linking, C = _jumping_branch()
    T0, Tj = 1e-12, 2e-11
    l0 = linking(T0)
    below, above = linking(Tj), linking(Tj * (1 + 1e-9))
    inside = 0.5 * (below + above)
    for x, root in ((0.999 * below, True), (1.001 * above, True), (inside, False)):
        xs = np.array([x])
        p, s = np.array([T0]), np.array([l0])
        calls = []

        def counted(T, calls=calls):
            calls.append(1)
            return equilibrium(T)

        if root:
            _, T = ct.secant(xs, p, s, C, counted, None)
            assert linking(T)[0] == pytest.approx(x, rel=1e-12)
        else:
            with pytest.raises(ValidityError, match="linking per length jumps at tension 20 pN"):
                ct.secant(xs, p, s, C, counted, None)
        assert len(calls) < 60


@pytest.mark.filterwarnings("ignore::supercoil.exceptions.ValidityWarning")
def test_the_screened_jump_to_contact_is_named_for_fully_coiled_turns():
    """10 mM NaCl (screened, strands snap into contact at ~5 pN): 300 turns at 1.2 pN
    fully coil past the jump of the branch; 200 turns fully coil below it."""
    dna = sc.load_parameters("dna_10mM_nacl")
    f = 1.2 * sc.ureg.pN
    df = sc.hat_curve(dna, f, [200.0], model="free-energy", interaction="screened")
    assert df.phase[0] == "fully coiled"
    with pytest.raises(ValidityError, match=r"\|N\| up to 300 turns.*jumps at tension 5\.0"):
        sc.hat_curve(dna, f, [300.0], model="free-energy", interaction="screened")


@pytest.mark.parametrize("end_loop", [False, True])
@pytest.mark.parametrize("path", ["inverse", "series"])
def test_hat_points_to_full_coiling_match_the_direct_solve(si, end_loop, path, monkeypatch):
    """hat_points solves its fully coiled points from one table of the branch per call:
    the cubic inverse (coiled_table.inverse_of, from INVERSE_MIN_POINTS points) or Newton
    on the Chebyshev series (fewer): torque and free energy agree with the direct solve
    per point (the secant on every point, and brentq on seven) to 1e-12, far inside the
    1e-8 the fits need; extension is 0 there by construction, and the other phases are
    untouched (bit for bit the same as without the table)."""
    monkeypatch.setattr(ct, "INVERSE_MIN_POINTS", 0 if path == "inverse" else 10**9)
    used = []
    evaluate = ct.evaluate_inverse
    monkeypatch.setattr(ct, "evaluate_inverse", lambda *a: used.append(1) or evaluate(*a))
    L, B, C, kT, _ = si
    N = np.linspace(-40.0, 40.0, 4001)
    F = np.full(N.size, 1.2e-12)
    p = fe.hat_points(N, F, L, B, C, kT, equilibrium_of(si), end_loop=end_loop)
    assert bool(used) == (path == "inverse")
    coiled = p.phase == fe.FULLY_COILED
    assert coiled.sum() > 1000
    co = fe.coexistence(F[:1], L, B, C, kT, equilibrium_of(si))
    if end_loop:
        lc = fe.loop_constants(co, L, B, C, kT)
        x = 2 * np.pi * (np.abs(N[coiled]) - el.LOOP_WRITHE) / L
        start, loop = co.torque[0] / C + co.torsion[0] * (1.0 - lc.length[0] / L), (B, L)
    else:
        x, start, loop = 2 * np.pi * np.abs(N[coiled]) / L, co.torque[0] / C + co.torsion[0], None
    M, T = ct.secant(x, np.full(x.size, co.pull[0]), np.full(x.size, start), C,
                     equilibrium_of(si), loop)
    np.testing.assert_allclose(np.abs(p.torque[coiled]), M, rtol=1e-12)
    assert np.all(p.extension[coiled] == 0.0)
    idx = np.linspace(0, x.size - 1, 7).astype(int)
    ref = np.array([_brentq(x[i], C, equilibrium_of(si), loop) for i in idx])
    np.testing.assert_allclose(np.abs(p.torque[coiled][idx]), ref[:, 0], rtol=1e-12)
    # G = -(L [- 2 l]) T - L M^2/(2C) + 2 pi (|N| [- w]) M: T enters through G
    q = fe.hat_points(N[~coiled], F[~coiled], L, B, C, kT, equilibrium_of(si),
                      end_loop=end_loop)
    for field in ("extension", "torque", "free_energy"):
        np.testing.assert_array_equal(getattr(p, field)[~coiled], getattr(q, field))
    lc_T = el.loop_length(T, B) if end_loop else 0.0
    G = -(L - 2.0 * lc_T) * T - L * M * M / (2.0 * C) \
        + 2 * np.pi * (np.abs(N[coiled]) - (el.LOOP_WRITHE if end_loop else 0.0)) * M
    np.testing.assert_allclose(p.free_energy[coiled], G, rtol=1e-12)


def test_inverse_table_matches_newton_on_the_table_and_gives_up_on_a_kink(si):
    """The cubic inverse agrees with Newton on the same Chebyshev table to 1e-13 over its
    whole domain (ends included); on a kinked branch (no converged table) it is None."""
    _, _, C, _, _ = si
    pull, start, _, x_full = _problem(si, 1.2e-12, False)
    _, T_hi = ct.secant(np.array([3 * x_full]), np.array([pull]), np.array([start]), C,
                        equilibrium_of(si), None)
    inv = ct.inverse_table((pull, T_hi[0]), C, equilibrium_of(si))
    x = np.linspace(inv.x_lo, inv.x_hi, 301)
    M, T = ct.evaluate_inverse(inv, x)
    got = ct.torque_at_linking(x, (pull, T_hi[0]), C, equilibrium_of(si))
    np.testing.assert_allclose(M, got[0], rtol=1e-13)
    np.testing.assert_allclose(T, got[1], rtol=1e-13)
    eq, _, C_k = _jumping_branch()
    assert ct.inverse_table((1e-12, 1e-10), C_k, eq) is None


def test_inverse_one_step_level_is_the_newton_roots_level(si, monkeypatch):
    """The finer inverse levels take one Newton step from the coarser inverse and move the
    series' values to the roots by Taylor's rule (coiled_table._one_step): the table the
    roots and a second series evaluation give, to a few ulp (4e-15; the inverse's own
    tolerance is 3e-14), at 1.73 times full coiling (40 turns at 1.2 pN: the step is
    used); at 3 times the coarser inverse is too far and the roots solve."""
    _, _, C, _, _ = si
    pull, start, _, x_full = _problem(si, 1.2e-12, False)
    _, T_hi = ct.secant(np.array([1.73 * x_full]), np.array([pull]), np.array([start]), C,
                        equilibrium_of(si), None)
    series = ct.branch_series((pull, T_hi[0]), C, equilibrium_of(si))
    used = []
    one_step = ct._one_step
    monkeypatch.setattr(ct, "_one_step", lambda *a: used.append(one_step(*a)) or used[-1])
    new = ct.inverse_of(series)
    assert used and all(u is not None for u in used)
    monkeypatch.setattr(ct, "_one_step", lambda *a: None)
    ref = ct.inverse_of(series)
    assert new.coefficients.shape == ref.coefficients.shape
    x = np.linspace(ref.x_lo, ref.x_hi, 20001)
    (M, T), (M_r, T_r) = ct.evaluate_inverse(new, x), ct.evaluate_inverse(ref, x)
    assert np.max(np.abs(M - M_r)) <= 4e-15 * np.max(np.abs(M_r))
    np.testing.assert_allclose(T, T_r, rtol=4e-15)


@pytest.mark.parametrize("order", [1, 2, 3])
def test_derivative_bound_bounds_the_series_derivative(order):
    """coiled_table._derivative_bound: at least max |f^(n)| on [-1, 1], and reached by
    T_k itself (at t = 1)."""
    from numpy.polynomial import chebyshev as ch

    rng = np.random.default_rng(order)
    t = np.linspace(-1.0, 1.0, 4001)
    for _ in range(20):
        c = rng.normal(size=33) * 0.8 ** np.arange(33)
        assert np.max(np.abs(ch.chebval(t, ch.chebder(c, order)))) <= \
            ct._derivative_bound(c, order) * (1 + 1e-12)
    unit = np.zeros(9)
    unit[8] = 1.0
    assert ct._derivative_bound(unit, order) == pytest.approx(
        ch.chebval(1.0, ch.chebder(unit, order)), rel=1e-13)
