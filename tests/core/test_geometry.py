"""Geometry core (docs/theory/geometry.md): identities, derivatives, round trips, units, writhe."""

import numpy as np
import pint
import pytest
from hypothesis import given
from hypothesis import strategies as st

import supercoil as sc
from supercoil.core import gauss_writhe as gw
from supercoil.core import geometry as g

alphas = st.floats(min_value=1e-3, max_value=np.pi / 2 - 1e-3)
radii = st.floats(min_value=1e-9, max_value=1.0)


@given(alphas, radii)
def test_curvature_torsion_identities(alpha, R):
    k, t = g.curvature(alpha, R), g.torsion(alpha, R)
    assert k**2 + t**2 == pytest.approx(np.sin(alpha) ** 2 / R**2, rel=1e-12, abs=0)
    assert t / k == pytest.approx(1.0 / np.tan(alpha), rel=1e-12, abs=0)


@given(alphas, radii)
def test_pitch_tilt_round_trip(alpha, R):
    P = g.pitch_from_tilt(alpha, R)
    assert g.tilt_angle(R, P) == pytest.approx(alpha, rel=1e-12, abs=0)
    assert g.radius_from_tilt(alpha, P) == pytest.approx(R, rel=1e-12, abs=0)


@given(alphas, radii)
def test_curvature_and_torsion_from_the_parametrised_curve(alpha, R):
    # kappa = |r' x r''| / |r'|^3, tau = (r' x r'') . r''' / |r' x r''|^2 at theta = 0
    P = g.pitch_from_tilt(alpha, R)
    c = P / (2 * np.pi)
    r1 = np.array([0.0, R, c])
    r2 = np.array([-R, 0.0, 0.0])
    r3 = np.array([0.0, -R, 0.0])
    x = np.cross(r1, r2)
    kappa = np.linalg.norm(x) / np.linalg.norm(r1) ** 3
    tau = np.dot(x, r3) / np.dot(x, x)
    assert g.curvature(alpha, R) == pytest.approx(kappa, rel=1e-10, abs=0)
    assert g.torsion(alpha, R) == pytest.approx(tau, rel=1e-10, abs=0)


@given(st.floats(0.05, 1.5), st.floats(0.1, 10.0))
def test_partial_derivatives_against_finite_differences(alpha, R):
    h = 1e-6
    for func, partials in ((g.curvature, g.curvature_partials), (g.torsion, g.torsion_partials)):
        da, dr = partials(alpha, R)
        fd_a = (func(alpha + h, R) - func(alpha - h, R)) / (2 * h)
        fd_r = (func(alpha, R + h * R) - func(alpha, R - h * R)) / (2 * h * R)
        assert da == pytest.approx(fd_a, rel=1e-7, abs=1e-9)
        assert dr == pytest.approx(fd_r, rel=1e-7, abs=1e-9)


def test_partials_broadcast_over_arrays():
    a = np.linspace(0.1, 1.0, 7)[:, None]
    R = np.array([1.0, 2.0, 3.0])
    da, dr = g.torsion_partials(a, R)
    assert da.shape == dr.shape == (7, 3)


def test_curvature_error_factor():
    assert g.curvature_error(0.0) == 1.0
    # exact curvature of the slowly varying helix: e - 1 ~ (dP/ds)^2 / (8 pi^2)
    d = 1e-2
    assert g.curvature_error(d) - 1 == pytest.approx(d**2 / (8 * np.pi**2), rel=1e-4)
    s = np.linspace(0, 1, 101)
    e = g.curvature_error_profile(s, 0.3 * s)  # dP/ds = 0.3 exactly
    np.testing.assert_allclose(e, np.sqrt(1 + 0.09 / (4 * np.pi**2)), rtol=1e-14)


