"""Screened interaction and the generic uniform-plectoneme solver.

Independent references: K0 (parallel rods), a direct double integral over both strands
(scipy cubature on 3-D strand positions), finite differences, the paper's Marko-Siggia
solver (hard-core w plugged into the generic solver), the un-reduced (GE1), (GE2) and
tension equations, a fixed-torque minimisation (second method), trends, unit
invariance, named errors, and the published numbers listed with their citations.
"""

import pickle

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import cubature
from scipy.optimize import minimize
from scipy.special import k0

import supercoil as sc
from supercoil.core.dna import contact as ct
from supercoil.core.dna import equilibrium as eq
from supercoil.core.dna import marko_siggia as ms
from supercoil.core.dna import moroz_nelson as mn
from supercoil.core.dna import plectoneme as pl
from supercoil.core.dna import screened as scr
from supercoil.dna.interactions import Screened, get_interaction
from supercoil.exceptions import NoEquilibriumError, ParameterError
from supercoil.units import BOLTZMANN

KT = BOLTZMANN * 298.15
B50 = 50e-9 * KT
FORCES = np.array([0.5, 1.0, 2.0, 4.0]) * 1e-12
SALTS = [10.0, 50.0, 150.0, 500.0, 1000.0]


@pytest.fixture(scope="module")
def dna150():
    return sc.load_parameters("dna_150mM_nacl")


def _at_salt(dna, c, ureg=sc.ureg):
    return dna.replace(salt=c * ureg.mM)


# ---- the interaction -------------------------------------------------------


@pytest.mark.parametrize("R", [1.0e-9, 2.5e-9, 8e-9])
@pytest.mark.parametrize("lam", [0.304e-9, 0.96e-9, 3.04e-9])
def test_parallel_rod_limit_k0(R, lam):
    # alpha -> 0: two parallel line charges 2R apart, w = nu^2 kT l_B K0(2R/lambda)
    w = scr.electrostatic(1e-5, R, lam, 1.0)
    assert w == pytest.approx(k0(2 * R / lam), rel=1e-9, abs=0)
    assert scr.parallel_rods(R, lam, 1.0) == pytest.approx(k0(2 * R / lam), rel=1e-15, abs=0)


def test_small_tilt_helical_factor_is_one_plus_alpha_squared():
    # saddle point at z = 0 for R >> lambda: g = w / (K0 limit) = 1 + alpha^2 + O(alpha^4)
    R, lam = 30e-9, 0.304e-9
    for a in (0.03, 0.06):
        g = scr.electrostatic(a, R, lam, 1.0) / k0(2 * R / lam)
        assert (g - 1) / a**2 == pytest.approx(1.0, rel=0.03)
    # the helix always repels more than the straight pair (closer pitch neighbours)
    a = np.radians([5, 15, 25, 35, 44])
    g = scr.electrostatic(a, 2.5e-9, 0.78e-9, 1.0) / k0(2 * 2.5e-9 / 0.78e-9)
    assert np.all(np.diff(g) > 0) and g[0] > 1


def _direct_double_integral(alpha, R, lam):
    """w from 3-D strand positions: one turn of strand 1 against all of strand 2."""
    p = R / np.tan(alpha)
    ds = R / np.sin(alpha)
    phi_max = (2 * R + 45 * lam) / p

    def f(x):
        t1, t2 = x[:, 0], x[:, 0] + x[:, 1]
        d = np.sqrt((R * np.cos(t1) + R * np.cos(t2)) ** 2
                    + (R * np.sin(t1) + R * np.sin(t2)) ** 2 + (p * (t1 - t2)) ** 2)
        return np.exp(-d / lam) / d * ds * ds

    res = cubature(f, [0.0, -phi_max], [2 * np.pi, phi_max], rtol=1e-10, atol=0.0)
    assert res.status == "converged"
    return res.estimate / (2 * 2 * np.pi * ds)  # per DNA length: both strands of one turn


@pytest.mark.parametrize(("alpha_deg", "R", "lam"),
                         [(15, 2.5e-9, 0.78e-9), (30, 2.0e-9, 0.78e-9), (40, 5e-9, 3.04e-9)])
def test_helical_interaction_against_direct_double_integral(alpha_deg, R, lam):
    a = np.radians(alpha_deg)
    assert scr.electrostatic(a, R, lam, 1.0) == pytest.approx(
        _direct_double_integral(a, R, lam), rel=1e-8)


