"""The rough-helix kernel: solution object, evaluation budget, accuracy outliers, memory."""

import inspect
import tracemalloc

import numpy as np
import pytest

import supercoil as sc
from supercoil.core.rod import contact as sco
from supercoil.core.rod import rough as rh
from supercoil.core.rod import rough_solution as ro

u = sc.ureg


def rod_a(mu=0.5):
    """Paper Fig. kzero(a): r = 1.0 mm, L = 56.7 cm (silicone rubber E, G)."""
    return sc.ElasticRod(1.0 * u.mm, 56.7 * u.cm, 4.20 * u.MPa, 1.51 * u.MPa, mu)


def _si(rod):
    s = rod.si
    return s.radius, s.length, s.bending_rigidity, s.torsional_rigidity


# --- every ODE run ends in bounded time -------------------------------------------------


def test_absurd_twist_rate_ends_in_a_named_error_within_the_budget():
    """Used to sit in LSODA for more than 10 minutes; now the budget of right-side
    evaluations ends it with the rate named. The default budget is 100 000 evaluations
    (~2-4 s here); the run below spends a tenth of it, the same path in a tenth of the time."""
    assert inspect.signature(sc.rough_helix).parameters["max_nfev"].default == 100_000
    with pytest.raises(sc.SingularityError,
                       match=r"after 10000 right-side evaluations \(its budget\).*"
                             r"twisting rate is k = 1e\+300 rad/m"):
        sc.rough_helix(rod_a(), 40, twist_rate=1e300 / u.m, max_nfev=10_000)
    # implicit solvers fail inside their linear algebra: named too, not a raw ValueError
    for method in ("Radau", "BDF"):
        with pytest.raises(sc.SingularityError, match=rf"\({method}\).*k = 1e\+300 rad/m"):
            sc.rough_helix(rod_a(), 40, twist_rate=1e300 / u.m, ode_method=method)


def test_budget_is_an_argument_and_counts_every_evaluation():
    ok = sc.rough_helix(rod_a(), 40, twist_rate=5 / u.m, slack_max=0.2 * u.m)
    n = ok.solver["nfev"]
    again = sc.rough_helix(rod_a(), 40, twist_rate=5 / u.m, slack_max=0.2 * u.m, max_nfev=n)
    assert again.solver["nfev"] == n
    with pytest.raises(sc.SingularityError, match=rf"after {n - 1} right-side evaluations"):
        sc.rough_helix(rod_a(), 40, twist_rate=5 / u.m, slack_max=0.2 * u.m, max_nfev=n - 1)
    with pytest.raises(ValueError, match="max_nfev must be >= 1"):
        sc.rough_helix(rod_a(), 40, method="ode", max_nfev=0)
    with pytest.raises(TypeError, match="max_nfev"):
        sc.rough_helix(rod_a(), 40, method="ode", max_nfev=1e5)


# --- accuracy outliers ----------------------------------------------------------------------


@pytest.mark.parametrize(("N", "r_mm", "L_cm", "old"), [
    # hypothesis' case: DOP853 ended 5.4e-7 short of s_max, alpha 6.2e-5 rad off (clipping
    # y at 0 put a kink into the right side inside the step over s_max)
    (2.3330754336164494, 2.0000874659683334, 59.5262881778452, "5.4e-7"),
    # one DOP853 step over [0.025, 0.16] m: its dense output put y = 1e-3 1e-8 m off
    # (alpha 1.6e-8 rad off) until the step with the event is integrated again
    (12.705249022274558, 0.4212037922389474, 264.48010497961985, "6e-11"),
])
def test_ode_matches_the_closed_form_at_former_outliers(N, r_mm, L_cm, old):
    rod = sc.ElasticRod(r_mm * u.mm, L_cm * u.cm, 4.2 * u.MPa, 1.51 * u.MPa, 0.5)
    r, L, B, C = _si(rod)
    a0 = sco.initial_tilt(N, r, L, B, C)
    it = rh.integrate(a0, None, r, L, B, C)
    assert it.reason == "alpha->0"
    assert it.s_end == pytest.approx(rh.k0_s_max(a0, L, B, C), rel=1e-11, abs=0)
    cf = sc.rough_helix(rod, N, method="closed_form")
    ode = sc.rough_helix(rod, N, method="ode", s=cf.profile["s"].to_numpy() * u.mm)
    da = np.abs(ode.profile["alpha"].to_numpy() - cf.profile["alpha"].to_numpy())
    assert da.max() <= 1e-8


def test_right_side_is_smooth_through_the_end():
    """k = 0: dy/ds is evaluated as it is for y < 0 (a trial stage past s_max), no kink."""
    r, L, B, C = _si(rod_a())
    y = np.array([-1e-3, 0.0, 1e-3])
    d = ro.dy_ds(0.1, y, 0.0, r, L, B, C)
    np.testing.assert_allclose(d, rh.k0_dy_ds(0.1, y, L, B, C), rtol=1e-14)
    assert d[0] != d[1]  # clipped, these were equal
    assert ro._dy_ds_scalar(0.1, -1e-3, 0.0, r, L, B, C) == pytest.approx(d[0], rel=1e-15, abs=0)


# --- the solution object (scipy OdeSolution style) --------------------------------------------


