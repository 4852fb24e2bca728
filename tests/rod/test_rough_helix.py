"""Case II, rough surface (docs/theory/rough.md): physics checks of supercoil.rough_helix."""

import numpy as np
import pint
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

import supercoil as sc
from supercoil.core.rod import contact as sco
from supercoil.core.rod import rough as rh

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
    assert rh.k0_s_max(a0, L, B, C) == pytest.approx(printed, rel=1e-13, abs=0)
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
        # stopped by slack_max / the table's end with k != 0: the helix end is unknown
        assert r.s_max is None
        assert r.s_end.m_as(u.mm) == pytest.approx(250.0, rel=1e-12)
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
    assert c.s_max.m_as(u.m) == pytest.approx(d.s_max.m_as(u.m), rel=1e-14, abs=0)
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
# an accuracy outlier: DOP853 ended 5.4e-7 (relative) short of s_max here (the case as
# reported, rounded, and an unrounded neighbour that reproduced it)
@example(N=2.3326, r_mm=2.00001, L_cm=59.507)
@example(N=2.3330754336164494, r_mm=2.0000874659683334, L_cm=59.5262881778452)
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
    assert it.s_end == pytest.approx(smax, rel=1e-10)  # measured worst 3e-12 (391 rods)
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


# --- audit fixes: non-finite twist rates, grids, onsets, argument checks ----------------


@pytest.mark.parametrize("k", [np.inf, -np.inf, np.nan])
def test_non_finite_constant_twist_rate_is_refused(k):
    with pytest.raises(ValueError, match="twist_rate must be finite"):
        sc.rough_helix(rod_a(), 40, twist_rate=k / u.m)


@pytest.mark.parametrize("bad", [np.inf, np.nan])
def test_callable_twist_rate_returning_inf_or_nan_raises_naming_the_slack(bad):
    """Used to hang (LSODA calling the right side forever) or end in a NoHelixError."""
    def k(S):
        return np.where(S.m > 0.2, bad, 0.5) / u.m

    for ode_method in ("LSODA", "DOP853"):
        with pytest.raises(sc.ValidityError,
                           match=r"twist_rate\(slack\) returned .* slack S = 0\.2"):
            sc.rough_helix(rod_a(), 40, twist_rate=k, ode_method=ode_method)


def test_ode_right_side_refuses_a_non_finite_rate():
    r, L, B, C = _si(rod_a())
    a0 = sco.initial_tilt(40.0, r, L, B, C)
    with pytest.raises(sc.ValidityError, match="not finite"):
        rh.integrate(a0, lambda S: np.full_like(np.asarray(S, float), np.inf), r, L, B, C,
                     ode_method="LSODA")


@pytest.mark.parametrize(("slack", "k", "match"), [
    ([0.0, 0.1, 0.2], [1.0, np.inf, 1.0], "twist_rate must be finite"),
    ([0.0, 0.1, 0.2], [1.0, np.nan, 1.0], "twist_rate must be finite"),
    ([0.0, np.nan, 0.2], [1.0, 1.0, 1.0], "slack must be finite"),
])
def test_twist_rate_table_with_nan_or_inf_is_refused(slack, k, match):
    with pytest.raises(ValueError, match=match):
        sc.rough_helix(rod_a(), 40, twist_rate=(np.array(slack) * u.m, np.array(k) / u.m))


def test_twist_rate_table_without_units_and_odd_sequences_are_named():
    import pandas as pd

    table = pd.DataFrame({"slack": [0.0, 0.5], "twist_rate": [1.0, 1.0]})
    with pytest.raises(sc.DataError, match=r"attrs\['units'\] for 'slack' and 'twist_rate'"):
        sc.rough_helix(rod_a(), 40, twist_rate=table)
    with pytest.raises(ValueError, match=r"\(slack, twist_rate\) pair"):
        sc.rough_helix(rod_a(), 40, twist_rate=(1, 2, 3))


def _tw_wr_reference(rod, N, s_pts):
    """Tw, Wr at slack 2 s of the k = 0 helix by scipy.quad of the closed form."""
    from scipy.integrate import quad

    r, L, B, C = _si(rod)
    a0 = sco.initial_tilt(N, r, L, B, C)

    def alpha(x):
        return float(sco.alpha_of_y(rh.k0_y_of_s(x, a0, L, B, C)))

    out = []
    for s in s_pts:
        om = quad(lambda x: sco.twist_density(alpha(x), r, B, C), 0, s, epsabs=0, epsrel=1e-13)[0]
        ta = quad(lambda x: np.sin(2 * alpha(x)) / (2 * r), 0, s, epsabs=0, epsrel=1e-13)[0]
        om_s = sco.twist_density(alpha(s), r, B, C)
        out.append((om / np.pi + om_s * (L - 2 * s) / (2 * np.pi), ta / np.pi))
    return np.array(out)