@given(st.floats(3.0, 44.0), st.floats(1.1e-9, 10e-9), st.floats(0.3e-9, 3.1e-9))
def test_partials_against_finite_differences(alpha_deg, R, lam):
    a = np.radians(alpha_deg)
    w, w_a, w_R = scr.electrostatic_partials(a, R, lam, 1.0)
    assert w == pytest.approx(scr.electrostatic(a, R, lam, 1.0), rel=1e-14, abs=0)
    ha, hR = 1e-6 * a, 1e-6 * R
    e = scr.electrostatic
    fd_a = (e(a + ha, R, lam, 1.0) - e(a - ha, R, lam, 1.0)) / (2 * ha)
    fd_R = (e(a, R + hR, lam, 1.0) - e(a, R - hR, lam, 1.0)) / (2 * hR)
    assert w_a == pytest.approx(fd_a, rel=1e-6, abs=1e-9 * abs(w) / a)
    assert w_R == pytest.approx(fd_R, rel=1e-6, abs=0)
    _, c_a, c_R = scr.confinement_partials(a, R, B50, KT)
    fd_ca = (scr.confinement(a + ha, R, B50, KT) - scr.confinement(a - ha, R, B50, KT)) / (2 * ha)
    fd_cR = (scr.confinement(a, R + hR, B50, KT) - scr.confinement(a, R - hR, B50, KT)) / (2 * hR)
    assert c_a == pytest.approx(fd_ca, rel=1e-6, abs=0)
    assert c_R == pytest.approx(fd_cR, rel=1e-6)


def test_confinement_is_the_papers_entropic_term():
    # the paper's w (Li, Zhao et al., Example III):
    # w_MS = hard core + B^(-1/3) [1 + x^(-2/3)] kT^(4/3) / R^(2/3)
    a = np.radians(np.linspace(5, 44, 9))
    R, r0 = 2.3e-9, 1.75e-9
    x = np.pi / np.tan(a)
    hard = (1 + x**-12.0) * KT / r0 * (R / r0) ** -12
    assert scr.confinement(a, R, B50, KT) == pytest.approx(
        ms.interaction(a, R, B50, KT, r0) - hard, rel=1e-12, abs=0)


def test_closest_approach_is_2R_up_to_45_degrees():
    a = np.radians([5.0, 30.0, 45.0])
    assert scr.closest_approach(a, 2e-9) == pytest.approx(4e-9, rel=1e-12, abs=0)
    assert scr.closest_approach(np.radians(70.0), 2e-9) < 4e-9  # pitch neighbours closer


# ---- the generic solver ----------------------------------------------------


def test_generic_solver_reproduces_the_papers_hard_core_solver():
    kT = BOLTZMANN * 300.0
    B, C, r0 = 48e-9 * kT, 86e-9 * kT, 1.75e-9

    def partials(a, R):
        return (ms.interaction(a, R, B, kT, r0), *ms.interaction_partials(a, R, B, kT, r0))

    branch = eq.branch_table(B, partials, 0.5 * r0, 1e4 * r0, points=400)
    F = np.geomspace(0.1e-12, 20e-12, 9)
    alpha, R, M = eq.solve_equilibrium(F, B, partials, branch)
    ref = pl.equilibrium(F, B, C, kT, r0, rtol=1e-13)
    assert alpha == pytest.approx(ref.alpha, rel=1e-10)
    assert R == pytest.approx(ref.radius, rel=1e-10, abs=0)
    assert M == pytest.approx(ref.torque, rel=1e-10, abs=0)


@pytest.mark.filterwarnings("ignore::supercoil.exceptions.ValidityWarning")
@pytest.mark.parametrize("c", SALTS)
def test_screened_state_solves_ge1_ge2_and_tension(dna150, c):
    dna = _at_salt(dna150, c)
    inter = Screened(hard_contact=0)  # free branch only: (GE2) holds everywhere
    F = np.geomspace(0.2e-12, 5e-12, 7)
    s = inter.equilibrium(F, dna.si)
    part = lambda a, R: inter.partials(a, R, dna.si)  # noqa: E731
    si = dna.si
    for res in eq.equilibrium_residuals(F, s.alpha, s.radius, s.omega, si.bending_rigidity,
                                        si.torsional_rigidity, part):
        assert np.max(np.abs(res)) < 1e-10
    assert np.all(s.radius > 1e-9) and np.all(s.alpha < np.pi / 4)


@pytest.mark.filterwarnings("ignore::supercoil.exceptions.ValidityWarning")
@settings(max_examples=6)
@given(st.floats(5.0, 2000.0), st.floats(0.002, 0.998), st.booleans())
def test_every_force_on_the_branch_solves_the_equations(dna150, salt, frac, conf):
    si = _at_salt(dna150, salt).si
    inter = Screened(confinement=float(conf), hard_contact=0)
    br = inter.branch(si)
    lo = 0.0 if br.ends_at_zero else br.tension[-1]
    F = np.array([lo + frac * (br.tension[0] - lo)])
    s = inter.equilibrium(F, si)
    part = lambda a, R: inter.partials(a, R, si)  # noqa: E731
    res = eq.equilibrium_residuals(F, s.alpha, s.radius, s.omega, si.bending_rigidity,
                                   si.torsional_rigidity, part)
    assert max(np.max(np.abs(r)) for r in res) < 1e-10
    assert s.radius[0] >= br.radius[0] * (1 - 1e-12) and 0 < s.alpha[0] < np.pi / 4


