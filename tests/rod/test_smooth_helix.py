"""Case I, smooth surface (docs/theory/smooth.md): physics checks of supercoil.smooth_helix."""

import warnings

import numpy as np
import pint
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad

import supercoil as sc
from supercoil.core.rod import contact as sco
from supercoil.core.rod import smooth as sm

u = sc.ureg


@pytest.fixture
def fig2_rod():
    """Paper figure 2: r = 1.0 mm, L = 57.0 cm, E = 4.20 MPa, G = 1.51 MPa."""
    return sc.ElasticRod(1.0 * u.mm, 57.0 * u.cm, 4.20 * u.MPa, 1.51 * u.MPa, 0.5)


def _si(rod):
    s = rod.si
    return s.radius, s.length, s.bending_rigidity, s.torsional_rigidity


def test_solution_satisfies_hard_contact_and_linking_balance(fig2_rod):
    r, L, B, C = _si(fig2_rod)
    N = np.array([5.0, 20.0, 40.0, 80.0])[:, None]
    S = np.array([0.0, 0.05, 0.2, 0.4, 0.55])[None, :]
    h = sc.smooth_helix(fig2_rod, N, S * u.m)
    a = h.alpha.m_as(u.rad)
    omega = h.omega.m_as(1 / u.m)
    # (HC) [eq dom/ds1 self contact]
    np.testing.assert_allclose(omega, sco.twist_density(a, r, B, C), rtol=1e-12)
    # [smooth surface]
    tau = np.sin(a) * np.cos(a) / r
    np.testing.assert_allclose(omega, (2 * np.pi * N - tau * S) / L, rtol=1e-12)
    assert h.alpha.shape == (4, 5)
    assert np.all((a > 0) & (a < np.pi / 4))


@settings(max_examples=60)
@given(N=st.floats(0.5, 300.0), frac=st.floats(0.0, 0.999))
def test_linking_number_equals_turns(N, frac):
    rod = sc.load_parameters("silicone_rubber_rod")
    L = rod.si.length
    for sign in (1.0, -1.0):
        with warnings.catch_warnings():  # N ~ 300: past hard contact (Hertz warning)
            warnings.simplefilter("ignore", sc.ValidityWarning)
            h = sc.smooth_helix(rod, sign * N, frac * L * u.m)
        lk = (h.twist + h.writhe).m_as(u.turn)
        assert lk == pytest.approx(sign * N, rel=1e-12, abs=1e-12)
        assert h.linking_number.m_as(u.turn) == pytest.approx(sign * N, rel=1e-12, abs=0)
        assert np.sign(h.writhe.magnitude) in (0.0, sign)


def test_slack_zero_is_the_initial_helix_of_eq_ini(fig2_rod):
    r, L, B, C = _si(fig2_rod)
    N = np.array([3.0, 40.0, 150.0])
    h = sc.smooth_helix(fig2_rod, N, 0 * u.m)
    np.testing.assert_allclose(h.alpha.m_as(u.rad), sco.initial_tilt(N, r, L, B, C), rtol=1e-12)


def test_tension_is_minus_energy_derivative_at_fixed_turns(fig2_rod):
    r, L, B, C = _si(fig2_rod)
    for N, S in [(40.0, 0.1), (80.0, 0.3), (10.0, 0.5)]:
        dS = 1e-6
        dE = sm.energy(N, S + dS, r, L, B, C) - sm.energy(N, S - dS, r, L, B, C)
        T = sc.smooth_helix(fig2_rod, N, S * u.m).tension.m_as(u.N)
        assert T == pytest.approx(-dE / (2 * dS), rel=1e-6)
        assert T > 0
        # the tension depends on alpha only and equals [eq tension]
        a = sc.smooth_helix(fig2_rod, N, S * u.m).alpha.m_as(u.rad)
        assert T == pytest.approx(sco.tension(a, r, B), rel=1e-10, abs=0)


def test_independent_of_twisting_history(fig2_rod):
    """Work along two different (N, S) paths equals the energy change of the end state.

    The energy balance dE_p = -T dS + 2 pi M_3 dN [force0, eq dW] holds along any
    path, i.e. the state at (N, S) does not remember the path (no friction).
    """
    r, L, B, C = _si(fig2_rod)
    N0, N1, S1 = 20.0, 60.0, 0.35

    def work_slack(N, Sa, Sb):
        return quad(lambda S: -sm.smooth_state(N, S, r, L, B, C)["tension"], Sa, Sb,
                    epsabs=1e-14, epsrel=1e-11)[0]

    def work_twist(S, Na, Nb):
        return quad(lambda N: 2 * np.pi * sm.smooth_state(N, S, r, L, B, C)["torque"], Na, Nb,
                    epsabs=1e-14, epsrel=1e-11)[0]

    w_twist_first = work_twist(0.0, N0, N1) + work_slack(N1, 0.0, S1)
    w_slack_first = work_slack(N0, 0.0, S1) + work_twist(S1, N0, N1)
    # a zig-zag path
    w_zigzag = (work_slack(N0, 0.0, 0.1) + work_twist(0.1, N0, 45.0)
                + work_slack(45.0, 0.1, S1) + work_twist(S1, 45.0, N1))
    dE = sm.energy(N1, S1, r, L, B, C) - sm.energy(N0, 0.0, r, L, B, C)
    assert w_twist_first == pytest.approx(dE, rel=1e-8)
    assert w_slack_first == pytest.approx(dE, rel=1e-8)
    assert w_zigzag == pytest.approx(dE, rel=1e-8)
    # and the state itself is a function of (N, S) only
    a1 = sc.smooth_helix(fig2_rod, N1, S1 * u.m)
    a2 = sc.smooth_helix(fig2_rod, [N0, N1], [S1, S1] * u.m)
    assert a2.alpha[1] == a1.alpha


