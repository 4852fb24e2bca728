"""Example II: the designed helix (docs/theory/design.md) and its round trip through rough_helix."""

import numpy as np
import pytest

import supercoil as sc
from supercoil.core.rod import contact as sco
from supercoil.core.rod import design as dh
from supercoil.rod.design import sinusoidal_pitch

u = sc.ureg


@pytest.fixture
def rod57():
    """Paper Fig. sin / real2: r = 1.0 mm, L = 57 cm (silicone rubber E, G, mu)."""
    return sc.ElasticRod(1.0 * u.mm, 57 * u.cm, 4.20 * u.MPa, 1.51 * u.MPa, 0.5)


@pytest.fixture
def paper_pitch():
    P0 = 16 * u.mm
    return sinusoidal_pitch(P0, 4 * u.mm, 2 * np.pi / (10 * P0))


def test_round_trip_recovers_the_pitch(rod57, paper_pitch):
    sched = sc.design_twist_schedule(rod57, paper_pitch, slack_max=50 * u.cm, n_points=2001)
    grid = sched["s"].to_numpy() * u.mm
    res = sc.rough_helix(rod57, sched["turns"].iloc[0], twist_rate=sched, s=grid,
                         rtol=1e-9, atol=1e-11)
    assert res.method == "ode" and res.end == "s_stop"
    P_back = res.profile["pitch"].to_numpy()
    P_want = paper_pitch(grid).m_as(u.mm)
    np.testing.assert_allclose(P_back, P_want, rtol=2e-5)
    # the forward run counts the same turns (it integrates the tabulated k by the
    # trapezoid rule, O(h^2) ~ 1e-4 turns on this grid; the schedule's N(S) comes
    # from the linking identity by 4th-order quadrature) and predicts the same tension
    np.testing.assert_allclose(res.profile["turns"], sched["turns"], atol=2e-4)
    np.testing.assert_allclose(res.profile["tension"], sched["tension"], rtol=1e-4)
    # the schedule conserves the linking number of the helix it builds [Eq Lk=Tw+Wr]
    p = res.profile
    np.testing.assert_allclose(p["twist"] + p["writhe"], sched["turns"], atol=2e-4)
    # paper: the no-slip condition holds along the designed helix
    assert res.slip_onset is None


def test_constant_pitch_needs_k_equal_to_torsion_like_rate(rod57):
    """A uniform helix (P' = 0) needs k = sin(2a) / (2r) = tau / cos... at every S."""
    r = rod57.si.radius
    sched = sc.design_twist_schedule(rod57, lambda s: 14 * u.mm + 0 * s, slack_max=0.4 * u.m)
    a = np.arctan(2 * np.pi * r / 0.014)
    np.testing.assert_allclose(sched["twist_rate"], np.sin(2 * a) / (2 * r), rtol=1e-10)
    np.testing.assert_allclose(sched["tension"], sco.tension(a, r, rod57.si.bending_rigidity),
                               rtol=1e-12)
    # N0 from [eq ini]; N grows linearly with slack
    n0 = sched["turns"].iloc[0]
    assert sc.rough_helix(rod57, n0).alpha0.m_as(u.rad) == pytest.approx(a, rel=1e-12, abs=0)
    slope = np.diff(sched["turns"]) / np.diff(sched["slack"] * 1e-3)
    np.testing.assert_allclose(slope, np.sin(2 * a) / (2 * r) / (2 * np.pi), rtol=1e-10)


def test_schedule_columns_units_and_friction(rod57, paper_pitch):
    sched = sc.design_twist_schedule(rod57, paper_pitch)
    for c in ("slack", "turns", "tension", "s", "pitch", "twist_rate"):
        assert c in sched.columns and c in sched.attrs["units"]
    assert sched.attrs["units"]["slack"] == "mm"
    assert sched["slack"].iloc[-1] == pytest.approx(570, rel=1e-5)
    # paper: the no-slip condition is satisfied well for the designed helix
    assert np.all(sched["friction_torque_required"] < sched["friction_torque_available"])


def test_finite_difference_derivative_is_accurate(paper_pitch):
    f = lambda x: 0.016 + 0.004 * np.sin(39.27 * x)  # noqa: E731
    x = np.linspace(0, 0.28, 101)
    d = dh.derivative(f, x, 2.8e-5, 0.0, 0.28)
    np.testing.assert_allclose(d, 0.004 * 39.27 * np.cos(39.27 * x), atol=1e-9)


def test_explicit_derivative_gives_the_same_schedule(rod57, paper_pitch):
    kw = 2 * np.pi / (10 * 16e-3)
    a = sc.design_twist_schedule(rod57, paper_pitch)
    b = sc.design_twist_schedule(
        rod57, paper_pitch,
        pitch_derivative=lambda s: 4e-3 * kw * np.cos(kw * s.m_as(u.m)) * u.dimensionless)
    np.testing.assert_allclose(a["twist_rate"], b["twist_rate"], rtol=1e-7, atol=1e-6)


def test_pitch_at_or_below_2_pi_r_is_the_pi_over_4_singularity(rod57):
    with pytest.raises(sc.SingularityError, match="pi/4"):
        sc.design_twist_schedule(rod57, lambda s: 6 * u.mm + 0 * s)
    with pytest.raises(sc.SingularityError, match="positive"):
        sc.design_twist_schedule(rod57, lambda s: -1 * u.mm + 0 * s)


def test_unit_invariance(paper_pitch):
    rod_si = sc.ElasticRod(1e-3 * u.m, 0.57 * u.m, 4.2e6 * u.Pa, 1.51e6 * u.Pa, 0.5)
    rod_mm = sc.ElasticRod(1 * u.mm, 57 * u.cm, 4.2 * u.MPa, 1.51 * u.MPa, 0.5)
    a = sc.design_twist_schedule(rod_si, paper_pitch, slack_max=0.5 * u.m)
    b = sc.design_twist_schedule(rod_mm, paper_pitch, slack_max=500 * u.mm)
    np.testing.assert_allclose(a["turns"], b["turns"], rtol=1e-12)
    np.testing.assert_allclose(a["tension"], b["tension"], rtol=1e-12)


# --- audit fixes: argument checks ---------------------------------------------------


@pytest.mark.parametrize("n", [0, 2, 9])
def test_too_few_points_are_refused(rod57, paper_pitch, n):
    with pytest.raises(ValueError, match="n_points must be >= 10"):
        sc.design_twist_schedule(rod57, paper_pitch, n_points=n)


def test_non_finite_pitch_derivative_and_guard_are_named(rod57, paper_pitch):
    with pytest.raises(ValueError, match="pitch_derivative"):
        sc.design_twist_schedule(rod57, paper_pitch,
                                 pitch_derivative=lambda s: np.nan * s.m * u.dimensionless)
    with pytest.raises(ValueError, match="cos2a_min"):
        sc.design_twist_schedule(rod57, paper_pitch, cos2a_min=np.nan)
    with pytest.raises(ValueError, match="slack_max"):
        sc.design_twist_schedule(rod57, paper_pitch, slack_max=np.nan * u.m)