def test_state_is_the_minimum_of_f_at_its_torque(dna150):
    # second method: minimise f = B kappa^2/2 + w - M tau over (alpha, R); T = -f_min
    si = dna150.si
    inter = Screened()
    s = inter.equilibrium(np.array([1e-12]), si)
    M, B = s.torque[0], si.bending_rigidity

    def f(x):
        a, R = x[0], x[1] * 1e-9
        kap, tau = np.sin(a) ** 2 / R, np.sin(a) * np.cos(a) / R
        return (0.5 * B * kap**2 + inter.energy(a, R, si) - M * tau) * 1e12

    x0 = [s.alpha[0] * 1.05, s.radius[0] * 1e9 * 0.95]
    res = minimize(f, x0, method="Nelder-Mead", options=dict(xatol=1e-11, fatol=1e-16,
                                                             maxiter=4000))
    assert res.x[0] == pytest.approx(s.alpha[0], rel=1e-6)
    assert res.x[1] * 1e-9 == pytest.approx(s.radius[0], rel=1e-6, abs=0)
    assert -res.fun * 1e-12 == pytest.approx(1e-12, rel=1e-9, abs=0)


# ---- trends and the li-zhao construction ------------------------------------


def _li_zhao(si, s, F):
    """Buckling turns and post-buckling slope of the paper's thermal construction."""
    B, C, kT, L = si.bending_rigidity, si.torsional_rigidity, si.kT, si.length
    ratio = mn.twist_rigidity_ratio(F, B, C, kT)
    D = s.torsion - (ratio - 1) * s.omega
    Nb = s.torque * ratio * L / (2 * np.pi * C)
    return Nb, -2 * np.pi * mn.long_tail_factor(F, s.torque, B, kT) / D, -2 * np.pi / s.torsion


def test_public_li_zhao_buckling_and_slope_use_the_screened_state(dna150, ureg):
    # the li-zhao model receives the interaction and calls interaction.equilibrium(T, dna)
    si = dna150.si
    s = Screened().equilibrium(FORCES, si)
    Nb, slope, slope0 = _li_zhao(si, s, FORCES)
    F = FORCES * 1e12 * ureg.pN
    assert sc.buckling_turns(dna150, F, interaction="screened").m_as("turn") == \
        pytest.approx(Nb, rel=1e-12)
    assert sc.post_buckling_slope(dna150, F, interaction="screened").m_as("m/turn") == \
        pytest.approx(slope, rel=1e-12, abs=0)
    assert sc.post_buckling_slope(dna150, F, interaction="screened", thermal=False).m_as(
        "m/turn") == pytest.approx(slope0, rel=1e-12, abs=0)
    eq_pub = sc.plectoneme_equilibrium(dna150, F, interaction=Screened())
    assert eq_pub.radius.m_as("m") == pytest.approx(s.radius, rel=1e-14, abs=0)


def test_radius_torque_turns_slope_fall_with_salt_and_radius_with_force(dna150):
    rows = []
    for c in SALTS:
        si = _at_salt(dna150, c).si
        s = Screened().equilibrium(FORCES, si)
        Nb, slope, slope0 = _li_zhao(si, s, FORCES)
        rows.append((s.radius, s.torque, Nb, -slope, -slope0))
        assert np.all(np.diff(s.radius) < 0)  # R decreases as the force rises
    for k in range(4):  # R, torque, N_b, athermal |slope| all fall as salt rises
        q = np.array([r[k if k < 3 else 4] for r in rows])
        assert np.all(np.diff(q, axis=0) < 0), k
    # thermal |slope| falls with salt at 0.5-2 pN; at 4 pN and 10 mM the state sits close
    # to the fold (5.39 pN) and the thermal slope is not monotone there (documented)
    thermal = np.array([r[3] for r in rows])
    assert np.all(np.diff(thermal[:, :3], axis=0) < 0)
    assert np.all(np.diff(thermal[1:, 3]) < 0)


