"""supercoil.core.numerics: each helper against scipy and closed forms, and bounded.

``python tests/core/test_numerics.py`` prints the measurements quoted in the
module docstring of :mod:`supercoil.core.numerics` (no test asserts a timing).
"""

import time

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import tanhsinh
from scipy.optimize import brentq
from scipy.optimize.elementwise import find_root

from supercoil.core import numerics as nu


def test_bisection_matches_find_root_and_the_closed_root():
    q = np.geomspace(1e-300, 1e3, 200)
    x = nu.bisect_increasing(lambda x: x**3 - q, np.zeros_like(q), np.full_like(q, 20.0))
    ref = find_root(lambda x, q: x**3 - q, (np.zeros_like(q), np.full_like(q, 20.0)),
                    args=(q,)).x
    # the root of the float function x**3 - q: np.power's and np.cbrt's SIMD loops round
    # differently on different CPUs (a few ulp: on an AVX2-only CPU the two are 5.7e-16
    # apart, within 4e-16 on the earlier ones), so the closed root is met to 1e-15
    np.testing.assert_allclose(x, np.cbrt(q), rtol=1e-15)
    # find_root agrees, but stops on |f| ~ 4 tiny for roots below ~1e-98 (7e-12 off)
    np.testing.assert_allclose(x[q > 1e-290], ref[q > 1e-290], rtol=1e-15)
    np.testing.assert_allclose(x, ref, rtol=1e-11)


def test_bisection_uses_only_the_sign_and_reaches_subnormal_roots():
    q = np.array([0.3, 2.0, 7.5])
    a = nu.bisect_increasing(lambda x: x - q, 0.0, 10.0)
    b = nu.bisect_increasing(lambda x: 1e-200 * (x - q) * (1 + x**2), 0.0, 10.0)
    assert np.array_equal(a, b)  # any positive multiple: the same floats
    tiny = nu.bisect_increasing(lambda x: x - 1e-320, 0.0, 1.0)
    assert tiny == pytest.approx(1e-320, rel=1e-3, abs=0)  # subnormal: ~3 significant digits exist


@given(q=st.floats(1e-6, 1e6))
def test_safe_newton_matches_find_root_on_a_square_root(q):
    x = nu.safe_newton(lambda x: (x * x - q, 2 * x), np.array([1.0]), np.array([0.0]),
                       np.array([max(1.0, q)]), 1e-15)
    ref = find_root(lambda x: x * x - q, (0.0, max(1.0, q))).x
    assert x[0] == pytest.approx(np.sqrt(q), rel=1e-14, abs=0)
    assert x[0] == pytest.approx(ref, rel=1e-14, abs=0)


def test_safe_newton_falls_back_to_bisection_and_stops():
    # zero and NaN derivatives: Newton steps are refused, the bracket still shrinks
    x = nu.safe_newton(lambda x: (x - 0.7, np.where(x < 0.5, 0.0, np.nan)), np.array([0.1]),
                       np.array([0.0]), np.array([1.0]), 1e-15)
    assert x[0] == pytest.approx(0.7, abs=1e-14)
    # maxiter bounds the work even for a hopeless tolerance
    calls = []
    nu.safe_newton(lambda x: (calls.append(1) or (x - 0.7), np.full_like(x, np.nan)),
                   np.array([0.1]), np.array([0.0]), np.array([1.0]), 0.0, maxiter=30)
    assert len(calls) == 30