@pytest.mark.parametrize("k", [0.0, -20.0, 5.0])
def test_solution_object_segments_and_dense_output(k):
    r, L, B, C = _si(rod_a())
    a0 = float(sco.initial_tilt(40.0, r, L, B, C))
    kfun = None if k == 0 else (lambda S: np.full_like(np.asarray(S, float), k))
    it = rh.integrate(a0, kfun, r, L, B, C, s_stop=0.25)
    sol = it.solution
    assert isinstance(sol, ro.RoughSolution) and sol.t_min == 0.0 and sol.t_max == it.s_end
    assert len(sol.ts) == len(sol.interpolants) + 1 and np.all(np.diff(sol.ts) > 0)
    assert sol(0.0) == pytest.approx(sco.y_of_alpha(a0), rel=1e-15, abs=0)
    # segment lookup: a boundary belongs to the segment on its right, the end to the last
    n = len(sol.interpolants)
    np.testing.assert_array_equal(sol.segment(sol.ts), [*range(n), n - 1])
    inner = 0.5 * (sol.ts[:-1] + sol.ts[1:])
    np.testing.assert_array_equal(sol.segment(inner), np.arange(n))
    for i, interp in enumerate(sol.interpolants):
        # continuity at the boundaries: both neighbouring interpolants agree
        left, right = sol.ts[i], sol.ts[i + 1]
        assert interp(np.array([right]))[0] == pytest.approx(
            sol(right), rel=1e-9, abs=1e-12)
        if i:
            assert sol.interpolants[i - 1](np.array([left]))[0] == pytest.approx(
                interp(np.array([left]))[0], rel=1e-9, abs=1e-12)
        # the dense output reproduces its nodes: an s(y) segment maps its y-nodes to s
        if interp.kind == "s(y)":
            ys = interp.dense.ts
            ys = ys[(ys <= interp.y_start) & (ys >= interp.y_end)]
            s_nodes = interp.s_of_y(ys)
            # Scale of the round trip: y = 1 - cos 2 alpha falls from 1e-3 to 0 along the
            # segment, and the s-nodes it comes back from are rounded to ulp(s) = 2.8e-17 m
            # (s ~ 0.21 m), so y can return only to |dy/ds| ulp(s) (dy/ds = -146 /m at
            # y = 1.6e-6 for k = -20: 4e-15, a relative 2.5e-9, where rtol 1e-10 failed),
            # plus the inversion's own stop |dy| <= 1e-15 + 1e-13 |y| (RoughSolution s(y)
            # in supercoil/core/rod/rough_solution.py). Factor 2 for the rounding of dy/ds itself.
            slope = np.abs(interp._rate(s_nodes, ys))
            tol = 2.0 * np.spacing(s_nodes) * slope + 1e-15 + 1e-13 * np.abs(ys)
            err = np.abs(interp(s_nodes) - ys)
            assert np.all(err <= tol), (err / tol).max()
    if k == 0:  # the whole solution against the closed form
        s = np.linspace(0, it.s_end, 301)[:-1]
        np.testing.assert_allclose(sol(s), rh.k0_y_of_s(s, a0, L, B, C), rtol=0, atol=4e-11)
        assert set(sol.kinds) == {"y(s)", "s(y)"}
    with pytest.raises(sc.NoHelixError, match="outside the integrated helix"):
        sol(it.s_end * 1.001)
    with pytest.raises(ValueError, match="ts must increase"):
        ro.RoughSolution([0.0, 1.0], [])


def test_closed_form_is_one_segment_of_the_same_kind_of_object():
    r, L, B, C = _si(rod_a())
    res = rh.rough_profile(40.0, r, L, B, C, 0.5)
    assert res.solution.kinds == ("closed form",) and res.end == "alpha->0"
    a0 = res.alpha0
    s = np.linspace(0, res.s_end, 50)
    np.testing.assert_array_equal(res.solution(s), rh.k0_y_of_s(s, a0, L, B, C))


# --- bounded memory -------------------------------------------------------------------------


def test_long_profile_needs_bounded_memory_beyond_the_output():
    """n_points = 1e7 used to need 10 GB (every profile point in the quadrature grid);
    the profile is now built in chunks: <= 64 bytes per point beyond the table."""
    n = 200_000
    sc.rough_helix(rod_a(), 40, n_points=100)  # warm caches outside the measurement
    tracemalloc.start()
    try:
        res = sc.rough_helix(rod_a(), 40, n_points=n)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    p = res.profile
    out = p.memory_usage(deep=True).sum()
    assert len(p) >= n - 1
    assert (peak - out) / len(p) <= 64
    # the long profile is the short one, refined
    short = sc.rough_helix(rod_a(), 40, s=p["s"].to_numpy()[::997] * u.mm).profile
    for c in ("alpha", "twist", "writhe", "turns"):
        np.testing.assert_allclose(p[c].to_numpy()[::997], short[c], rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("kw", [{}, {"twist_rate": -20 / u.m}, {"twist_rate": 5 / u.m}])
def test_chunks_do_not_change_the_profile(monkeypatch, kw):
    ref = sc.rough_helix(rod_a(), 40, n_points=300, **kw).profile
    monkeypatch.setattr(rh, "CHUNK", 7)  # and a last chunk of 1 or 2 points near the end
    chunked = sc.rough_helix(rod_a(), 40, n_points=300, **kw).profile
    for c in ref.columns:  # the s(y) inversion stops at 1e-13 relative in y
        np.testing.assert_allclose(chunked[c], ref[c], rtol=1e-9, atol=1e-12)
