"""Roots of many increasing functions started from a table of their values (float numerics).

The pattern of the ensemble kernel (:mod:`supercoil.core.dna.ensemble`): each element's
function is a cheap combination of a few functions tabulated on one grid of nodes, so
its values and slopes at the nodes cost a gather, not an evaluation. A binary search
over the node indices (:func:`cell_search`) finds the cell of the sign change, inverse
Hermite interpolation of the cell (:func:`hermite_inverse`) estimates the root, and a
safeguarded Newton iteration on the exact function (:func:`bracketed_newton`) finishes
it in one or two evaluations, keeping what the last exact evaluation returned beside the
value (extension, free energy) so that nothing is evaluated again at the root.

Kept hand-written by measurement (the numbers are in docs/theory/ensemble.md#34-numerics):
scipy's elementwise ``find_root`` from the whole torque bracket needs about 11
evaluations of the exact function per element, this scheme about 2.
"""

from __future__ import annotations

import numpy as np

__all__ = ["bracketed_newton", "cell_search", "hermite_inverse"]


def cell_search(value_at, n_nodes, shape):
    """Cell ``k`` (``0 <= k <= n_nodes - 2``) of each element's sign change, by bisection.

    ``value_at(k)`` returns each element's function value at its node index ``k`` (an
    integer array of ``shape``). For an increasing function with ``value_at(0) <= 0 <
    value_at(n_nodes - 1)`` the result satisfies ``value_at(k) <= 0 < value_at(k + 1)``;
    elsewhere (no sign change, NaN nodes) it is some cell, which the caller checks.
    """
    lo = np.zeros(shape, np.intp)
    hi = np.full(shape, n_nodes - 1, np.intp)
    for _ in range(int(np.ceil(np.log2(max(n_nodes - 1, 1))))):
        mid = (lo + hi) // 2
        neg = value_at(mid) <= 0.0
        lo = np.where(neg, mid, lo)
        hi = np.where(neg, hi, mid)
    return lo


def hermite_inverse(x0, x1, f0, f1, d0, d1):
    """Root estimate in ``[x0, x1]`` from the inverse cubic Hermite interpolant.

    ``x(f)`` is interpolated through ``(f0, x0)`` and ``(f1, x1)`` with slopes ``1/d0``,
    ``1/d1`` and evaluated at ``f = 0`` (``f0 <= 0 < f1``): third order in the cell
    width where the slopes are positive; the secant where they are not, or where the
    estimate leaves the cell.
    """
    df = f1 - f0
    s = -f0 / df
    with np.errstate(divide="ignore", invalid="ignore"):
        x = ((2.0 * s - 3.0) * s * s + 1.0) * x0 + (3.0 - 2.0 * s) * s * s * x1 \
            + s * (s - 1.0) * df * ((s - 1.0) / d0 + s / d1)
    good = (d0 > 0.0) & (d1 > 0.0) & np.isfinite(x) & (x >= x0) & (x <= x1)
    return np.where(good, x, x0 + s * (x1 - x0))


def bracketed_newton(fun, x, lo, hi, rtol, atol, maxiter=8):
    """Newton iteration inside a bracket, on the elements that have not converged.

    Parameters
    ----------
    fun : callable
        ``fun(x, idx) -> (f, df, extras)`` for the elements ``idx`` (flat indices) at
        ``x``; ``f`` increasing in ``x``, ``extras`` a tuple of arrays like ``x``.
    x, lo, hi : ndarray
        Start and bracket (``f(lo) <= 0 <= f(hi)``), 1-D.
    rtol, atol : float
        An element is done when its next Newton step is at most ``rtol |x| + atol``
        (quadratic convergence: the evaluated ``x`` is then within about that of the
        root), when ``f == 0``, or when its bracket is that narrow.

    Returns
    -------
    x, extras, done
        Where ``done``: the last evaluated point of each element and the extras
        evaluated there. ``done`` is False where ``maxiter`` evaluations did not
        converge or ``f`` was not finite (the side of the root unknown); the caller
        falls back there.
    """
    x, lo, hi = (np.array(a, float, copy=True) for a in (x, lo, hi))
    done = np.zeros(x.shape, bool)
    extras = None
    act = np.arange(x.size)
    for _ in range(maxiter):
        f, df, ex = fun(x[act], act)
        if extras is None:
            extras = tuple(np.full(x.shape, np.nan) for _ in ex)
        for store, e in zip(extras, ex, strict=True):
            store[act] = e
        xa = x[act]
        neg = f < 0.0
        lo[act] = np.where(neg, xa, lo[act])
        hi[act] = np.where(neg | np.isnan(f), hi[act], xa)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = -f / df
        tol = rtol * np.abs(xa) + atol
        newton = np.isfinite(step) & (xa + step >= lo[act]) & (xa + step <= hi[act])
        fin = (newton & (np.abs(step) <= tol)) | (f == 0.0) | (hi[act] - lo[act] <= tol)
        lost = ~np.isfinite(f)  # the side of the root is unknown: left to the caller
        fin &= ~lost
        done[act] = fin
        x[act] = np.where(fin, xa, np.where(newton, xa + step, 0.5 * (lo[act] + hi[act])))
        act = act[~(fin | lost)]
        if act.size == 0:
            break
    return x, extras, done
