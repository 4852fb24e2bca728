"""Case II, rough surface (MODEL.md s.4): physics checks of supercoil.rough_helix."""

import numpy as np
import pint
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import supercoil as sc
from supercoil.core import rough_helix as rh
from supercoil.core import self_contact as sco

u = sc.ureg


def rod_a(mu=0.5):
    """Paper Fig. kzero(a): r = 1.0 mm, L = 56.7 cm (silicone rubber E, G)."""
    return sc.ElasticRod(1.0 * u.mm, 56.7 * u.cm, 4.20 * u.MPa, 1.51 * u.MPa, mu)


def rod_b(mu=0.5):
    """Paper Fig. kzero(b): r = 1.7 mm, L = 142.0 cm (silicone rubber E, G)."""
    return sc.ElasticRod(1.7 * u.mm, 142.0 * u.cm, 4.20 * u.MPa, 1.51 * u.MPa, mu)


def _si(rod):
    s = rod.si
    return s.radius, s.length, s.bending_rigidity, s.torsional_rigidity


def _alpha_rhs(s, a, k, r, L, B, C):
    """[eq da/ds] exactly as printed, in alpha."""
    c = np.cos(2 * a)
    return C / (B * (L - 2 * s)) * (np.sin(2 * a) - 2 * r * k) * c**2 / (c**3 - 1)


@pytest.mark.parametrize(("make", "N"), [(rod_a, 20), (rod_a, 40), (rod_a, 60), (rod_b, 40),
                                         (rod_b, 80), (rod_b, 150)])
def test_closed_form_and_ode_agree_along_the_whole_helix(make, N):
    """|alpha_ode - alpha_closed| <= 1e-8 rad at rtol 1e-10 on a grid reaching s_max (1 - 1e-7)."""
    rod = make()
    cf = sc.rough_helix(rod, N, method="closed_form")
    grid = cf.profile["s"].to_numpy() * u.mm
    assert grid[-1].m_as(u.mm) >= cf.s_max.m_as(u.mm) * (1 - 1.01e-7)
    ode = sc.rough_helix(rod, N, method="ode", s=grid, rtol=1e-10, atol=1e-12)
    assert cf.method == "closed_form" and ode.method == "ode"
    da = np.abs(ode.profile["alpha"].to_numpy() - cf.profile["alpha"].to_numpy())
    assert da.max() <= 1e-8
    # y = 1 - cos 2 alpha, the integrated variable, agrees uniformly much better
    dy = np.abs(np.cos(2 * ode.profile["alpha"]) - np.cos(2 * cf.profile["alpha"]))
    assert dy.max() <= 1e-10
    # s_max from its formula equals the ODE's terminal event alpha -> 0
    assert ode.end == cf.end == "alpha->0"
    assert ode.s_max.m_as(u.mm) == pytest.approx(cf.s_max.m_as(u.mm), rel=1e-10)


def test_s_max_formula_as_printed_matches_the_closed_form_end():
    r, L, B, C = _si(rod_a())
    a0 = sco.initial_tilt(40.0, r, L, B, C)
    c0 = np.cos(2 * a0)
    printed = 0.5 * L * (1 - (2 * np.exp(1 / c0 - 1) / (c0 + 1)) ** (-B / C))
    assert rh.k0_s_max(a0, L, B, C) == pytest.approx(printed, rel=1e-13)
    assert printed < L / 2


def test_closed_form_solves_the_printed_ode():
    """Finite-difference slope of the closed form matches [eq da/ds] in alpha (k = 0)."""
    r, L, B, C = _si(rod_a())
    a0 = sco.initial_tilt(40.0, r, L, B, C)
    smax = rh.k0_s_max(a0, L, B, C)
    s = np.linspace(0.01, 0.95, 7) * smax
    h = 1e-6
    a = lambda x: sco.alpha_of_y(rh.k0_y_of_s(x, a0, L, B, C))  # noqa: E731
    slope = (a(s + h) - a(s - h)) / (2 * h)
    np.testing.assert_allclose(slope, _alpha_rhs(s, a(s), 0.0, r, L, B, C), rtol=1e-6)
    # explicit s(alpha) inverts alpha(s)
    np.testing.assert_allclose(rh.k0_s_of_alpha(a(s), a0, L, B, C), s, rtol=1e-10)


