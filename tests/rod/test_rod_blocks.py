"""smooth_helix and twist_spinning in blocks: the values of the whole-array solver, bit for bit.

tests/rod/data/smooth_spinning_reference.json holds every field of both records on a
12 x 4 and a 12 x 5 grid (turns from 1e-3 to 55.5, both signs; slack 0-33.3 cm; head
tension 0-17 N), written with repr() by the earlier implementation (commit d9eedab: one
plain bisection over the whole array); the present solver (a Newton estimate, a grid
cell checked by signs, the bisection inside it) must give the same roots. The roots
(the tilts) are the same floats on any machine (the bisection keeps the sign of each
cell); the fields derived from them through sin, cos and tan are met to 4 ulp, because
numpy's SIMD loops of those round differently on different CPUs (1 ulp apart on an
AVX2-only CPU).
"""

import json
import warnings
from pathlib import Path

import numpy as np
import pytest

import supercoil as sc
from supercoil.core import numerics as nu
from supercoil.core.numerics import bisect_from_estimate, bisect_increasing
from supercoil.core.rod import smooth as sm
from supercoil.core.rod import spinning as sp

u = sc.ureg
REF = json.loads((Path(__file__).parent / "data" / "smooth_spinning_reference.json").read_text())


def _records():
    rod = sc.load_parameters("silicone_rubber_rod")
    N = np.array(REF["turns"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.ValidityWarning)  # the largest tilts (b > r)
        h = sc.smooth_helix(rod, N[:, None], np.array(REF["slack_cm"])[None, :] * u.cm)
        s = sc.twist_spinning(rod, N[:, None], np.array(REF["head_tension_N"])[None, :] * u.N)
    return {"smooth": h, "spinning": s}


def test_blocked_solvers_reproduce_the_previous_values_bitwise():
    for name, rec in _records().items():
        for field, text in REF[name].items():
            want = np.array([float(v) for v in text])
            got = np.ravel(np.broadcast_to(rec.si(field), np.shape(rec.si("alpha"))))
            if field.startswith("alpha"):
                np.testing.assert_array_equal(got, want, err_msg=f"{name}.{field}")
            else:
                np.testing.assert_allclose(got, want, rtol=9e-16, atol=0.0,
                                           err_msg=f"{name}.{field}")


def test_block_boundaries_do_not_change_values():
    rod = sc.load_parameters("silicone_rubber_rod")
    N = np.linspace(1, 40, 2 * sm.BLOCK + 7)
    big_h = sc.smooth_helix(rod, N, 10 * u.cm)
    big_s = sc.twist_spinning(rod, N, 2 * u.N)
    for i in (0, sm.BLOCK - 1, sm.BLOCK, sm.BLOCK + 1, 2 * sm.BLOCK + 6):
        one_h = sc.smooth_helix(rod, N[i], 10 * u.cm)
        one_s = sc.twist_spinning(rod, N[i], 2 * u.N)
        for f in ("alpha", "tension", "normal_force", "linking_number"):
            assert big_h.si(f)[i] == one_h.si(f), (f, i)
        for f in ("alpha", "beta", "pitch", "alpha_slacking", "pitch_increase"):
            assert big_s.si(f)[i] == one_s.si(f), (f, i)


def test_estimate_steered_bisection_equals_plain_bisection_where_newton_misses():
    # a useless Newton estimate (and a root near the smallest normal float): the cell
    # check fails, the plain bisection runs
    def fun(x, c):
        return x - c

    def fun_df(x, c):
        return x - c + 1e300 * (x > 0), np.ones_like(x)

    c = np.array([1e-300, 0.3, 0.7])
    lo, hi = np.zeros(3), np.ones(3)
    got = bisect_from_estimate(fun, fun_df, (c,), lo, hi)
    np.testing.assert_array_equal(got, bisect_increasing(lambda x: x - c, lo, hi))


@pytest.mark.parametrize("off_cells", [0.5, 1.5, 40.0])
def test_an_estimate_off_by_cells_is_moved_or_replaced_by_the_plain_bisection(off_cells):
    # Newton converges to a shifted root: half a cell off stays in or next to the cell,
    # 1.5 cells off is moved once or (two cells off) checked and replaced, 40 cells off
    # fails the check; every element gives the plain bisection's root
    c = np.linspace(0.11, 0.74, 257)
    shift = off_cells * 2.0**nu.CELL_BITS * np.spacing(c)

    def fun(x, c):
        return np.sin(x) - np.sin(c)

    def fun_df(x, c):
        return np.sin(x) - np.sin(c + shift), np.cos(x)

    lo, hi = np.zeros(c.shape), np.ones(c.shape)
    got = bisect_from_estimate(fun, fun_df, (c,), lo, hi)
    np.testing.assert_array_equal(got, bisect_increasing(lambda x: fun(x, c), lo, hi))


@pytest.mark.parametrize("tension", [0.0, 2.0, 17.0])
def test_rod_tilts_equal_the_plain_bisection_on_a_wide_grid(tension):
    rod = sc.load_parameters("silicone_rubber_rod").si
    r, L, B, C = rod.radius, rod.length, rod.bending_rigidity, rod.torsional_rigidity
    n = np.geomspace(1e-3, 55.0, 3001)
    lo, hi = np.zeros(n.shape), np.full(n.shape, np.pi / 4)
    want = bisect_increasing(lambda a: sp._G(a, n / L, tension, r, B, C), lo, hi)
    np.testing.assert_array_equal(sp.spinning_tilt(n, tension, r, L, B, C), want)
    rhs = (C / B) * 4.0 * np.pi * r * n / L
    want0 = bisect_increasing(lambda a: sp._h0(a, rhs), lo, hi)
    np.testing.assert_array_equal(sp.slacking_tilt(n, r, L, B, C), want0)