def test_negative_turns_mirror_the_helix(fig2_rod):
    p = sc.smooth_helix(fig2_rod, 40, 20 * u.cm)
    m = sc.smooth_helix(fig2_rod, -40, 20 * u.cm)
    assert m.alpha == p.alpha and m.pitch == p.pitch and m.tension == p.tension
    for name in ("omega", "torque", "twist", "writhe", "linking_number"):
        assert getattr(m, name).magnitude == pytest.approx(-getattr(p, name).magnitude)


def test_unit_invariance():
    rod_si = sc.ElasticRod(1e-3 * u.m, 0.57 * u.m, 4.2e6 * u.Pa, 1.51e6 * u.Pa)
    rod_mm = sc.ElasticRod(1.0 * u.mm, 570 * u.mm, 4.2 * u.MPa, 1510 * u.kPa)
    a = sc.smooth_helix(rod_si, 40 * u.turn, 0.2 * u.m)
    b = sc.smooth_helix(rod_mm, 80 * np.pi * u.rad, 200 * u.mm)
    for name in ("alpha", "pitch", "tension", "torque", "twist", "writhe"):
        qa, qb = getattr(a, name), getattr(b, name)
        assert qa.to(qb.units).magnitude == pytest.approx(qb.magnitude, rel=1e-12, abs=0)


def test_units_of_results(fig2_rod):
    h = sc.smooth_helix(fig2_rod, 40, 10 * u.cm)
    assert h.pitch.check("[length]") and h.tension.check("[force]")
    assert h.torque.check("[force] * [length]")
    with pytest.raises(pint.DimensionalityError, match="slack"):
        sc.smooth_helix(fig2_rod, 40, 0.1)


@pytest.mark.parametrize(
    ("N", "S", "match"),
    [
        (0.0, 0.1, "N = 0"),
        (40.0, -0.01, "S = .* < 0"),
        (40.0, "L", ">= rod length"),
        (40.0, 0.9, ">= rod length"),
    ],
)
def test_no_helix_conditions_are_named(fig2_rod, N, S, match):
    if S == "L":
        S = fig2_rod.si.length
    with pytest.raises(sc.NoHelixError, match=match):
        sc.smooth_helix(fig2_rod, N, S * u.m)