def test_ode_in_y_is_the_printed_ode_with_twisting():
    r, L, B, C = _si(rod_a())
    s = np.array([0.01, 0.1, 0.2])
    a = np.array([0.1, 0.3, 0.6])
    for k in (0.0, 50.0, -30.0):
        dyds = rh.dy_ds(s, sco.y_of_alpha(a), k, r, L, B, C)
        np.testing.assert_allclose(dyds / (2 * np.sin(2 * a)),
                                   _alpha_rhs(s, a, k, r, L, B, C), rtol=1e-12)


@pytest.mark.parametrize("method", ["closed_form", "ode"])
def test_linking_number_conserved_at_every_slack(method):
    """Lk = Tw + Wr = N(S) along the profile [Eq Lk=Tw+Wr] (trapezoid integrals)."""
    res = sc.rough_helix(rod_a(), 40, method=method, n_points=2001)
    p = res.profile
    lk = p["twist"] + p["writhe"]
    np.testing.assert_allclose(lk, p["turns"], atol=2e-5 * 40)
    assert p["turns"].iloc[0] == 40 and p["twist"].iloc[0] == pytest.approx(40, rel=1e-12)


def test_linking_number_conserved_with_twisting_while_slacking():
    k = 20.0 * u.rad / u.m  # ~3.2 turns per metre of slack

    res = sc.rough_helix(rod_a(), 30, twist_rate=lambda S: k * np.ones(np.shape(S.m)),
                         n_points=2001, slack_max=40 * u.cm)
    p = res.profile
    assert res.method == "ode" and res.end == "s_stop"
    N_expected = 30 + k.m_as(u.rad / u.m) * p["slack"] * 1e-3 / (2 * np.pi)
    np.testing.assert_allclose(p["turns"], N_expected, rtol=1e-12)
    np.testing.assert_allclose(p["twist"] + p["writhe"], p["turns"], atol=1e-4)


@pytest.mark.parametrize("k", [0.0, 20.0, -20.0])
def test_tension_formula_from_energy_balance(k):
    """[eq tension] equals -dE_p/dS + C omega_t k of [Eq Ep1, force0, eq dW] (Appendix C).

    The printed T depends on alpha(S/2) only; the energy balance confirms this
    for k != 0 too.
    """
    rod = rod_a()
    r, L, B, C = _si(rod)
    p = sc.rough_helix(rod, 40, twist_rate=k / u.m, method="ode", ode_method="DOP853",
                       n_points=4001, slack_max=0.3 * u.m).profile
    s = p["s"].to_numpy() * 1e-3
    a = p["alpha"].to_numpy()
    kap, om = np.sin(a) ** 2 / r, sco.twist_density(a, r, B, C)
    f = B * kap**2 + C * om**2
    Ep = np.concatenate(([0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(s)))) \
        + C * om**2 * (L - 2 * s) / 2
    T_energy = -np.gradient(Ep, 2 * s) + C * om * k
    sel = slice(10, len(s) - 10)
    np.testing.assert_allclose(T_energy[sel], p["tension"].to_numpy()[sel], rtol=1e-6)


def test_required_friction_is_C_domega_ds():
    rod = rod_a()
    C = rod.si.torsional_rigidity
    p = sc.rough_helix(rod, 40, n_points=4001).profile
    s = p["s"].to_numpy() * 1e-3
    om = p["omega"].to_numpy() * 1e3
    fd = C * np.abs(np.gradient(om, s))
    sel = slice(10, 3000)
    np.testing.assert_allclose(fd[sel], p["friction_torque_required"].to_numpy()[sel], rtol=1e-4)


