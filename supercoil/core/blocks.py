"""Vectorised kernels over large inputs in blocks: bounded temporaries (float-only).

A solver that is vectorised over its input (e.g. the plectoneme equilibrium
over forces) allocates a few tens of temporary arrays of the input's size.
:func:`in_blocks` runs it on slices of ``block`` elements and writes each
result into preallocated output arrays, so the peak memory beyond the output
is bounded by the block, not by the input (issue 9, item 12).
"""

from __future__ import annotations

import numpy as np

__all__ = ["in_blocks"]


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