def test_cumulative_integrals_against_closed_forms_and_tanhsinh():
    b = np.linspace(0.0, 3.0, 7)
    out = nu.cumulative_integrals(lambda x: np.vstack([np.sin(x), np.exp(x)]), b)
    np.testing.assert_allclose(out[0], 1 - np.cos(b), rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(out[1], np.expm1(b), rtol=1e-13)
    ref = np.concatenate([[0.0], np.cumsum(tanhsinh(np.sin, b[:-1], b[1:]).integral)])
    np.testing.assert_allclose(out[0], ref, rtol=1e-12, atol=1e-15)
    # a single breakpoint: zeros; an integrable sqrt singularity at the left end
    assert nu.cumulative_integrals(lambda x: np.vstack([x]), [1.0]).shape == (1, 1)
    root = nu.cumulative_integrals(lambda x: np.vstack([1 / np.sqrt(x)]), [0.0, 1.0])
    assert root[0, -1] == pytest.approx(2.0, rel=1e-6)


def test_cumulative_integrals_localise_a_jump_and_stay_bounded():
    b = np.array([0.0, 1.0])
    jump = nu.cumulative_integrals(lambda x: np.vstack([np.where(x < 1 / 3, 1.0, 5.0)]), b)
    assert jump[0, -1] == pytest.approx(1 / 3 + 5 * 2 / 3, rel=1e-10)
    calls = []

    def nan_inside(x):
        calls.append(x.size)
        return np.vstack([np.where(x > 0.5, np.nan, x)])

    out = nu.cumulative_integrals(nan_inside, b)  # no refinement helps: returned, not looped
    assert np.isnan(out[0, -1]) and len(calls) == 1


def test_cumulative_integrals_absolute_budget_stops_rounding_noise():
    """A short piece of a long integral: with only the relative budget, noise of the
    integrand above rtol forces halving (14 levels, 670 000 evaluations here); an
    absolute budget (from the whole range) accepts the first pass."""
    rng = np.random.default_rng(0)
    calls = []

    def noisy(x):
        calls.append(x.size)
        return np.vstack([1.0 + 1e-10 * rng.standard_normal(x.size)])

    b = np.linspace(0.5, 0.5 + 1e-9, 5)
    nu.cumulative_integrals(noisy, b)
    assert len(calls) > 5
    calls.clear()
    out = nu.cumulative_integrals(noisy, b, atol=1e-15)
    assert out[0, -1] == pytest.approx(1e-9, rel=0, abs=1e-15) and len(calls) == 1  # the budget


def test_finite_difference_matches_scipy_and_the_exact_derivative():
    from scipy.differentiate import derivative

    x = np.linspace(0.0, 1.0, 41)
    d = nu.finite_difference(np.exp, x, 1e-3, 0.0, 1.0)  # one-sided at both ends
    np.testing.assert_allclose(d, np.exp(x), rtol=1e-10)
    ref = derivative(np.exp, x[5:-5]).df
    np.testing.assert_allclose(d[5:-5], ref, rtol=1e-10)
    seen = []
    nu.finite_difference(lambda t: seen.append(t) or np.sin(t), x, 1e-2, 0.0, 1.0)
    assert min(map(np.min, seen)) >= 0.0 and max(map(np.max, seen)) <= 1.0


def test_first_crossing_matches_brentq():
    s = np.linspace(0.0, 2.0, 11)

    def g(x):
        return np.cos(x) - 0.2

    ref = brentq(g, 0.0, 2.0, xtol=1e-15)
    assert nu.first_crossing(s, -g(s), lambda x: -g(x)) == pytest.approx(ref, abs=1e-14)
    assert nu.first_crossing(s, -np.ones_like(s), lambda x: -1.0) is None
    assert nu.first_crossing(s + 1.0, np.ones_like(s), lambda x: 1.0) == 1.0


def measure(repeat=7):
    """Times of the hand-written solvers and their scipy equivalents (printed)."""
    from supercoil.core.dna import plectoneme as pl
    from supercoil.core.rod import contact as sc
    from supercoil.core.rod import rough as rh

    def best(f):
        t = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            f()
            t.append(time.perf_counter() - t0)
        return min(t)

    r, L, B, C = 1e-3, 0.567, np.pi * 4.2e6 * 1e-12 / 4, np.pi * 1.51e6 * 1e-12 / 2
    rhs = (C / B) * 4 * np.pi * r * np.geomspace(1e-6, 2000, 1000) / L

    def h(a, q):
        return sc.y_of_alpha(a) * np.sin(2 * a) - q * np.cos(2 * a)

    lo, hi = np.zeros_like(rhs), np.full_like(rhs, sc.QUARTER_PI)
    own = best(lambda: nu.bisect_increasing(lambda a: h(a, rhs), lo, hi))
    print("bisection / find_root", best(lambda: find_root(h, (lo, hi), args=(rhs,))) / own)
    rho = np.geomspace(pl.RHO_MIN, 1e4, 600)
    own = best(lambda: pl.reduced_tilt(rho, 100.0))
    fr = best(lambda: find_root(lambda a, q: pl.reduced_ge2(a, q, 100.0),
                                (np.full(rho.shape, 1e-6), np.full(rho.shape, np.pi / 4 - 1e-9)),
                                args=(rho,)))
    print("safe_newton / find_root", fr / own)
    a0 = float(sc.initial_tilt(40.0, r, L, B, C))
    s = np.linspace(0, rh.k0_s_max(a0, L, B, C) * (1 - 1e-7), 2000)
    y0, drop = float(sc.y_of_alpha(a0)), -(C / B) * np.log1p(-2 * s / L)
    own = best(lambda: rh.k0_y_of_s(s, a0, L, B, C))
    fr = best(lambda: find_root(lambda y, d: d - rh.phi_diff(y, y0),
                                (np.zeros_like(s), np.full_like(s, y0)), args=(drop,)))
    print("k = 0 Newton / find_root", fr / own)
    from supercoil.core.dna import phases as ph

    A, kT = 50e-9, 1.380649e-23 * 298.15
    for n in (1, 20, 1000):
        f = np.linspace(0.0, 100e-12, n) * A / kT if n > 1 else np.array([2e-12 * A / kT])
        own = best(lambda f=f: ph.wlc_extension(f * kT / A, A, kT))
        fr = best(lambda f=f: find_root(lambda x, t: ph._bouchiat_reduced_force(x) - t,
                                        (np.zeros_like(f), np.full_like(f, 1.0 - 1e-13)),
                                        args=(f,)))
        print(f"WLC inversion ({n} forces) safe_newton / find_root", fr / own)


if __name__ == "__main__":
    measure()


def test_table_cubic_reproduces_cubics_on_a_descending_table():
    """numerics.table_cubic: Lagrange through the four rows around each interval is exact
    for cubics (to rounding), on a non-uniform descending table, at its ends too; a table
    of two rows interpolates linearly."""
    from supercoil.core.numerics import table_cubic

    nodes = np.sort(np.random.default_rng(5).uniform(0.0, 3.0, 40))[::-1]
    x = np.linspace(nodes[-1], nodes[0], 997)
    k = np.clip(np.searchsorted(-nodes, -x, side="left") - 1, 0, nodes.size - 2)
    cubic = lambda t: 0.3 - 1.2 * t + 0.7 * t**2 - 0.25 * t**3  # noqa: E731
    line = lambda t: 2.0 - 0.5 * t  # noqa: E731
    got, also = table_cubic(x, k, nodes, cubic(nodes), line(nodes))
    np.testing.assert_allclose(got, cubic(x), rtol=0, atol=1e-12)
    np.testing.assert_allclose(also, line(x), rtol=0, atol=1e-13)
    two = nodes[[0, -1]]
    (lin,) = table_cubic(x, np.zeros(x.size, int), two, line(two))
    np.testing.assert_allclose(lin, line(x), rtol=0, atol=1e-13)


@pytest.mark.parametrize(("m", "n", "columns"), [
    (4, 33, 10), (4, 33, 496), (4, 33, 497), (4, 33, 4097), (6, 65, 2049), (2, 17, 1),
    (300, 300, 3)])  # the last: wider than the bound in one column, one column per block
def test_single_thread_product_is_the_matrix_product(m, n, columns):
    """The column blocks give ``a @ b``: the same dot products, so within the sums' rounding
    (n eps sum|a||b|), and the blocks stay under the single-thread bound."""
    rng = np.random.default_rng(columns)
    a, b = rng.normal(size=(m, n)), rng.normal(size=(n, columns))
    got = nu.single_thread_product(a, b)
    assert got.shape == (m, columns)
    bound = n * np.finfo(float).eps * (np.abs(a) @ np.abs(b))
    assert np.all(np.abs(got - a @ b) <= bound)
    width = max(nu.SINGLE_THREAD_PRODUCT // (m * n), 1)
    assert m * n * min(width, columns) <= max(nu.SINGLE_THREAD_PRODUCT, m * n)


def _helper_thread_ticks():
    """CPU clock ticks of this process's threads that Python did not start (BLAS's and
    other libraries' workers; not the suite's background lane), from Linux's /proc."""
    import os
    import threading

    python, ticks = {t.native_id for t in threading.enumerate()}, 0
    for task in os.listdir("/proc/self/task"):
        if int(task) not in python:
            with open(f"/proc/self/task/{task}/stat") as f:
                fields = f.read().rsplit(")", 1)[1].split()
            ticks += int(fields[11]) + int(fields[12])  # utime + stime
    return ticks


def test_a_cold_physical_fit_leaves_the_blas_threads_idle():
    """A cold free-energy + screened fit (its branch table built: a (4 x 33) @ (33 x 4097)
    product of the series rows) runs no BLAS product threaded: a threaded product leaves
    OpenBLAS's idle threads spinning for about 0.1 s, CPU that doubled the fit's. The
    helper threads may use at most 2 clock ticks (20 ms) over the fit and 0.15 s after it;
    a spinning thread takes about 10 in the 0.15 s alone."""
    import os

    tp = pytest.importorskip("threadpoolctl")
    if not os.path.isdir("/proc/self/task"):
        pytest.skip("needs Linux /proc to read each thread's CPU")
    pools = [p for p in tp.threadpool_info() if p["user_api"] == "blas"]
    if not pools:  # threadpoolctl 3.1 does not know numpy 2's scipy-openblas build
        pytest.skip(f"threadpoolctl {tp.__version__} finds no BLAS library here, so the "
                    "test cannot tell whether BLAS may run threaded")
    if max(p["num_threads"] for p in pools) < 2:
        pytest.skip("BLAS runs on one thread here (no helper thread could spin)")
    import warnings

    import supercoil as sc
    from supercoil.benchmark.targets_fit import clear_kernel_caches

    u = sc.ureg
    dna = sc.load_parameters("dna_150mM_nacl")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        data = sc.simulate_rotation_curves(dna, np.array([0.5, 2.0]) * u.pN,
                                           points_per_force=40, noise=5 * u.nm, seed=3)
        clear_kernel_caches()
        time.sleep(0.2)  # threads a product before this test started settle first
        before = _helper_thread_ticks()
        sc.fit_hat_curves(data, dna, vary=["twist_persistence"], model="free-energy",
                          interaction="screened")
        time.sleep(0.15)
    assert _helper_thread_ticks() - before <= 2