def test_hat_curve_and_cli_with_the_screened_interaction(dna150, ureg, tmp_path, capsys):
    import warnings

    from supercoil.cli import main

    F = [1.0, 2.0] * ureg.pN
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.ValidityWarning)  # denaturation at N < 0
        df = sc.hat_curve(dna150, F, np.linspace(0, 120, 25), interaction="screened")
    nb = sc.buckling_turns(dna150, F, interaction="screened").m_as("turn")
    for (_, g), n_b in zip(df.groupby("force", sort=True), nb, strict=True):
        post = g[g["turns"] > n_b + 2]
        assert set(post["phase"]) <= {"plectoneme", "fully coiled"}
        assert np.all(np.diff(post["extension"]) < 0)  # plectoneme grows, z falls
    code = main(["hat", "--params", "dna_150mM_nacl", "--interaction", "screened",
                 "--force", "1pN", "--turns=0:60:5", "--out", str(tmp_path), "--no-plot"])
    assert code == 0 and "35.54" in capsys.readouterr().out
    assert main(["hat", "--params", "dna", "--interaction", "screened", "--force", "1pN",
                 "--out", str(tmp_path), "--no-plot"]) == 2
    assert "salt" in capsys.readouterr().err


@pytest.mark.parametrize("c", [10.0, 150.0])
def test_free_energy_model_with_screened_interaction_obeys_maxwell(dna150, c):
    # the free-energy construction is Maxwell-consistent for any interaction whose states
    # obey dT = tau dM; a wrong screened torque or tension would break dz/dN = -2 pi dM/dF
    from supercoil.dna.models import get_model

    si = _at_salt(dna150, c).si
    model, inter = get_model("free-energy"), Screened()
    F = 1e-12
    nb = model.buckling(np.array([F]), si, True, inter).turns[0]
    N = np.array([0.5 * nb, nb + 20.0])  # stretched and plectoneme phase
    hN, hF = 1e-4, 1e-5

    def pts(n, f):
        return model.points(n, np.full(n.shape, f), si, True, inter, None)

    dz = (pts(N + hN, F).extension - pts(N - hN, F).extension) / (2 * hN)
    dM = (pts(N, F * (1 + hF)).torque - pts(N, F * (1 - hF)).torque) / (2 * hF * F)
    assert dz / (-2 * np.pi * dM) == pytest.approx([1.0, 1.0], rel=1e-5)
    # athermal free-energy is the athermal li-zhao construction exactly
    lz = get_model("li-zhao").buckling(np.array([F]), si, False, inter)
    fe0 = model.buckling(np.array([F]), si, False, inter)
    assert fe0.turns == pytest.approx(lz.turns, rel=1e-10)
    assert fe0.slope == pytest.approx(lz.slope, rel=1e-10, abs=0)


def test_reduced_charge_fraction_narrows_the_plectoneme(dna150):
    si = dna150.si
    full = Screened().equilibrium(FORCES, si)
    low = Screened(charge_fraction=0.4).equilibrium(FORCES, si)  # Maffeo et al. 2010
    assert np.all(low.radius < full.radius) and np.all(low.torque < full.torque)


def test_without_confinement_clauvelin_variant_solves(dna150):
    si = dna150.si
    s = Screened(confinement=0).equilibrium(FORCES, si)
    part = lambda a, R: Screened(confinement=0).partials(a, R, si)  # noqa: E731
    res = eq.equilibrium_residuals(FORCES, s.alpha, s.radius, s.omega, si.bending_rigidity,
                                   si.torsional_rigidity, part)
    assert max(np.max(np.abs(r)) for r in res) < 1e-10
    # no entropic term: the plectoneme exists at every small positive force (R grows)
    low = Screened(confinement=0).equilibrium(np.array([0.01e-12]), si)
    assert low.radius[0] > s.radius[0]


def test_published_zero_force_superhelix_diameter_100mM(dna150):
    # Hammermann et al., J. Appl. Cryst. 33, 526 (2000), abstract (text): SANS superhelix
    # diameter 9.0 +/- 0.7 nm at 100 mM Na+ (plasmids, no force). Model: the state at T -> 0+
    br = Screened().branch(_at_salt(dna150, 100.0).si)
    assert br.ends_at_zero
    R0 = np.interp(0.0, br.tension[::-1], br.radius[::-1])
    assert 2 * R0 * 1e9 == pytest.approx(9.0, abs=2 * 0.7)


# ---- units, errors, object behaviour ----------------------------------------


def test_unit_invariance(dna150, ureg):
    si = dna150.si
    ref = Screened().equilibrium(FORCES, si)
    for inter in (Screened(hard_core_radius=10 * ureg.angstrom),
                  Screened(hard_core_radius=1e-9), get_interaction("screened")):
        assert inter == Screened()
    other = dna150.replace(salt=0.15 * ureg.molar, temperature=ureg.Quantity(25.0, "degC"),
                           bending_persistence=0.05 * ureg.um)
    got = Screened().equilibrium(FORCES, other.si)
    assert got.radius == pytest.approx(ref.radius, rel=1e-12, abs=0)
    assert got.torque == pytest.approx(ref.torque, rel=1e-12, abs=0)


def test_needs_salt(dna):
    with pytest.raises(ParameterError, match="salt"):
        Screened().equilibrium(FORCES, dna.si)
    with pytest.raises(ParameterError, match="salt"):
        Screened().energy(0.3, 2e-9, dna)


