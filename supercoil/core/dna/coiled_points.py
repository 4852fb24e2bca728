"""The fully coiled points of one free-energy hat-curve call. Float-only.

:func:`supercoil.core.dna.free_energy.hat_points` classifies its points in blocks;
the fully coiled ones need the plectoneme state whose linking per length matches the
turns (:mod:`supercoil.core.dna.coiled_table`). :func:`call_branch` builds, once per
call, one inverse ``x -> (M, T)`` of the branch that covers every fully coiled point
of every block and force (a table per block would repeat the bracket and the table);
:func:`solve` evaluates it for a block's points, or solves them by the secant where
the call has few such points or the inverse does not resolve the branch.
"""

from __future__ import annotations

import warnings
from typing import NamedTuple

import numpy as np

from supercoil.core.dna import branch_memo as _memo
from supercoil.core.dna import coiled_table as _table
from supercoil.core.dna import end_loop as _loop
from supercoil.exceptions import NoEquilibriumError, ValidityError

__all__ = ["Few", "call_branch", "coiled_turns", "record_extremes", "solve"]

_TWO_PI = 2.0 * np.pi


def coiled_turns(co, loop, length):
    """Per force: the turns from which a point is fully coiled (slightly below: rounding)."""
    if loop is None:
        top = co.buckling_turns + length * co.linking_rate / _TWO_PI
    else:  # S >= L - l with S of _assemble's looped branch, and past the jump
        top = np.maximum(loop.linking + (length - loop.length)
                         * (co.tail_linking + co.linking_rate) / _TWO_PI, loop.jump_turns)
    return top * (1.0 - 1e-12)


def _start(ci, co, loop, length, B, C):
    """``(x(n), l_p at T_eff, loop)``: the fully coiled problem at the force indices ci."""
    if loop is None:
        return (lambda n: _TWO_PI * n / length), co.torque[ci] / C + co.torsion[ci], None
    start = co.torque[ci] / C + co.torsion[ci] * (1.0 - loop.length[ci] / length)
    return (lambda n: _TWO_PI * (n - _loop.LOOP_WRITHE) / length), start, (B, length)


class _AtC(NamedTuple):
    """A memo's C-free :class:`~supercoil.core.dna.branch_memo.BranchTable` at one C."""

    table: _memo.BranchTable
    C: float


def call_branch(turns, force, uf, co, loop, length, B, C, equilibrium, block, memo=None,
                extremes=None):
    """One table of the fully coiled branch for all points of a call, or None.

    A pass over the points (in blocks, no per-point temporaries kept) finds the fully
    coiled ones: fewer than :data:`~supercoil.core.dna.coiled_table.MIN_POINTS`, None
    (the secant per point is cheaper). Else the secant brackets the largest linking
    from the smallest ``T_eff`` (raising, naming the turns, where the interaction
    has no plectoneme there) and :func:`~supercoil.core.dna.coiled_table.inverse_table`
    covers every point of every force (``l_p`` does not depend on the force); False
    where it does not resolve the branch (the secant then solves every block).

    With a caller's ``memo`` (no end loop): the memo's C-free table of the branch
    (:func:`supercoil.core.dna.branch_memo.table_for`) where it has or builds one, for
    any number of fully coiled points.

    One force, no loop and fewer than ``MIN_POINTS`` fully coiled points: their states,
    solved once for the call (:class:`Few`) instead of once in each block that has some.
    ``extremes``: the caller's ``(turns.min(), turns.max())``, if it has them.
    """
    thr = coiled_turns(co, loop, length)
    count, top = 0, -np.inf
    if uf.size == 1:
        lo, hi = extremes or (turns.min(), turns.max())
        top = max(hi, -lo)
        if top >= thr[0]:
            count = np.count_nonzero(turns >= thr[0]) + np.count_nonzero(turns <= -thr[0])
    else:
        for lo in range(0, turns.size, block):
            a = np.abs(turns[lo:lo + block])
            hit = a >= thr[np.searchsorted(uf, force[lo:lo + block])]
            if hit.any():
                count += np.count_nonzero(hit)
                top = max(top, a[hit].max())
    if count == 0 or (count < _table.MIN_POINTS and (memo is None or loop is not None)):
        if count and uf.size == 1 and loop is None:
            return _few(turns, thr[0], co, length, B, C, equilibrium)
        return None
    i = int(np.argmin(co.pull))
    x_of, start, ends = _start(np.array([i]), co, loop, length, B, C)
    x_top = x_of(top)

    def upper(rungs=LADDER):
        T = _ladder(x_top, co.pull[i], start[0], C, equilibrium, ends, rungs)
        if T is None and rungs is not LADDER:
            T = _ladder(x_top, co.pull[i], start[0], C, equilibrium, ends)
        if T is None:
            with _naming_turns(top, length):
                T = _table.secant(np.array([x_top]), co.pull[i:i + 1], start, C, equilibrium,
                                  ends, upper=_table.DOMAIN_OVERSHOOT)[1][0]
        return T

    if memo is not None and loop is None:
        table = _memo.table_for(memo, np.log(co.pull[i]), x_top, C, equilibrium,
                                lambda: upper(LADDER[:SHORT_LADDER]))
        if table is not None:
            return _AtC(table, C)
        if count < _table.MIN_POINTS:
            return None
    T_hi = upper()
    series = _table.branch_series((co.pull[i], T_hi), C, equilibrium, ends)
    if series is None:
        return False
    if count < _table.INVERSE_MIN_POINTS:
        return series
    return _table.inverse_of(series) or series