def test_alpha_to_pi_over_4_is_a_named_singularity(fig2_rod):
    # tension grows without bound as N r / L grows (past alpha = 0.699 rad hard contact
    # is no longer valid: a ValidityWarning) ...
    with pytest.warns(sc.ValidityWarning, match="Hertz contact half-width"):
        T = sc.smooth_helix(fig2_rod, [1e2, 1e4, 1e6], 0.1 * u.m).tension.m_as(u.N)
    assert np.all(np.diff(T) > 0) and T[-1] > 1e3 * T[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sc.smooth_helix(fig2_rod, [10.0, 100.0], 0.1 * u.m)  # the paper's range: no warning
        warnings.simplefilter("ignore", sc.ValidityWarning)
        # ... and the pi/4 limit is reported, not returned as inf/NaN
        with pytest.raises(sc.SingularityError, match=r"pi/4"):
            sc.smooth_helix(fig2_rod, 1e13, 0.1 * u.m)
        with pytest.raises(sc.SingularityError, match="alpha"):
            sc.smooth_helix(fig2_rod, 1e3, 0.1 * u.m, cos2a_min=0.1)


def test_table_convention(fig2_rod):
    h = sc.smooth_helix(fig2_rod, [10, 40], 0.1 * u.m)
    t = h.to_table()
    assert len(t) == 2 and t.attrs["units"]["pitch"] == "mm"
    assert "parameters" in t.attrs["provenance"]


def test_normal_force_is_the_contact_multiplier(fig2_rod):
    """F = (1/S) dE_p/dR at fixed N, S, alpha (Lagrange multiplier of R >= r).

    This is twice the paper's printed [eq normal reaction] (see core.self_contact).
    """
    r, L, B, C = _si(fig2_rod)
    for N, S in [(40.0, 0.2), (10.0, 0.4), (150.0, 0.05)]:
        h = sc.smooth_helix(fig2_rod, N, S * u.m)
        a = h.alpha.m_as(u.rad)

        def E(R, a=a, N=N, S=S):
            kap = np.sin(a) ** 2 / R
            tau = np.sin(a) * np.cos(a) / R
            om = (2 * np.pi * N - tau * S) / L
            return 0.5 * S * B * kap**2 + 0.5 * C * om**2 * L

        dR = 1e-9
        F_energy = (E(r + dR) - E(r - dR)) / (2 * dR) / S
        F = h.normal_force.m_as(u.N / u.m)
        assert F == pytest.approx(F_energy, rel=1e-6)
        assert F == pytest.approx(2 * sco.normal_force_paper(a, r, B), rel=1e-12)
        # Kirchhoff rod, free head: F = B sin^4(a) / (r^3 cos 2a)
        assert F == pytest.approx(B * np.sin(a) ** 4 / (r**3 * np.cos(2 * a)), rel=1e-12)


# --- audit fixes: empty input, None/NaN turns, signed superhelical turns, guards --------


def test_empty_turns_give_empty_results(fig2_rod):
    h = sc.smooth_helix(fig2_rod, np.array([]), 0.1 * u.m)
    assert h.alpha.shape == (0,) and h.tension.shape == (0,)
    assert len(h.to_table()) == 0
    assert sc.smooth_helix(fig2_rod, np.zeros((0, 3)), [0.1, 0.2, 0.3] * u.m).alpha.shape == (0, 3)


@pytest.mark.parametrize(("turns", "exc", "match"), [
    (None, TypeError, "turns must be a number"),
    (np.nan, ValueError, "turns must be finite"),
    ([40, np.inf], ValueError, "turns must be finite"),
])
def test_bad_turns_are_named(fig2_rod, turns, exc, match):
    with pytest.raises(exc, match=match):
        sc.smooth_helix(fig2_rod, turns, 0.1 * u.m)


def test_bad_slack_and_guard_are_named(fig2_rod):
    with pytest.raises(ValueError, match="slack must be finite"):
        sc.smooth_helix(fig2_rod, 40, np.nan * u.m)
    for c in (np.nan, 0.0, 1.0, -1.0):
        with pytest.raises(ValueError, match=r"cos2a_min must lie in \(0, 1\)"):
            sc.smooth_helix(fig2_rod, 40, 0.1 * u.m, cos2a_min=c)


def test_superhelical_turns_are_signed_like_the_writhe(fig2_rod):
    h = sc.smooth_helix(fig2_rod, [40, -40], 0.2 * u.m)
    n = h.superhelical_turns.m_as(u.turn)
    assert n[0] > 0 and n[1] == -n[0]
    np.testing.assert_allclose(h.writhe.m_as(u.turn),
                               2 * np.cos(h.alpha.m_as(u.rad)) * n, rtol=1e-12)
    unsigned = sc.geometry.superhelical_turns(h.alpha[1], 1 * u.mm, 0.2 * u.m)
    assert unsigned.m_as(u.turn) == pytest.approx(-n[1], rel=1e-12)


def test_tiny_turns_give_the_loose_helix_or_a_named_error(fig2_rod):
    """alpha ~ 2 pi N r / S for tiny N (bisection reaches subnormal roots); a pitch
    beyond the float range is an error, not an inf."""
    a = sc.smooth_helix(fig2_rod, 1e-300, 0.1 * u.m).alpha.m_as(u.rad)
    assert a == pytest.approx(2 * np.pi * 1e-300 * 1e-3 / 0.1, rel=1e-6, abs=0)
    with pytest.raises(sc.ValidityError, match="pitch"):
        sc.smooth_helix(fig2_rod, 5e-324, 0.1 * u.m)


def test_hard_contact_validity_limit_is_the_hertz_half_width():
    """b/r = sin^2 a / sqrt(cos 2a) reaches 1 at cos 2a = 3 - 2 sqrt 2 (alpha = 0.699 rad);
    the paper's rods stay well below (N = 40, r = 1 mm, L = 56.7 cm: b/r = 0.29)."""
    from supercoil.core.rod import contact as sco

    a_star = 0.5 * np.arccos(3 - 2 * np.sqrt(2))
    assert a_star == pytest.approx(0.699, abs=5e-4)
    assert sco.contact_width_ratio(a_star) == pytest.approx(1.0, rel=1e-12)
    rod = sc.load_parameters("silicone_rubber_rod")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        h = sc.rough_helix(rod, 40)
    assert sco.contact_width_ratio(h.alpha0.m_as(u.rad)) == pytest.approx(0.29, abs=0.01)
    n_star = (sco.g_contact(a_star) * rod.si.bending_rigidity / rod.si.torsional_rigidity
              * rod.si.length / (4 * np.pi * rod.si.radius))
    with pytest.warns(sc.ValidityWarning, match=r"b = 1\.\d+ r exceeds the limit b = 1 r"):
        sc.rough_helix(rod, 1.05 * n_star)