def test_named_errors_where_no_state_exists(dna150):
    low_salt = _at_salt(dna150, 10.0).si
    free_only = Screened(hard_contact=0)
    with pytest.raises(NoEquilibriumError, match=r"6 pN.*hard core"):
        free_only.equilibrium(np.array([1e-12, 6e-12]), low_salt)  # above the fold
    with pytest.raises(NoEquilibriumError, match=r"40 pN.*pass through each other"):
        free_only.equilibrium(np.array([40e-12]), dna150.si)  # R would drop below a
    with pytest.raises(NoEquilibriumError, match="positive"):
        Screened().equilibrium(np.array([-1e-12]), dna150.si)
    # with confinement T(R) crosses zero, so every positive force has a state; without
    # it T -> 0+ only as R -> inf and the table ends where (GE2) loses its root
    assert Screened().equilibrium(np.array([1e-18]), dna150.si).radius[0] > 3e-9
    with pytest.raises(NoEquilibriumError, match="below"):
        Screened(confinement=0).equilibrium(np.array([1e-17]), dna150.si)


@pytest.mark.filterwarnings("ignore::supercoil.exceptions.ValidityWarning")
def test_contact_holds_the_strands_where_the_free_branch_ends(dna150):
    # 150 mM: above T(R = a) = 29.6 pN the strands touch; R, alpha, M continuous there
    si = dna150.si
    inter = Screened()
    T_a = inter.branch(si).tension[0]
    st = inter.equilibrium(np.array([T_a * (1 - 1e-7), T_a * (1 + 1e-7), 40e-12]), si)
    assert st.radius[0] > 1e-9 and st.radius[1] == 1e-9 and st.radius[2] == 1e-9
    assert st.torque[1] == pytest.approx(st.torque[0], rel=1e-5, abs=0)
    assert st.alpha[1] == pytest.approx(st.alpha[0], rel=1e-5)
    # contact states satisfy (GE1) and the tension equation; the reaction presses (N >= 0)
    part = lambda a, R: inter.partials(a, R, si)  # noqa: E731
    ge1, _, ten = eq.equilibrium_residuals(st.force, st.alpha, st.radius, st.omega,
                                           si.bending_rigidity, si.torsional_rigidity, part)
    assert np.max(np.abs(ge1)) < 1e-10 and np.max(np.abs(ten)) < 1e-10
    _, _, N = ct.normal_reaction(st.alpha[1:], 1e-9, si.bending_rigidity, part)
    assert np.all(N > 0)


@pytest.mark.filterwarnings("ignore::supercoil.exceptions.ValidityWarning")
def test_low_salt_first_order_jump_to_contact_is_the_lower_torque(dna150):
    # 10 mM: between T(R = a) = 3.13 pN and the fold (5.39 pN) a free and a contact state
    # coexist; the equilibrium is the one of lower torque (the global minimum of f)
    si = _at_salt(dna150, 10.0).si
    F = np.array([4.0e-12, 5.0e-12])
    both = Screened().equilibrium(F, si)
    free = Screened(hard_contact=0).equilibrium(F, si)
    assert both.radius[0] == free.radius[0] > 2e-9  # free wins at 4 pN
    assert both.radius[1] == 1e-9 and both.torque[1] < free.torque[1]  # contact at 5 pN
    # second method: minimise f = B kappa^2/2 + w - M tau over alpha and R >= a at the
    # 5 pN state's torque from both basins; the lower minimum is the contact state
    B, M = si.bending_rigidity, both.torque[1]
    inter = Screened()

    def f(x):
        a, R = x[0], x[1] * 1e-9
        kap, tau = np.sin(a) ** 2 / R, np.sin(a) * np.cos(a) / R
        return (0.5 * B * kap**2 + inter.energy(a, R, si) - M * tau) * 1e12

    runs = [minimize(f, x0, method="L-BFGS-B", bounds=[(0.05, 0.78), (1.0, 20.0)],
                     options=dict(ftol=1e-15, gtol=1e-12))
            for x0 in ([both.alpha[1], 1.2], [free.alpha[1], free.radius[1] * 1e9])]
    best = min(runs, key=lambda r: r.fun)
    assert best.x[1] == pytest.approx(1.0, abs=1e-6)
    assert -best.fun * 1e-12 == pytest.approx(5e-12, rel=1e-6, abs=0)


@pytest.mark.parametrize("kw", [dict(charge_fraction=0.0), dict(charge_fraction=1.6),
                                dict(hard_core_radius=-1e-9), dict(confinement=2.0),
                                dict(hard_contact=0.5)])
def test_parameter_bounds(kw):
    with pytest.raises(ValueError, match=f"screened.{next(iter(kw))}"):
        Screened(**kw)