@given(alphas, radii, st.floats(1e-9, 10.0))
def test_writhe_is_two_cos_alpha_per_superhelical_turn(alpha, R, S):
    n = g.superhelical_turns(alpha, R, S)
    assert g.writhe_uniform(alpha, R, S) == pytest.approx(2 * np.cos(alpha) * n, rel=1e-12, abs=0)
    assert g.writhe_one_view(alpha, R, S) == pytest.approx(2 * n, rel=1e-12, abs=0)


def test_strand_integrals_of_uniform_profiles():
    s = np.linspace(0.0, 0.2, 51)
    tau = np.full_like(s, 3.0)
    assert g.strand_integral(s, tau) == pytest.approx(3.0 * 0.4 / (2 * np.pi))
    cum = g.cumulative_strand_integral(s, tau)
    assert cum[0] == 0.0
    np.testing.assert_allclose(cum, 3.0 * 2 * s / (2 * np.pi), rtol=1e-13)


# --- public wrappers: units, dimensions, invariance ---------------------------------

def test_unit_invariance_of_public_geometry(ureg):
    a1 = sc.geometry.tilt_angle(2.0 * ureg.nm, 20.0 * ureg.nm)
    a2 = sc.geometry.tilt_angle(2e-9 * ureg.m, 0.02 * ureg.um)
    assert a1.m_as("rad") == pytest.approx(a2.m_as("rad"), rel=1e-14, abs=0)
    k1 = sc.geometry.curvature(30 * ureg.deg, 1.0 * ureg.mm)
    k2 = sc.geometry.curvature(np.pi / 6 * ureg.rad, 1e-3 * ureg.m)
    assert k1.m_as("1/m") == pytest.approx(k2.m_as("1/m"), rel=1e-14)
    assert k1.m_as("1/m") == pytest.approx(0.25e3, rel=1e-12)


@pytest.mark.parametrize(
    ("call", "argname"),
    [
        (lambda u: sc.geometry.tilt_angle(1 * u.s, 1 * u.m), "radius"),
        (lambda u: sc.geometry.tilt_angle(1 * u.m, 1 * u.N), "pitch"),
        (lambda u: sc.geometry.torsion(1 * u.m, 1 * u.m), "alpha"),
        (lambda u: sc.geometry.writhe(0.3 * u.rad, 1 * u.mm, 1 * u.K), "slack"),
        (lambda u: sc.geometry.linking_number(0.3 * u.rad, 1 * u.mm, 1 * u.m, 2 * u.m,
                                              1 * u.m), "omega_helix"),
    ],
)
def test_wrong_dimension_raises_naming_the_argument(ureg, call, argname):
    with pytest.raises(pint.DimensionalityError, match=f"'{argname}'"):
        call(ureg)


def test_pitch_singular_at_zero_tilt(ureg):
    with pytest.raises(sc.SingularityError, match="alpha = 0"):
        sc.geometry.pitch_from_tilt(0 * ureg.rad, 1 * ureg.mm)


def test_linking_number_conservation_uniform(ureg):
    alpha, R, S, L = 0.4 * ureg.rad, 1 * ureg.mm, 20 * ureg.cm, 57 * ureg.cm
    omega = 30 / ureg.m
    lk, tw, wr = sc.geometry.linking_number(alpha, R, S, L, omega)
    assert (tw + wr).m == pytest.approx(lk.m)
    expected_wr = np.sin(0.4) * np.cos(0.4) / 1e-3 * 0.2 / (2 * np.pi)
    assert wr.m == pytest.approx(expected_wr)
    assert tw.m == pytest.approx(30 * 0.57 / (2 * np.pi))


# --- independent check of the writhe formula by the Gauss double integral -----------