def test_twist_and_writhe_do_not_depend_on_the_grid():
    """A grid starting at s > 0 or a coarse grid gave Tw = 15.83, Wr = 0 at s = 100 mm
    (trapezoids from s[0] on the user grid); now they are integrals from the head."""
    rod = rod_a()
    ref = _tw_wr_reference(rod, 40.0, [0.05, 0.1])
    off = sc.rough_helix(rod, 40, s=100 * u.mm).profile
    assert off["twist"].iloc[0] == pytest.approx(ref[1, 0], rel=1e-10)
    assert off["writhe"].iloc[0] == pytest.approx(ref[1, 1], rel=1e-10)
    assert off["twist"].iloc[0] == pytest.approx(27.3522, abs=1e-4)
    coarse = sc.rough_helix(rod, 40, s=[0, 50, 100] * u.mm).profile
    np.testing.assert_allclose(coarse["twist"].iloc[1:], ref[:, 0], rtol=1e-10)
    np.testing.assert_allclose(coarse["writhe"].iloc[1:], ref[:, 1], rtol=1e-10)
    np.testing.assert_allclose(coarse["twist"] + coarse["writhe"], 40, rtol=1e-12)


@pytest.mark.parametrize("kw", [{"method": "ode"}, {"twist_rate": 20 / u.m, "slack_max": 0.4 * u.m},
                                {"twist_rate": -20 / u.m}, {"twist_rate": (
                                    np.array([0, 0.2, 0.45]) * u.m,
                                    np.array([2.0, 30.0, -5.0]) / u.m)}])
def test_linking_number_on_offset_and_coarse_grids(kw):
    """Lk = Tw + Wr = N(S) to ~1e-9 relative on any grid; values agree between grids."""
    dense = sc.rough_helix(rod_a(), 40, **kw)
    s_end = dense.s_end.m_as(u.mm)
    pts = np.array([0.31, 0.62, 0.93]) * s_end
    coarse = sc.rough_helix(rod_a(), 40, s=pts * u.mm, **kw).profile
    for p in (dense.profile, coarse):
        np.testing.assert_allclose(p["twist"] + p["writhe"], p["turns"], rtol=0, atol=4e-9 * 40)
    ref = dense.profile
    for col in ("twist", "writhe", "turns"):
        np.testing.assert_allclose(coarse[col], np.interp(pts, ref["s"], ref[col]), rtol=1e-4)
    if isinstance(kw.get("twist_rate"), tuple):  # N(S) of a piecewise-linear table: exact
        nodes, ks = [0.0, 0.2, 0.45], [2.0, 30.0, -5.0]
        exact = []
        for Sj in 2 * pts * 1e-3:
            x = np.array([v for v in nodes if v < Sj] + [Sj])
            exact.append(np.trapezoid(np.interp(x, nodes, ks), x))
        np.testing.assert_allclose(coarse["turns"], 40 + np.array(exact) / (2 * np.pi),
                                   rtol=1e-13)


@pytest.mark.parametrize(("s", "match"), [
    ([0, 50, 20] * u.mm, "increase strictly"),
    ([0, 50, 50] * u.mm, "increase strictly"),
    ([0, np.nan] * u.mm, "s must be finite"),
    (np.array([]) * u.mm, "at least one point"),
])
def test_profile_grid_must_be_finite_and_increasing(s, match):
    with pytest.raises(ValueError, match=match):
        sc.rough_helix(rod_a(), 40, s=s)


def test_onsets_do_not_depend_on_the_output_grid():
    """n_points = 1 reported slip_onset 212.52 mm (the head dropped, s[0] taken as the
    onset); the onsets now come from an internal grid from s = 0."""
    ref = sc.rough_helix(rod_a(), 40)
    assert ref.slip_onset.m_as(u.mm) == pytest.approx(193.5408695, rel=1e-8)
    with pytest.raises(ValueError, match="n_points must be >= 2"):
        sc.rough_helix(rod_a(), 40, n_points=1)
    for res in (sc.rough_helix(rod_a(), 40, n_points=2),
                sc.rough_helix(rod_a(), 40, s=[150, 200] * u.mm),
                sc.rough_helix(rod_a(), 40, s=[195, 196] * u.mm)):
        assert res.slip_onset.m_as(u.mm) == pytest.approx(ref.slip_onset.m_as(u.mm), rel=1e-10)
        assert res.curvature_error_onset.m_as(u.mm) == pytest.approx(
            ref.curvature_error_onset.m_as(u.mm), rel=1e-10)