def test_immutable_and_picklable():
    inter = Screened(charge_fraction=0.4)
    assert pickle.loads(pickle.dumps(inter)) == inter
    assert inter.replace(charge_fraction=1.0) == Screened()
    with pytest.raises(AttributeError):
        inter.values = {}


@pytest.mark.parametrize("name", ["hard-core", "screened"])
def test_equilibrium_does_not_depend_on_the_twist_rigidity_or_the_length(name):
    """(GE2) contains no C: tilt, radius and torque at a tension are independent of C and
    L; omega = M/C. This is what makes ``Interaction.cache_key`` C-free for every
    interaction (the fit's equilibrium cache)."""
    import supercoil as sc
    from supercoil.dna.interactions import get_interaction

    u = sc.ureg
    inter = get_interaction(name)
    a = sc.load_parameters("dna_150mM_nacl")
    b = a.replace(twist_persistence=a.twist_persistence * 1.3, length=2 * a.length)
    T = np.array([0.4e-12, 1.5e-12, 4e-12])
    sa, sb = inter.equilibrium(T, a.si), inter.equilibrium(T, b.si)
    for f in ("alpha", "radius", "torque", "torsion", "interaction_energy"):
        np.testing.assert_allclose(getattr(sb, f), getattr(sa, f), rtol=1e-12, err_msg=f)
    np.testing.assert_allclose(sb.omega * b.si.torsional_rigidity, sa.torque, rtol=1e-12)
    assert inter.cache_key(a.si) == inter.cache_key(b.si)
    assert inter.cache_key(a.replace(salt=10 * u.mM).si) != inter.cache_key(a.si) \
        or name == "hard-core"
    assert inter.cache_key(a.replace(bending_persistence=40 * u.nm).si) != inter.cache_key(a.si)


def test_a_fit_varying_twist_stiffness_and_length_reuses_the_screened_equilibria(monkeypatch):
    """Jacobian columns in C_t and L need no new screened equilibrium (cache_key is C-free)."""
    import warnings

    import supercoil as sc
    from supercoil.dna.interactions.screened import Screened

    u = sc.ureg
    dna = sc.load_parameters("dna_150mM_nacl")
    data = sc.simulate_rotation_curves(dna, [0.6, 1.5] * u.pN, noise=3 * u.nm, seed=2,
                                       model="free-energy", interaction="screened",
                                       points_per_force=40)
    calls = []
    real = Screened.equilibrium

    def counted(self, tension, d):
        calls.append((d.twist_persistence, d.length))
        return real(self, tension, d)

    monkeypatch.setattr(Screened, "equilibrium", counted)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sc.fit_hat_curves(data, dna, vary=["twist_persistence", "length"], model="free-energy",
                          interaction="screened")
    # every solve at the first molecule's C and L: varying them reuses the tables
    assert calls and len(set(calls)) == 1


def test_screened_warns_where_the_strand_gap_is_below_a_debye_length():
    """Issue 20 item 17: above its contact jump the 10 mM set gave slopes of -15 nm/turn
    (less steep than at 150 mM: the salt trend reversed) without a word. Stigter's far
    field does not hold at a surface gap 2 (R - a) below one Debye length."""
    import warnings

    from supercoil.dna.interactions.screened import MIN_GAP_DEBYE_LENGTHS
    from supercoil.exceptions import ValidityWarning

    u = sc.ureg
    dna = sc.load_parameters("dna_10mM_nacl")
    lam = Screened().lengths(dna)["debye_length"].m_as("nm")
    with pytest.warns(ValidityWarning, match=r"10 mM: above 5\.01 pN tension") as rec:
        slope = sc.post_buckling_slope(dna, [6, 8] * u.pN, model="free-energy",
                                       interaction="screened")
    assert "Debye length (3.04 nm" in str(rec[0].message)
    assert np.all(slope.m_as("nm/turn") > -20)  # the contact states it warns about
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # below the onset: no warning
        sc.post_buckling_slope(dna, 4 * u.pN, model="free-energy", interaction="screened")
        eq_ok = sc.plectoneme_equilibrium(dna, [0.5, 4.9] * u.pN, interaction="screened")
    assert np.all(2 * (eq_ok.radius.m_as("nm") - 1.0) >= MIN_GAP_DEBYE_LENGTHS * lam)
    with pytest.warns(ValidityWarning, match="150 mM: above 14.1 pN"):
        st_ = sc.plectoneme_equilibrium(sc.load_parameters("dna_150mM_nacl"), 20 * u.pN,
                                        interaction="screened")
    assert 2 * (st_.radius.m_as("nm") - 1.0) < 0.784