class Few(NamedTuple):
    """The fully coiled states of a call's few points (one force, no loop), by linking.

    Solved by the secant of :func:`solve` on the call's distinct ``|N|`` at once: each
    point's secant steps are its own (the equilibrium solves each tension by itself), so
    its state is the one a block's secant gives, bit for bit.
    """

    linking: np.ndarray  # x = 2 pi |N| / L, ascending, rad/m
    torque: np.ndarray  # N m
    tension: np.ndarray  # N


def _few(turns, thr, co, length, B, C, equilibrium):
    """:class:`Few` of the fully coiled points among ``turns`` (one force), or None where
    the secant fails (each block's secant then raises, naming its turns)."""
    n = np.abs(turns[(turns >= thr) | (turns <= -thr)])
    S = np.maximum(n - co.buckling_turns[0], 0.0) * (_TWO_PI / co.linking_rate[0])
    n = np.unique(n[S >= length])  # the test of the points' phase (free_energy._assemble)
    if n.size == 0:
        return None
    x = _TWO_PI * n / length
    ci = np.zeros(n.size, np.intp)
    try:
        M, T = _table.secant(x, co.pull[ci], _start(ci, co, None, length, B, C)[1], C,
                             equilibrium, None)
    except (NoEquilibriumError, ValidityError):
        return None
    return Few(x, M, T)


#: exponents e of the ladder ``T_eff (x / l_p(T_eff))^e`` probed in one equilibrium call
#: (measured root exponents 1.8-10.7, hard-core and screened, 0.3-5 pN, from 1.001 to 10
#: times full coiling); rungs above :data:`LADDER_MAX` times ``T_eff`` are not probed
LADDER = (1.6, 2.0, 2.5, 3.2, 4.0, 5.0, 6.5, 8.5, 11.0)
LADDER_MAX = 1e3
#: rungs probed first for a memo's table (its domain grows by itself): the high rungs'
#: tensions reach the strands' contact, where a screened state costs several times more
SHORT_LADDER = 6


def _ladder(x, T0, l0, C, equilibrium, loop, rungs=LADDER):
    """The lowest rung of ``rungs`` whose ``l_p`` reaches x (an upper end of the
    table's domain, above the root by at most the rung spacing), or None.

    One equilibrium call on up to nine tensions, about the cost of one (instead of the
    secant's 2-6 calls on one); the probes' warnings are dropped (no probe state is a
    result). None where no rung reaches x or the interaction fails on a rung (a probe
    beyond its range): the secant then brackets the root and raises the interaction's
    error where it applies.
    """
    x = float(np.ravel(x)[0])
    T = T0 * (x / l0) ** np.asarray(rungs)
    T = T[(T > T0) & (T <= LADDER_MAX * T0)]
    if T.size == 0:
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # a probe's state is no result: its warnings neither
        try:
            st = equilibrium(T)
            lp = _table.branch_linking(np.asarray(st.torque, float),
                                       np.asarray(st.torsion, float), T, C, loop)
        except (NoEquilibriumError, ValidityError):
            return None
    above = np.flatnonzero(np.isfinite(lp) & (lp >= x))
    if above.size == 0 or not np.all(np.diff(lp[:above[0] + 1]) > 0.0):
        return None
    return float(T[above[0]])