def test_slip_onset_is_where_required_meets_available():
    rod = rod_a(mu=0.5)
    r, L, B, C = _si(rod)
    res = sc.rough_helix(rod, 40)
    assert res.slip_onset is not None
    s1 = res.slip_onset.m_as(u.m)
    assert 0 < s1 < res.s_max.m_as(u.m)
    a0 = sco.initial_tilt(40.0, r, L, B, C)
    y = rh.k0_y_of_s(s1, a0, L, B, C)
    req = sco.friction_torque_required_y(y, rh.k0_dy_ds(s1, y, L, B, C), r, B)
    avail = sco.friction_torque_available(sco.alpha_of_y(y), r, B, 0.5)
    assert req == pytest.approx(avail, rel=1e-8)
    p = res.profile
    before = p["s"] < res.slip_onset.m_as(u.mm)
    assert np.all(p["friction_torque_required"][before] <= p["friction_torque_available"][before])
    # more friction, later slip; enough friction everywhere would give None
    later = sc.rough_helix(rod_a(mu=2.0), 40).slip_onset
    assert later > res.slip_onset


def test_unknown_friction_coefficient_is_said_not_hidden():
    with pytest.warns(sc.ValidityWarning, match="friction_coefficient is None"):
        res = sc.rough_helix(rod_a(mu=None), 40)
    assert res.slip_onset is None
    assert res.profile["friction_torque_available"].isna().all()


def test_alpha_goes_to_zero_at_s_max_and_not_beyond():
    res = sc.rough_helix(rod_a(), 40)
    p = res.profile
    assert p["alpha"].iloc[-1] < 1e-3 and np.all(np.diff(p["alpha"]) < 0)
    assert np.all(np.isfinite(p.select_dtypes("number").to_numpy()))
    assert p["s"].iloc[-1] < res.s_max.m_as(u.mm)
    with pytest.raises(sc.NoHelixError, match="s_max"):
        sc.rough_helix(rod_a(), 40, s=[0, 10, 500] * u.mm)
    with pytest.raises(sc.NoHelixError, match="s_max"):
        sc.rough_helix(rod_a(), 40, method="ode", s=res.s_max * np.array([0.5, 1.0]))


def test_curvature_error_onset_and_flag():
    res = sc.rough_helix(rod_a(), 40)
    p = res.profile
    assert res.curvature_tolerance == 0.01
    first = p["s"][p["curvature_error_flag"]].iloc[0]
    onset = res.curvature_error_onset.m_as(u.mm)
    assert p["s"][~p["curvature_error_flag"]].iloc[-1] < onset <= first
    tight = sc.rough_helix(rod_a(), 40, curvature_tolerance=0.0015)
    assert tight.curvature_error_onset < res.curvature_error_onset
    assert np.all(p["curvature_error"] >= 1.0)


def test_alpha_to_pi_over_4_is_named():
    with pytest.raises(sc.SingularityError, match="pi/4"):
        sc.rough_helix(rod_a(), 1e13)
    # twisting much faster than the helix can take up: alpha driven to pi/4
    with pytest.raises(sc.SingularityError, match=r"alpha -> pi/4 .* at s ="):
        sc.rough_helix(rod_a(), 40, twist_rate=2000 * u.rad / u.m, cos2a_min=0.05)


def test_no_helix_without_turns():
    with pytest.raises(sc.NoHelixError, match="N_0 = 0"):
        sc.rough_helix(rod_a(), 0)


def test_method_selection_and_errors():
    assert sc.rough_helix(rod_a(), 40).method == "closed_form"
    assert sc.rough_helix(rod_a(), 40, twist_rate=0 * u.rad / u.m).method == "closed_form"
    assert sc.rough_helix(rod_a(), 40, twist_rate=1 / u.m, slack_max=0.1 * u.m).method == "ode"
    with pytest.raises(ValueError, match="closed_form"):
        sc.rough_helix(rod_a(), 40, twist_rate=1 / u.m, method="closed_form")
    with pytest.raises(ValueError, match="method"):
        sc.rough_helix(rod_a(), 40, method="magic")
    with pytest.raises(pint.DimensionalityError, match="twist_rate"):
        sc.rough_helix(rod_a(), 40, twist_rate=3 * u.m)