def test_the_shipped_10mM_set_jumps_to_contact_at_5_03_pN():
    """The theory page's 4.93 pN is the 150 mM set's A = 50 nm at 10 mM; the shipped
    dna_10mM_nacl (A = 56 nm) jumps at 5.03 pN (R 2.50 -> 1.0 nm, M = 63.0 pN nm)."""
    import warnings

    from scipy.optimize import brentq

    u = sc.ureg
    for dna, force in ((sc.load_parameters("dna_10mM_nacl"), 5.030),
                       (sc.load_parameters("dna_150mM_nacl").replace(salt=10 * u.mM), 4.929)):
        def radius(f, dna=dna):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                st_ = sc.plectoneme_equilibrium(dna, f * u.pN, interaction="screened")
            return float(st_.radius.m_as("nm"))

        jump = brentq(lambda f, radius=radius: radius(f) - 1.5, 4.5, 5.5, xtol=1e-5)
        assert jump == pytest.approx(force, abs=1e-3)
        assert radius(jump - 1e-3) > 2.4 and radius(jump + 1e-3) == pytest.approx(1.0)


# ---- the Newton solver against the direct nested solve -----------------------------


def _kernel(dna, **kw):
    inter = Screened(**kw)
    si, lam, pref = inter.screening_functions(dna)
    B = si.bending_rigidity
    from supercoil.dna.interactions import screened as scm

    f = scm.partials_function(B, si.kT, lam, pref, inter.values["confinement"])
    return B, f, inter.branch(si)


def _forces_on_branch(br, n=40):
    lo = max(0.05e-12, (0.0 if br.ends_at_zero else br.tension[-1]) * (1 + 1e-9))
    hi = min(50e-12, br.tension[0])
    F = np.geomspace(lo, hi, n)
    near_top = hi * (1.0 - 10.0 ** -np.arange(2.0, 13.0, 2.0))  # towards T_max (fold)
    nodes = br.tension[(br.tension > lo) & (br.tension <= hi)][::5]
    return np.concatenate([F, near_top, nodes])


@pytest.mark.parametrize("salt", [5.0, 30.0, 150.0, 1000.0])
@pytest.mark.parametrize("kw", [{}, {"confinement": 0.0}, {"charge_fraction": 0.4}])
def test_newton_equilibrium_matches_the_direct_solve(dna150, salt, kw):
    B, f, br = _kernel(_at_salt(dna150, salt), **kw)
    F = _forces_on_branch(br)
    ref = eq.solve_equilibrium(F, B, f, br, method="direct")
    new = eq.solve_equilibrium(F, B, f, br)
    for x, y in zip(new, ref, strict=True):  # alpha, R, torque
        np.testing.assert_allclose(x, y, rtol=1e-10, atol=0.0)


def test_newton_converges_without_the_fallback_inside_the_branch(dna150):
    # the speed-up is real only if the fallback is rare: away from the fold and the
    # branch ends every force converges by Newton alone
    B, f, br = _kernel(dna150)
    F = np.geomspace(0.01e-12, br.tension[0] * 0.99, 200)
    *_, ok = eq._solve_free_newton(F, B, f, br)
    assert np.all(ok)


def test_newton_needs_about_six_evaluations_per_force(dna150):
    # one fresh Jacobian (3 evaluations), chord steps until two of them bound the error,
    # the final state (1): the count before the chord bound was 7.9 per force
    B, f, br = _kernel(dna150)
    F = np.geomspace(0.05e-12, 5e-12, 200)
    seen = []

    def counted(a, R):
        seen.append(np.size(a))
        return f(a, R)

    eq.solve_equilibrium(F, B, counted, br)
    assert sum(seen) / F.size <= 6.5


@pytest.mark.parametrize("salt", [10.0, 150.0])
def test_energy_is_the_interaction_at_the_returned_states(dna150, salt):
    # Newton's last evaluation (bit for bit a new call), nodes, the fallback, contact
    B, f, br = _kernel(_at_salt(dna150, salt))
    d = _at_salt(dna150, salt).si
    inter = Screened()
    contact = inter.contact_branch(d)
    F = np.concatenate([_forces_on_branch(br, 40), [br.tension[5]]])
    if contact is not None:
        F = np.concatenate([F, [contact.tension[0] * 2.0]])
    for method in ("newton", "direct"):
        a, R, M, w = eq.solve_equilibrium(F, B, f, br, contact, method=method, energy=True)
        ref = eq.solve_equilibrium(F, B, f, br, contact, method=method)
        for x, y in zip((a, R, M), ref, strict=True):
            np.testing.assert_array_equal(x, y)
        np.testing.assert_array_equal(w, f(a, R)[0])