class _naming_turns:
    """Re-raise the fully coiled solvers' errors naming the turns and the length."""

    def __init__(self, top, length):
        self.top, self.length = top, length

    def __enter__(self):
        return self

    def __exit__(self, kind, e, tb):
        where = f"|N| up to {self.top:.6g} turns (L = {self.length * 1e9:.6g} nm)"
        if isinstance(e, NoEquilibriumError):
            raise NoEquilibriumError(f"no fully coiled plectoneme for {where}: {e}") from e
        if isinstance(e, ValidityError):
            raise ValidityError(f"fully coiled points with {where}: {e}") from e
        return False


def _domain(branch):
    """``(x_lo, x_hi)``: the linkings an :class:`Inverse` or a :class:`Series` covers."""
    if isinstance(branch, _table.Inverse):
        return branch.x_lo, branch.x_hi
    if isinstance(branch, _AtC):
        t = branch.table
        return (t.torque_nodes[0] / branch.C + t.torsion_nodes[0],
                t.torque_nodes[-1] / branch.C + t.torsion_nodes[-1])
    return branch.nodes[-1], branch.nodes[0]


def solve(n, inv, coiled, co, loop, length, B, C, equilibrium, trial_equilibrium,
          branch=None):
    """``(M, T)`` of the fully coiled points n, with or without loop.

    ``inv[coiled]`` is their force index (``inv`` None: all at the force ``co.force[0]``).

    From the call's inverse ``branch`` (:func:`call_branch`) where it covers the
    points, else by the secant per point (few points in the call: the table costs more;
    or a branch the table cannot resolve: it would be tried again in every block).
    """
    ends = None if loop is None else (B, length)
    x = _TWO_PI * (n if loop is None else n - _loop.LOOP_WRITHE) / length
    got = None
    if isinstance(branch, Few):
        j = np.minimum(np.searchsorted(branch.linking, x), branch.linking.size - 1)
        if np.array_equal(branch.linking[j], x):
            got = branch.torque[j], branch.tension[j]
    elif branch:
        x_lo, x_hi = _domain(branch)
        if x.max() <= x_hi and x.min() >= x_lo - 1e-9 * (x_hi - x_lo):
            if isinstance(branch, _AtC):
                got = _memo.solve(branch.table, x, branch.C)
            elif isinstance(branch, _table.Inverse):
                got = _table.evaluate_inverse(branch, x)
            else:
                got = _table.solve_series(branch, x)
    if got is not None:
        Mc, Tc = got
    else:  # few points in the call, or a branch the table cannot resolve
        ci = np.zeros(n.size, np.intp) if inv is None else inv[coiled]
        start = _start(ci, co, loop, length, B, C)[1]
        with _naming_turns(n.max(), length):
            Mc, Tc = _table.secant(x, co.pull[ci], start, C, trial_equilibrium or equilibrium,
                                   ends)
    if trial_equilibrium is not None:
        record_extremes(equilibrium, Tc)
    return Mc, Tc


def record_extremes(equilibrium, tension):
    """The fully coiled states at the smallest and largest of ``tension``, solved by the
    caller's recording ``equilibrium`` for its checks (the trials went to the unrecorded
    one); the points keep their own states.

    The shared check on these states (:func:`supercoil.dna.validity.plectoneme_messages`:
    the superhelix radius below the hard-core radius, named at the largest such tension)
    gives on the two the message it gives on every point, because the radius does not grow
    with the tension along the branch (measured for the shipped interactions, hard-core
    and screened, 1 mM-1 M and A = 10-200 nm: tests/dna/test_free_energy.py). Solving every
    point once more dominated the public hat curve past full coiling
    (docs/theory/free-energy.md#8-cost).
    """
    if tension.size:
        lo, hi = float(tension.min()), float(tension.max())
        equilibrium(np.array([lo, hi] if hi > lo else [lo]))
