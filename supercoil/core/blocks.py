"""Vectorised kernels over large inputs in blocks: bounded temporaries (float-only).

A solver that is vectorised over its input (e.g. the plectoneme equilibrium
over forces) allocates a few tens of temporary arrays of the input's size.
:func:`in_blocks` runs it on slices of ``block`` elements and writes each
result into preallocated output arrays, so the peak memory beyond the output
is bounded by the block, not by the input.
"""

from __future__ import annotations

import numpy as np

__all__ = ["extremes", "in_blocks", "outside", "points_in_blocks", "select"]


def extremes(x):
    """``(min, max)`` of a non-empty float array; NaN propagates into both.

    One value broadcast over the points (a 1-D view of stride 0, as the public
    layer passes one force) is read once: numpy reduces a stride-0 view element
    by element, as a full array (at 1e6 points 2.7x the reductions of the same
    values written out).
    """
    if x.ndim == 1 and x.strides[0] == 0:
        return x[0], x[0]
    return x.min(), x.max()


def in_blocks(solve, x, block, keep=None):
    """``solve(x)`` computed on blocks of ``x``; the same NamedTuple of arrays.

    Parameters
    ----------
    solve : callable
        ``solve(x_block) -> NamedTuple`` of float arrays of ``x_block``'s shape.
    x : numpy.ndarray
        Input (any shape; processed flattened).
    block : int
        Elements per block; ``x.size <= block`` calls ``solve(x)`` once.
    keep : str, optional
        A field that is ``x`` itself (returned as ``x``, not copied).
    """
    if x.size <= block:
        return solve(x)
    flat = x.reshape(-1)
    first = solve(flat[:block])
    out = {k: np.empty(flat.size) for k in first._fields if k != keep}
    for start in range(0, flat.size, block):
        part = first if start == 0 else solve(flat[start:start + block])
        for k, v in out.items():
            v[start:start + block] = getattr(part, k)
        del part
    fields = {k: v.reshape(x.shape) for k, v in out.items()}
    if keep is not None:
        fields[keep] = x
    return type(first)(**fields)


def points_in_blocks(solve, turns, force, block):
    """``solve(turns, force)`` on blocks of ``block`` points; the same NamedTuple.

    For the hat-curve points of a model: ``turns`` and ``force`` are 1-D arrays
    of one shape; each field keeps its dtype (int8 phases, bool flags) and None
    fields stay None. The temporaries of ``solve`` are bounded by the block.
    """
    n = turns.size
    if n <= block:
        return solve(turns, force)
    first = solve(turns[:block], force[:block])
    out = {k: None if v is None else np.empty(n, np.asarray(v).dtype)
           for k, v in zip(first._fields, first, strict=True)}
    for start in range(0, n, block):
        stop = start + block
        part = first if start == 0 else solve(turns[start:stop], force[start:stop])
        for k, v in out.items():
            if v is not None:
                v[start:stop] = getattr(part, k)
        del part
    return type(first)(**out)


def select(mask):
    """``mask`` as an index: None (no point), a slice (contiguous points: views, no copies)
    or the indices (a gather costs a third of a boolean mask's)."""
    idx = np.flatnonzero(mask)
    if idx.size == 0:
        return None
    if idx[-1] - idx[0] + 1 == idx.size:
        return slice(int(idx[0]), int(idx[-1]) + 1)
    return idx


def outside(size, *selections):
    """Boolean mask of the points in none of the selections (of :func:`select`)."""
    out = np.ones(size, bool)
    for sel in selections:
        if sel is not None:
            out[sel] = False
    return out