def test_quadrature_nodes_from_one_exponential_match_sinh_and_cosh():
    # _nodes takes sinh t and cosh t from exp(t): 12 digits of z at the smallest node
    a, R, lam = np.array([0.3, 0.6]), np.array([1e-9, 8e-9]), np.array(0.78e-9)
    _, _, z, dz = scr._nodes(a, R, lam)
    D = 2.0 * R[:, None]
    t_max = np.arccosh(1.0 + scr.CUTOFF_DECAYS * lam / D)
    t = t_max * scr._X
    np.testing.assert_allclose(z, D * np.sinh(t), rtol=1e-12, atol=0.0)
    np.testing.assert_allclose(dz, D * np.cosh(t) * t_max * scr._W, rtol=1e-15, atol=0.0)


@pytest.mark.parametrize("method", ["newton", "direct"])
def test_direct_and_newton_solve_at_a_node_and_at_the_branch_top(dna150, method):
    # failed before: a force equal to a table node's tension, or within rounding below a
    # hard-core-started branch's top, gave "root finding did not converge" (T recomputed
    # at exp(log R) lay a few ulp on the wrong side: no sign change in the bracket)
    B, f, br = _kernel(dna150)
    assert not br.fold
    F = np.array([br.tension[7], br.tension[0] * (1 - 1e-15), br.tension[0]])
    alpha, R, _ = eq.solve_equilibrium(F, B, f, br, method=method)
    assert R[0] == pytest.approx(br.radius[7], rel=1e-12, abs=0)
    assert R[1:] == pytest.approx(br.radius[0], rel=1e-12, abs=0)
    ge2 = eq.tilt_residual(alpha, R, B, f)
    assert np.all(np.abs(ge2) < 1e-12 * np.abs(eq.torque(alpha, R, B, f) / R))


@pytest.mark.parametrize("salt, kw", [(5.0, {}), (150.0, {}), (150.0, {"confinement": 0.0})])
def test_newton_and_direct_raise_the_same_errors_beyond_the_branch(dna150, salt, kw):
    B, f, br = _kernel(_at_salt(dna150, salt), **kw)
    bad = [-1e-12, 0.0, br.tension[0] * (1 + 1e-9), 1e-9]
    if not br.ends_at_zero:
        bad.append(br.tension[-1] * 0.5)
    for F in bad:
        msgs = []
        for method in ("newton", "direct"):
            with pytest.raises(NoEquilibriumError) as err:
                eq.solve_equilibrium(np.array([1e-12, F]), B, f, br, method=method)
            msgs.append(str(err.value))
        assert msgs[0] == msgs[1] and "pN" in msgs[0]
    with pytest.raises(ValueError, match="method"):
        eq.solve_equilibrium(np.array([1e-12]), B, f, br, method="chandrupatla")


@pytest.mark.parametrize("c", [10.0, 150.0])
def test_free_energy_coexistence_and_hat_points_through_newton_match_direct(
        dna150, c, monkeypatch):
    import functools

    from supercoil.dna.models import get_model

    si = _at_salt(dna150, c).si
    model, inter = get_model("free-energy"), Screened()
    F = np.array([0.3, 1.0, 2.5]) * 1e-12
    N = np.linspace(-40.0, 40.0, 41)

    def run():
        b = model.buckling(F, si, True, inter)
        pts = [model.points(N, np.full(N.shape, f), si, True, inter, None) for f in F]
        return b, pts

    b_new, p_new = run()
    direct = functools.partial(eq.solve_equilibrium, method="direct")
    monkeypatch.setattr(eq, "solve_equilibrium", direct)
    b_ref, p_ref = run()
    np.testing.assert_allclose(b_new.turns, b_ref.turns, rtol=1e-8)
    np.testing.assert_allclose(b_new.slope, b_ref.slope, rtol=1e-8)
    for x, y in zip(p_new, p_ref, strict=True):
        np.testing.assert_allclose(x.extension, y.extension, rtol=1e-8)
        np.testing.assert_allclose(x.torque, y.torque, rtol=1e-8, atol=1e-8 * np.max(
            np.abs(y.torque)))


@pytest.mark.parametrize("salt", [5.0, 10.0])
def test_fold_peak_with_newton_tilts_is_the_maximum_of_the_tension(dna150, salt, monkeypatch):
    # the fold's refined maximum of T(R) with tilts by Newton from the grid (_tilt_near)
    # is the one found with bracketed tilts: the same T_max; R to the flatness of a maximum
    B, f, br = _kernel(_at_salt(dna150, salt))
    assert br.fold
    monkeypatch.setattr(eq, "_tilt_near", lambda R, a0, B, p: eq.solve_tilt(R, B, p))
    ref = eq.branch_table(B, f, 1e-9, 1e-6)
    assert br.tension[0] == pytest.approx(ref.tension[0], rel=1e-13, abs=0)
    assert br.radius[0] == pytest.approx(ref.radius[0], rel=1e-6, abs=0)
    R = br.radius[0] * np.array([1 - 1e-3, 1 + 1e-3])
    assert np.all(eq.tension(eq.solve_tilt(R, B, f), R, B, f) < br.tension[0])