@pytest.mark.parametrize("ode_method", ["RK45", "Radau", "LSODA"])
def test_other_solve_ivp_methods(ode_method):
    cf = sc.rough_helix(rod_a(), 40)
    grid = cf.profile["s"].to_numpy()[:-60] * u.mm  # away from the sqrt end
    cf = sc.rough_helix(rod_a(), 40, s=grid)
    ode = sc.rough_helix(rod_a(), 40, method="ode", ode_method=ode_method, s=grid)
    assert ode.solver["ode_method"] == ode_method
    np.testing.assert_allclose(ode.profile["alpha"], cf.profile["alpha"], atol=1e-6)
    assert ode.s_max.m_as(u.mm) == pytest.approx(cf.s_max.m_as(u.mm), rel=1e-8)


def test_twist_rate_forms_agree():
    k = 15.0
    S_tab = np.linspace(0, 0.5, 11)
    grid = np.linspace(0, 250, 301) * u.mm
    res = [
        sc.rough_helix(rod_a(), 30, twist_rate=k / u.m, slack_max=0.5 * u.m, s=grid),
        sc.rough_helix(rod_a(), 30, twist_rate=lambda S: k / u.m * np.ones(np.shape(S.m)),
                       slack_max=0.5 * u.m, s=grid),
        sc.rough_helix(rod_a(), 30, twist_rate=(S_tab * u.m, np.full(11, k) / u.m), s=grid),
        sc.rough_helix(rod_a(), 30, s=grid, twist_rate=(
            S_tab * 100 * u.cm, np.full(11, k / (2 * np.pi)) * u.turn / u.m)),
    ]
    ref = res[0].profile
    for r in res:
        assert r.method == "ode" and r.end == "s_stop"
        assert r.s_max.m_as(u.mm) == pytest.approx(250.0, rel=1e-12)
        np.testing.assert_allclose(r.profile["alpha"], ref["alpha"], atol=1e-9)
        np.testing.assert_allclose(r.profile["turns"], ref["turns"], rtol=1e-12)


def test_negative_turns_mirror():
    p = sc.rough_helix(rod_a(), 40).profile
    m = sc.rough_helix(rod_a(), -40).profile
    np.testing.assert_allclose(m["alpha"], p["alpha"])
    for c in ("omega", "torque", "twist", "writhe", "turns"):
        np.testing.assert_allclose(m[c], -p[c])
    # k = 2 pi dN/dS with signed N: adding twist to N_0 < 0 is a negative k
    a = sc.rough_helix(rod_a(), 40, twist_rate=10 / u.m, slack_max=0.2 * u.m).profile
    b = sc.rough_helix(rod_a(), -40, twist_rate=-10 / u.m, slack_max=0.2 * u.m).profile
    np.testing.assert_allclose(a["alpha"], b["alpha"], rtol=1e-12)


def test_unit_invariance():
    rod_si = sc.ElasticRod(1e-3 * u.m, 0.567 * u.m, 4.2e6 * u.Pa, 1.51e6 * u.Pa, 0.5)
    rod_mm = sc.ElasticRod(1 * u.mm, 567 * u.mm, 4.2 * u.MPa, 1.51 * u.MPa, 0.5)
    a = sc.rough_helix(rod_si, 40, twist_rate=0.01 / u.mm, slack_max=0.3 * u.m)
    b = sc.rough_helix(rod_mm, 40 * u.turn, twist_rate=10 / u.m, slack_max=300 * u.mm)
    assert a.s_max == b.s_max and a.alpha0 == b.alpha0
    np.testing.assert_allclose(a.profile["tension"], b.profile["tension"], rtol=1e-12)
    c = sc.rough_helix(rod_mm, 40)
    d = sc.rough_helix(rod_si, 80 * np.pi * u.rad)
    assert c.s_max.m_as(u.m) == pytest.approx(d.s_max.m_as(u.m), rel=1e-14)
    assert c.slip_onset.m_as(u.m) == pytest.approx(d.slip_onset.m_as(u.m), rel=1e-9)