@pytest.mark.parametrize(("kw", "match"), [
    ({"slack_max": np.nan * u.m, "twist_rate": 1 / u.m}, "slack_max must be > 0"),
    ({"slack_max": -0.5 * u.m, "twist_rate": 1 / u.m}, "slack_max must be > 0"),
    ({"slack_max": 0 * u.m}, "slack_max must be > 0"),
    ({"curvature_tolerance": np.nan}, "curvature_tolerance"),
    ({"curvature_tolerance": -0.01}, "curvature_tolerance"),
    ({"cos2a_min": np.nan}, r"cos2a_min must lie in \(0, 1\)"),
    ({"cos2a_min": 0.0}, r"cos2a_min must lie in \(0, 1\)"),
    ({"cos2a_min": 1.0}, r"cos2a_min must lie in \(0, 1\)"),
    ({"method": "ode", "rtol": 0.5}, r"rtol must be finite and lie in \(0, 0.1\]"),
    ({"method": "ode", "atol": 0.0}, "atol"),
    ({"n_points": 0}, "n_points"),
])
def test_out_of_range_arguments_are_named(kw, match):
    with pytest.raises(ValueError, match=match):
        sc.rough_helix(rod_a(), 40, **kw)


def test_turns_must_be_a_finite_number():
    with pytest.raises(ValueError, match="turns must be finite"):
        sc.rough_helix(rod_a(), np.nan)
    with pytest.raises(ValueError, match="turns must be finite"):
        sc.rough_helix(rod_a(), np.inf)
    with pytest.raises(TypeError, match="turns"):
        sc.rough_helix(rod_a(), None)
    with pytest.raises(TypeError, match="n_points"):
        sc.rough_helix(rod_a(), 40, n_points=10.5)


def test_tiny_turns_are_accurate_or_a_named_error():
    """N_0 = 1e-30: a real, tiny helix (closed form and ODE agree; no cancellation in
    Phi(c) - Phi(c0)); N_0 = 1e-300: pitch gradients beyond the float range are an
    error, never a raw RuntimeWarning or an inf in the table."""
    _, L, B, C = _si(rod_a())
    cf = sc.rough_helix(rod_a(), 1e-30)
    ode = sc.rough_helix(rod_a(), 1e-30, method="ode")
    a0 = cf.alpha0.m_as(u.rad)
    # small alpha: s_max = (L/2)(B/C)(3/2) y0 with y0 = 2 a0^2
    assert cf.s_max.m_as(u.m) == pytest.approx(0.5 * L * (B / C) * 3 * a0**2, rel=1e-12, abs=0)
    assert ode.s_max.m_as(u.m) == pytest.approx(cf.s_max.m_as(u.m), rel=1e-8, abs=0)
    assert np.isfinite(cf.profile.select_dtypes("number").to_numpy()).all()
    for method in ("closed_form", "ode"):
        with pytest.raises(sc.SupercoilError):
            sc.rough_helix(rod_a(), 1e-300, method=method)


def test_turns_is_a_quantity_and_s_max_is_the_true_end():
    ref = sc.rough_helix(rod_a(), 40)
    assert ref.turns.check("[]") and ref.turns.m_as(u.turn) == 40
    assert sc.rough_helix(rod_a(), -40 * u.turn).turns.m_as(u.turn) == -40
    assert ref.s_end == ref.s_max and ref.end == "alpha->0"
    # k = 0 stopped at slack_max: the end is still known in closed form
    for method in ("closed_form", "ode"):
        stop = sc.rough_helix(rod_a(), 40, slack_max=20 * u.cm, method=method)
        assert stop.end == "s_stop" and stop.s_end.m_as(u.mm) == pytest.approx(100.0)
        assert stop.s_max.m_as(u.mm) == pytest.approx(ref.s_max.m_as(u.mm), rel=1e-12)
    # k != 0 stopped at slack_max: the end depends on the twisting beyond the stop
    k_stop = sc.rough_helix(rod_a(), 40, twist_rate=5 / u.m, slack_max=20 * u.cm)
    assert k_stop.s_max is None and k_stop.s_end.m_as(u.mm) == pytest.approx(100.0)
    # k > 0 relaxing to the fixed point: the helix takes the whole rod
    whole = sc.rough_helix(rod_a(), 40, twist_rate=5 / u.m)
    assert whole.end == "s_stop" and whole.s_max == whole.s_end
    assert whole.s_end.m_as(u.m) == pytest.approx(rod_a().si.length / 2, rel=1e-5)