@pytest.mark.parametrize("alpha_deg", [5, 12, 20, 30, 40])
def test_gauss_writhe_of_discretised_double_helix(alpha_deg):
    """Wr(formula) = 2 cos(alpha) per turn against the exact polygon Gauss integral.

    Tolerance: the polygon with 100 points per turn differs from the smooth
    helix by O((2 pi/100)^2 / 24) ~ 2e-4 relative; end effects (head loop,
    tail junction, closure) add a length-independent constant, removed by
    comparing the writhe gained between 2 and 4 turns. We assert 1e-3
    relative for the per-turn writhe and 0.01 absolute for the totals.
    The one-view count (2 per turn) misses by 2 (1 - cos alpha) per turn.
    """
    alpha = np.radians(alpha_deg)
    wr = {n: gw.writhe_polygon(gw.double_helix_polygon(alpha, 1.0, n, handedness=-1,
                                                       points_per_turn=100))
          for n in (2, 4)}
    per_turn = (wr[4] - wr[2]) / 2
    assert per_turn == pytest.approx(2 * np.cos(alpha), rel=1e-3)
    for n, value in wr.items():
        S = n * 4 * np.pi * 1.0 / np.sin(alpha)  # slack holding n superhelical turns
        assert value == pytest.approx(g.writhe_uniform(alpha, 1.0, S), abs=0.01)
        one_view_error = g.writhe_one_view(alpha, 1.0, S) - value
        assert one_view_error == pytest.approx(2 * n * (1 - np.cos(alpha)), abs=0.01)


def test_gauss_writhe_sign_follows_handedness():
    """Left-handed strands: positive writhe (positive N); right-handed: negative."""
    a = np.radians(25)
    left = gw.writhe_polygon(gw.double_helix_polygon(a, 1.0, 2, handedness=-1, points_per_turn=60))
    right = gw.writhe_polygon(gw.double_helix_polygon(a, 1.0, 2, handedness=+1, points_per_turn=60))
    assert left > 3.0
    assert right == pytest.approx(-left, rel=1e-10)


def test_gauss_writhe_of_planar_curve_is_zero():
    t = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    ellipse = np.column_stack((3 * np.cos(t), np.sin(t), np.zeros_like(t)))
    assert gw.writhe_polygon(ellipse) == pytest.approx(0.0, abs=1e-12)


@pytest.mark.parametrize(
    ("call", "match"),
    [
        (lambda u: sc.geometry.tilt_angle(1 * u.mm, -5 * u.mm), "pitch must be positive"),
        (lambda u: sc.geometry.tilt_angle(1 * u.mm, np.nan * u.mm), "pitch must be finite"),
        (lambda u: sc.geometry.tilt_angle(np.inf * u.mm, 5 * u.mm), "radius must be finite"),
        (lambda u: sc.geometry.pitch_from_tilt(np.nan * u.rad, 1 * u.mm), "alpha must be finite"),
        (lambda u: sc.geometry.pitch_from_tilt(2.0 * u.rad, 1 * u.mm), r"alpha must lie in"),
        (lambda u: sc.geometry.radius_from_tilt(0.3 * u.rad, -1 * u.mm), "pitch must be positive"),
        (lambda u: sc.geometry.curvature(-0.1 * u.rad, 1 * u.mm), "alpha must lie in"),
        (lambda u: sc.geometry.torsion(0.3 * u.rad, np.nan * u.mm), "radius must be finite"),
        (lambda u: sc.geometry.curvature_error(np.inf), "dpitch_ds must be finite"),
        (lambda u: sc.geometry.writhe(0.3 * u.rad, 1 * u.mm, -1 * u.m), "slack must be >= 0"),
        (lambda u: sc.geometry.linking_number(0.3 * u.rad, 1 * u.mm, 1 * u.m, 0.5 * u.m,
                                              1 / u.m), "slack must not exceed length"),
        (lambda u: sc.geometry.linking_number(0.3 * u.rad, 1 * u.mm, 0.1 * u.m, 0.5 * u.m,
                                              np.nan / u.m), "omega_helix must be finite"),
    ],
)
def test_non_finite_or_out_of_range_values_raise_naming_the_argument(ureg, call, match):
    """tilt_angle(1 mm, -5 mm) returned 2.24 rad unflagged; NaN passed through."""
    with pytest.raises(ValueError, match=match):
        call(ureg)