def test_profile_table_convention():
    res = sc.rough_helix(rod_a(), 40)
    p = res.profile
    need = ["s", "alpha", "pitch", "omega", "curvature", "torsion", "tension", "normal_force",
            "friction_torque_required", "friction_torque_available", "curvature_error"]
    assert all(c in p.columns for c in need)
    assert set(p.columns) <= set(p.attrs["units"])
    assert p.attrs["units"]["pitch"] == "mm" and p.attrs["units"]["tension"] == "N"
    assert p.attrs["provenance"]["turns"] == 40 and p.attrs["provenance"]["method"] == "closed_form"
    assert res.alpha0.check("[]") and res.s_max.check("[length]")


@settings(max_examples=25)
@given(N=st.floats(2.0, 300.0), r_mm=st.floats(0.3, 3.0), L_cm=st.floats(30.0, 300.0))
def test_s_max_event_matches_formula_property(N, r_mm, L_cm):
    rod = sc.ElasticRod(r_mm * u.mm, L_cm * u.cm, 4.2 * u.MPa, 1.51 * u.MPa, 0.5)
    r, L, B, C = _si(rod)
    a0 = sco.initial_tilt(N, r, L, B, C)
    if np.cos(2 * a0) < 1e-6:
        return
    smax = rh.k0_s_max(a0, L, B, C)
    it = rh.integrate(a0, lambda S: np.zeros_like(np.asarray(S, float)), r, L, B, C)
    if smax >= 0.5 * L * (1 - rh.TAIL_FRACTION_MIN):  # helix would take the whole rod
        assert it.reason == "s_stop" and it.s_end < smax
        return
    assert it.reason == "alpha->0"
    assert it.s_end == pytest.approx(smax, rel=1e-8)
    assert 0 < smax < L / 2


@settings(max_examples=60)
@given(N=st.floats(0.5, 2000.0), frac=st.floats(0.0, 1.0))
def test_closed_form_inversion_round_trip_property(N, frac):
    """alpha(s) (Newton in y) and the explicit s(alpha) of [eq example k=0] invert each other."""
    r, L, B, C = _si(rod_a())
    a0 = sco.initial_tilt(N, r, L, B, C)
    smax = rh.k0_s_max(a0, L, B, C)
    s = frac * smax
    y = rh.k0_y_of_s(s, a0, L, B, C)
    assert 0.0 <= y <= sco.y_of_alpha(a0)
    assert rh.k0_s_of_alpha(sco.alpha_of_y(y), a0, L, B, C) == pytest.approx(s, abs=1e-12 * L)


@pytest.mark.parametrize("k", [-100.0, -20.0, -5.0])
def test_untwisting_while_slacking_ends_the_helix_earlier(k):
    """k < 0: dy/ds ~ y^(-1/2) at the end; the s(y) phase reaches alpha = 0 regularly."""
    ref = sc.rough_helix(rod_a(), 40)
    res = sc.rough_helix(rod_a(), 40, twist_rate=k / u.m)
    assert res.end == "alpha->0" and res.s_max < ref.s_max
    p = res.profile
    assert np.all(np.isfinite(p.select_dtypes("number").to_numpy()))
    np.testing.assert_allclose(p["twist"] + p["writhe"], p["turns"], atol=2e-4)
    # the end agrees between an explicit and an implicit solver
    other = sc.rough_helix(rod_a(), 40, twist_rate=k / u.m, ode_method="Radau")
    assert other.s_max.m_as(u.mm) == pytest.approx(res.s_max.m_as(u.mm), rel=1e-7)


def test_slow_twisting_relaxes_to_the_fixed_point():
    """k > 0 constant: alpha relaxes to sin 2a* = 2 r k (stiff; auto picks LSODA)."""
    k = 5.0
    res = sc.rough_helix(rod_a(), 40, twist_rate=k / u.m)
    assert res.solver["ode_method"] == "LSODA" and res.end == "s_stop"
    a_star = 0.5 * np.arcsin(2 * rod_a().si.radius * k)
    assert res.profile["alpha"].iloc[-1] == pytest.approx(a_star, rel=1e-3)
