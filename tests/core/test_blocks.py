"""supercoil.core.blocks: blocked evaluation equals the whole, the extremes equal numpy's."""

from typing import NamedTuple

import numpy as np
from hypothesis import given
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from supercoil.core import blocks

FLOATS = st.floats(allow_nan=True, allow_infinity=True, width=64)


@given(hnp.arrays(np.float64, st.integers(1, 50), elements=FLOATS))
def test_extremes_are_numpys_min_and_max(x):
    np.testing.assert_equal(blocks.extremes(x), (x.min(), x.max()))


@given(FLOATS, st.integers(1, 10_000))
def test_extremes_of_one_value_broadcast_read_it_once(v, n):
    x = np.broadcast_to(np.float64(v), (n,))
    assert x.strides == (0,)
    np.testing.assert_equal(blocks.extremes(x), (x.min(), x.max()))
    np.testing.assert_equal(blocks.extremes(x), (v, v))


class _Pair(NamedTuple):
    x: np.ndarray
    y: np.ndarray


def test_blocked_solves_equal_the_whole_and_keep_dtypes():
    x = np.linspace(-3, 3, 1001)
    whole = _Pair(np.sin(x), np.cos(x))
    part = blocks.in_blocks(lambda b: _Pair(np.sin(b), np.cos(b)), x, 64)
    for a, b in zip(whole, part, strict=True):
        np.testing.assert_array_equal(a, b)
    kept = blocks.in_blocks(lambda b: _Pair(b, b * 2), x, 64, keep="x")
    assert kept.x is x
    pts = blocks.points_in_blocks(lambda t, f: _Pair(t > f, t * f), x, x[::-1].copy(), 100)
    assert pts.x.dtype == bool
    np.testing.assert_array_equal(pts.x, x > x[::-1])
    np.testing.assert_array_equal(pts.y, x * x[::-1])


def test_select_gives_a_slice_for_contiguous_points_and_outside_the_rest():
    m = np.zeros(10, bool)
    assert blocks.select(m) is None
    m[3:6] = True
    assert blocks.select(m) == slice(3, 6)
    m[8] = True
    np.testing.assert_array_equal(blocks.select(m), [3, 4, 5, 8])
    np.testing.assert_array_equal(blocks.outside(10, slice(3, 6), np.array([8]), None),
                                  ~m)
