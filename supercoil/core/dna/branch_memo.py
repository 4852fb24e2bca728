"""C-free tables of the plectoneme branch, kept across the calls of one fit. Float-only.

The plectoneme equilibrium at a tension T (torque ``M_p(T)``, torsion ``tau(T)``) does
not depend on the twist rigidity C ((GE2) contains no C), nor does the free-energy
model's effective pull ``T_eff`` (its Newton equation has no C). A fit that varies C
and the offsets therefore asks, call after call, for the same C-free quantities: the
pull at each force and the branch ``(M_p, tau)`` over the tensions its fully coiled
points reach. A caller that owns a ``memo`` (a dict, one per molecule's C-free
parameters: the fit's per-interaction memo) lets the free-energy kernel keep them:

* :func:`remember`: any C-free result under a key (the pull per force);
* :class:`BranchTable`: ``M_p`` and ``tau`` on ``u = log T`` in ``[u_lo, u_hi]`` as
  cubic Hermite pieces (values and slopes from one converged Chebyshev series of each,
  :mod:`supercoil.core.dna.coiled_table`), built once; for any C the fully coiled
  point ``l_p(u) = M_p/C + tau = x`` is then a piece lookup and Newton on one cubic
  (:func:`solve`), no equilibrium call. The table is rebuilt wider when a call's
  largest linking lies beyond it.

Accuracy: the series are accepted at :data:`~supercoil.core.dna.coiled_table.TAIL_RTOL`
(trailing coefficients relative to the largest value, or to the equilibrium's rounding
noise); the Hermite pieces at every piece's midpoint within :data:`HERMITE_RTOL` of the
series (measured, ``BranchTable.error``). Tested against the direct solve at 1e-8
relative in extension and torque (tests/dna/test_branch_memo.py).
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np
from numpy.polynomial import chebyshev as _ch

from supercoil.core.dna import coiled_table as _table
from supercoil.core.numerics import chebval_rows, stacked
from supercoil.exceptions import NoEquilibriumError, ValidityError

__all__ = ["GROWTH", "HERMITE_RTOL", "REMEMBERED", "START_DEGREE", "BranchTable", "build",
           "covers", "remember", "solve", "table_for"]

#: Hermite pieces accepted once their midpoint values of M_p and tau are within this
#: (relative to the largest |M_p|, |tau|) of the Chebyshev series
HERMITE_RTOL = 1e-13
#: the domain built: this factor times the width in log T that the request needs
GROWTH = 1.25
#: first degree of the series (33 nodes in one equilibrium call: a fit's branch has needed
#: 32-64 on the bench problems, which from degree 8 takes three or four calls; the per-call
#: table starts lower, for the hard-core equilibrium's scalar path on few tensions)
START_DEGREE = 32
#: results kept by :func:`remember` per memo
REMEMBERED = 16
_START_PIECES = 128
_MAX_PIECES = 1 << 14
_NEWTON_MAXITER = 8


def remember(memo, key, compute):
    """``compute()``, kept in ``memo`` under ``key`` (no memo: computed each time).

    At most :data:`REMEMBERED` results are kept (the oldest is dropped): a fit that
    varies the force scale asks for new forces at every evaluation.
    """
    if memo is None:
        return compute()
    store = memo.setdefault("remembered", {})
    hit = store.get(key)
    if hit is None:
        hit = store[key] = compute()
        if len(store) > REMEMBERED:
            del store[next(iter(store))]
    return hit


class BranchTable(NamedTuple):
    """``M_p(u)`` and ``tau(u)`` on ``u = log T`` as cubic Hermite pieces (C-free).

    ``u`` lies in piece ``j = floor((u - u_lo) scale)`` at position ``s`` in [0, 1];
    ``torque`` and ``torsion`` hold per piece the coefficients of ``s^0..s^3``;
    ``torque_nodes`` and ``torsion_nodes`` the values at the ``pieces + 1`` nodes.
    """

    u_lo: float  # log T (N) at the first node
    u_hi: float  # log T at the last node
    scale: float  # pieces per unit of u
    torque: np.ndarray  # (4, pieces), N m
    torsion: np.ndarray  # (4, pieces), 1/m
    torque_nodes: np.ndarray  # (pieces + 1,), N m
    torsion_nodes: np.ndarray  # (pieces + 1,), 1/m
    error: float  # largest midpoint difference from the series (relative)
    rising: bool  # M_p and tau both rise on the nodes: l_p rises for every C > 0


def _series(u_lo, u_hi, equilibrium):
    """Chebyshev coefficients of ``M_p`` and ``tau`` in t on [u_lo, u_hi], or None.

    Lobatto nodes doubled (nested) from :data:`START_DEGREE` until the
    last two coefficients of each are below ``TAIL_RTOL`` times its largest node value
    (or the equilibrium's noise); None beyond ``MAX_DEGREE``, where a doubling from
    degree 32 on shrinks them by less than 20 times (a kink: contact), or where
    ``M_p`` does not rise with T.
    """
    half = 0.5 * (u_hi - u_lo)

    def nodes(t):
        st = equilibrium(np.exp(u_lo + half * (t + 1.0)))
        return np.asarray(st.torque, float), np.asarray(st.torsion, float)

    degree = START_DEGREE
    M, tau = nodes(_table.lobatto(degree))
    err_prev = np.inf
    while True:
        if not np.all(np.diff(M) < 0.0):  # nodes descend in t: M_p rises with T
            return None
        cM, ct = _table.coefficients(M), _table.coefficients(tau)
        err = max(max(abs(c[-1]), abs(c[-2])) / max(_table.TAIL_RTOL * np.max(np.abs(v)),
                                                     _table.NOISE * np.max(np.abs(v)))
                  for c, v in ((cM, M), (ct, tau)))
        if err <= 1.0:
            return cM, ct
        if degree >= _table.MAX_DEGREE or (degree >= 32 and err > 0.05 * err_prev):
            return None
        err_prev = err
        degree *= 2
        M_new, tau_new = nodes(_table.lobatto(degree)[1::2])
        M, tau = _table.interleave(M, M_new), _table.interleave(tau, tau_new)


def build(u_lo, u_hi, equilibrium):
    """The :class:`BranchTable` of the branch on ``[u_lo, u_hi]``, or None (not resolved).

    The pieces double from 128 until every midpoint agrees with the series to
    :data:`HERMITE_RTOL` (the error falls as pieces^-4) and every piece's cubic bends
    little (``|p''/p'| <= 0.1``, which :func:`solve`'s stopping rule assumes); None
    beyond 16384 pieces.
    """
    series = _series(u_lo, u_hi, equilibrium)
    if series is None:
        return None
    cM, ct = series
    dcM, dct = _ch.chebder(cM), _ch.chebder(ct)
    half = 0.5 * (u_hi - u_lo)
    pieces = _START_PIECES
    while pieces <= _MAX_PIECES:
        t = np.linspace(-1.0, 1.0, 2 * pieces + 1)
        h = 2.0 / pieces  # piece width in t: slopes per unit s are h dv/dt
        rows, err = [], 0.0
        values = chebval_rows(t, stacked(cM, dcM, ct, dct))
        for v, dv in (values[:2], values[2:]):
            r = _table.hermite(v[0::2], dv[0::2], h)
            mid = r[0] + 0.5 * (r[1] + 0.5 * (r[2] + 0.5 * r[3]))
            err = max(err, np.max(np.abs(mid - v[1::2])) / np.max(np.abs(v)))
            rows.append((r, v[0::2].copy()))
        # the Newton of solve() stops on the quadratic-convergence bound |p''/p'| < 0.1
        bend = max(np.max((2.0 * np.abs(r[2]) + 6.0 * np.abs(r[3])) / np.abs(r[1]))
                   for r, _ in rows)
        if err <= HERMITE_RTOL and bend <= 0.1:
            (rM, nM), (rt, nt) = rows
            rising = bool(np.all(np.diff(nM) > 0.0) and np.all(np.diff(nt) > 0.0))
            return BranchTable(float(u_lo), float(u_hi), pieces / (2.0 * half), rM, rt, nM,
                               nt, float(err), rising)
        pieces *= 2 ** max(1, int(np.ceil(np.log2(1.25 * (err / HERMITE_RTOL) ** 0.25))),
                           int(np.ceil(np.log2(bend / 0.1))))
    return None


def covers(table, x_top, C):
    """True if the table's last node holds at least the linking ``x_top`` (rad/m) at C."""
    return table.torque_nodes[-1] / C + table.torsion_nodes[-1] >= x_top


def solve(table, x, C):
    """Fully coiled ``(M, T)`` with ``M_p(T)/C + tau(T) = x`` from the table, or None.

    None where ``l_p`` is not increasing on the nodes at this C, a linking lies outside
    the table, or Newton on the piece does not settle.
    """
    x = np.asarray(x, float)
    ln = table.torque_nodes / C
    ln += table.torsion_nodes
    span = ln[-1] - ln[0]
    if not (x.max() <= ln[-1] and x.min() >= ln[0] - 1e-9 * span
            and (table.rising or np.all(ln[1:] > ln[:-1]))):
        return None
    # array methods and in-place ufuncs throughout: a few hundred points, where numpy's
    # per-call overhead, not the arithmetic, is the cost
    j = ln.searchsorted(x)
    j -= 1
    np.maximum(j, 0, out=j)
    np.minimum(j, ln.size - 2, out=j)
    rM = table.torque.take(j, axis=1)  # (4, points)
    c = table.torsion.take(j, axis=1)
    c += rM / C
    c0, c1, c2, c3 = c
    d2, d3 = 2.0 * c2, 3.0 * c3
    lo = ln.take(j)
    s = x - lo
    s /= ln.take(j + 1) - lo
    c0 -= x
    for _ in range(_NEWTON_MAXITER):
        step = c3 * s
        step += c2
        step *= s
        step += c1
        step *= s
        step += c0
        den = d3 * s
        den += d2
        den *= s
        den += c1
        step /= den
        s -= step
        # quadratic convergence: after a step of 1e-6 the error in s is below
        # |p''/(2 p')| 1e-12, p the cubic of a piece (|p''/p'| < 0.1 on the pieces of
        # HERMITE_RTOL): under 1e-13 of a piece, 1e-16 in log T
        np.abs(step, out=step)
        if step.max() <= 1e-6:
            break
    else:
        return None
    M = rM[3] * s
    for k in (2, 1, 0):
        M += rM[k]
        if k:
            M *= s
    s += j
    s /= table.scale
    s += table.u_lo
    return M, np.exp(s, out=s)


def table_for(memo, u_lo, x_top, C, equilibrium, upper_tension):
    """The memo's :class:`BranchTable` from ``u_lo`` or below covering ``x_top`` at C, or None.

    One table per memo. ``upper_tension()`` -> a tension above the root of ``x_top``:
    called only where the table does not reach ``x_top``, which is then built on
    ``GROWTH`` times the width needed (at least 1.5 times the width of the table it
    replaces); where only its lower end lies above ``u_lo`` (a smaller pull: a fitted
    force scale), it is rebuilt from ``u_lo`` to its upper end. A branch the table
    does not resolve, or with a node beyond the interaction's range, is remembered
    (False): every later request returns None (the caller's solvers raise where the
    points themselves lie beyond it). The nodes' warnings are dropped; where there
    were any, the state at ``x_top`` is solved once, so that its own warnings are
    issued as the caller's solvers would.
    """
    table = memo.get("coiled branch")
    if table is False:
        return None
    reaches = table is not None and covers(table, x_top, C)
    if reaches and table.u_lo <= u_lo:
        return table
    lo = u_lo if table is None else min(u_lo, table.u_lo)
    if reaches:
        width = table.u_hi - lo
    else:
        width = GROWTH * (np.log(upper_tension()) - lo)
        if table is not None:
            width = max(width, 1.5 * (table.u_hi - lo))
    with warnings.catch_warnings(record=True) as caught:  # a node's state is no result
        warnings.simplefilter("always")
        try:
            new = build(lo, lo + width, equilibrium)
        except (NoEquilibriumError, ValidityError):  # a node beyond the interaction's range
            new = None
    if new is None or not covers(new, x_top, C):
        memo["coiled branch"] = False  # the caller's own solvers from now on
        return None
    memo["coiled branch"] = new
    top = solve(new, np.array([x_top]), C) if caught else None
    if top is not None:  # the warnings the largest point's own state gives, as without it
        equilibrium(top[1])
    return new
