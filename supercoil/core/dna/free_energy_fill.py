"""One-force blocks of the free-energy hat curve, filled in place. Float-only kernel.

:func:`supercoil.core.dna.free_energy.hat_points` hands each block of points at one
force (every block of a one-force call, every block but the seams of a force-major
table) and without the end loop to :func:`fill`. Its points are classified by the
operations of the general path (:func:`supercoil.core.dna.free_energy._assemble`); where
each phase's points are contiguous (turns in order: a hat curve, a table) the block is
a few runs of one phase each, and every run is filled by its phase's formulas alone,
with the force's constants as scalars, into the result's slices and a workspace that
each thread keeps between calls (:class:`Work`). The operations are those of the general path,
in the same order, so the points are bit-identical (tested); where a phase is not
contiguous :func:`fill` returns False and the general path fills the block.

Measured (1.2 pN, seed set, hard-core, blocks of 32768 points): the general path's
temporaries of the block's size are fresh memory for every operation (the allocator
returns freed blocks of this size to the system), so that a page fault per 512 points
costs more than the arithmetic: with fresh temporaries the fully coiled table lookup
cost 3 times as much CPU as with reused ones, the stretched tail's Newton 2.5 times, its
free energy 6 times. Each phase's formulas on its own run, instead of the plectoneme's
constants on every point overwritten where the phase differs, also drop the gathers and
scatters of the selections.
"""

from __future__ import annotations

import math
import threading

import numpy as np

from supercoil.core.dna import coiled_points as _points
from supercoil.core.dna import coiled_table as _table
from supercoil.core.dna import free_energy_tail as _tail
from supercoil.core.dna import moroz_nelson as _mn
from supercoil.core.dna.interface import FULLY_COILED, PLECTONEME, STRETCHED

__all__ = ["Work", "borrow", "fill", "fill_blocks", "first_coiled", "give_back", "one_force",
           "runs"]

_TWO_PI = 2.0 * np.pi
_TAIL_MAXITER = 60


class Work:
    """Workspace: float, complex, bool and index buffers of ``size`` points, reused block by block.

    One per thread is kept between calls (:func:`borrow`): a workspace allocated per
    call is fresh memory each time (the allocator returns it to the system when the
    call frees it), and its first use costs a page fault per 512 points (measured at
    2e5 points, 1.2 pN, to 40 turns: a third of the page faults of a call and a sixth of
    its CPU time). It holds about 3 MB.
    """

    def __init__(self, size):
        self.f = [np.empty(size) for _ in range(7)]
        self.b = [np.empty(size, bool) for _ in range(2)]
        self.j = np.empty(size, np.intp)
        self.c = [np.empty(size, complex) for _ in range(2)]


_KEPT = threading.local()


def borrow(size):
    """This thread's kept :class:`Work` if it holds ``size`` points, else a new one; hand
    it back with :func:`give_back` (a nested call meanwhile allocates its own)."""
    work = getattr(_KEPT, "work", None)
    _KEPT.work = None
    if work is None or work.j.size < size:
        work = Work(size)
    return work


def give_back(work):
    """Keep ``work`` for this thread's next call (the larger of it and the one kept)."""
    kept = getattr(_KEPT, "work", None)
    if kept is None or kept.j.size < work.j.size:
        _KEPT.work = work


def fill_blocks(t_all, f_all, uf, one, co, loop, length, B, C, kT, equilibrium, thermal,
                short_tail_length, trial_equilibrium, branch, block, assemble):
    """The points of :func:`supercoil.core.dna.free_energy.hat_points`, block by block.

    A one-force block without the end loop run by run (:func:`fill`); the others, and
    those whose phases are not contiguous, by the general path ``assemble``
    (``supercoil.core.dna.free_energy._assemble``, its signature).
    """
    from supercoil.core.dna.free_energy import FreeEnergyPoints

    size = t_all.size
    out = FreeEnergyPoints(*(np.empty(size, t) for t in (float,) * 3 + (np.int8, bool)
                             + (float,) * 2))
    work = borrow(block) if loop is None else None
    for lo in range(0, size, block):  # each block writes its slice of the result (no copies)
        sl = slice(lo, lo + block)
        t, f = t_all[sl], f_all[sl]
        part = FreeEnergyPoints(*(a[sl] for a in out))
        i = 0 if one else one_force(uf, f)
        if work is not None and i is not None and fill(
                t, f, i, co, length, B, C, kT, thermal, short_tail_length, equilibrium,
                trial_equilibrium, branch, one, part, work):
            continue
        assemble(np.abs(t), t, f, None if one else np.searchsorted(uf, f), co, loop, length,
                 B, C, kT, equilibrium, thermal, short_tail_length, trial_equilibrium,
                 branch, part)
    if work is not None:  # not on an exception: the next call allocates its own
        give_back(work)
    return out


def one_force(uf, f):
    """The index in ``uf`` of the block's one force, or None (several forces)."""
    lo = f.min()
    if lo != f.max():
        return None
    return int(np.searchsorted(uf, lo))


def runs(mask):
    """The True points of ``mask`` as a list of at most two slices, or False.

    ``[]``: no point; one slice: contiguous; two: a run at each end (a one-force call of
    one block, turns from -N to N: its fully coiled points); False: any other pattern.
    Counts and searches, no index array.
    """
    count = int(np.count_nonzero(mask))
    size = mask.size
    if count == 0:
        return []
    first = int(mask.argmax())
    if mask[first:first + count].all():
        return [slice(first, first + count)]
    if mask[0] and mask[-1]:
        a, b = int(mask.argmin()), size - int(mask[::-1].argmin())
        if a + size - b == count:
            return [slice(0, a), slice(b, size)]
    return False


def fill(turns, force, i, co, length, B, C, kT, thermal, short_tail_length, equilibrium,
         trial_equilibrium, branch, one, out, work):
    """The points of one block at the force ``co.force[i]`` (no end loop) into ``out``.

    ``out``: :class:`~supercoil.core.dna.free_energy.FreeEnergyPoints` of the block's
    slices of the result; ``one``: the call has this force only (the fully coiled solve's
    force index). Returns False, with ``out`` partly written, where the stretched or the
    fully coiled points are not contiguous (the general path then fills the block).
    """
    size = turns.size
    n = np.abs(turns, out=work.f[0][:size])
    Nb = co.buckling_turns[i]
    per_turn = _TWO_PI / co.linking_rate[i]  # S = (|N| - N_b) 2 pi / D, the general path's
    S = out.plectoneme_length  # (its max(., 0) and min(., L): the stretched runs' 0 and the
    top = first_coiled(Nb, per_turn, length)  # fully coiled runs' L, filled there)
    if top is None:  # S on every point, its test as the general path's
        np.subtract(n, Nb, out=S)
        S *= per_turn
        coiled = runs(np.greater_equal(S, length, out=work.b[1][:size]))
    else:  # the same test on |N| (S is monotone in |N|): S on the plectoneme runs only
        coiled = runs(np.greater_equal(n, top, out=work.b[1][:size]))
    stretched = runs(np.less_equal(n, Nb, out=work.b[0][:size]))
    if stretched is False or coiled is False or len(stretched) > 1:
        return False
    start = 0
    for r in [*sorted(stretched + coiled, key=lambda r: r.start), slice(size, size)]:
        if r.start > start:
            sl = slice(start, r.start)
            if top is not None:
                np.subtract(n[sl], Nb, out=S[sl])
                S[sl] *= per_turn
            _plectoneme(sl, n, turns, i, co, length, short_tail_length, out, work)
        start = r.stop
    if stretched:
        _stretched(stretched[0], n, turns, force[0], length, B, C, kT, thermal,
                   short_tail_length, out, work)
    if coiled:
        _coiled(coiled, n, turns, i, co, length, B, C, short_tail_length, equilibrium,
                trial_equilibrium, branch, one, out, work)
    return True


def first_coiled(Nb, per_turn, length):
    """The smallest float ``|N|`` whose plectoneme length ``fl(fl(|N| - N_b) per_turn)``
    reaches ``length`` (the fully coiled test of the general path, exactly), or None.

    The test is monotone in ``|N|`` (each rounded operation is), so it is one threshold:
    found from ``N_b + L / per_turn`` in a few steps of one ulp (Python floats round as
    numpy's float64 operations do). A block is then classified on ``|N|`` alone and S is
    computed on its plectoneme points only (two array passes fewer on the rest).
    """
    n = float(Nb + length / per_turn)
    Nb, per_turn = float(Nb), float(per_turn)
    for _ in range(64):
        if (n - Nb) * per_turn >= length:
            below = math.nextafter(n, -math.inf)
            if not (below - Nb) * per_turn >= length:
                return n
            n = below
        else:
            n = math.nextafter(n, math.inf)
    return None  # pragma: no cover - rounding moves the threshold by a few ulp


def _products(G, n, M, length, tmp):
    """``G = L g + (2 pi |N|) |M|`` in place of ``g`` (the general path's order)."""
    G *= length
    np.multiply(n, _TWO_PI, out=tmp)
    tmp *= M
    G += tmp


def _plectoneme(sl, n, turns, i, co, length, short_tail_length, out, work):
    """Plectoneme run: the coexistence torque, tail ``L - S``, ``G = L g* + 2 pi |N| M*``."""
    m = sl.stop - sl.start
    tail = work.f[1][:m]
    np.subtract(length, out.plectoneme_length[sl], out=tail)
    zinf, Mp = co.long_tail_factor[i], co.torque[i]
    np.multiply(tail, zinf, out=out.extension[sl])
    out.zeta[sl].fill(zinf)
    G = out.free_energy[sl]
    np.multiply(n[sl], _TWO_PI, out=G)
    G *= Mp
    G += co.free_energy_density[i] * length
    out.phase[sl].fill(PLECTONEME)
    np.copysign(Mp, turns[sl], out=out.torque[sl])
    np.less(tail, short_tail_length, out=out.short_tail[sl])


def _stretched(sl, n, turns, force, length, B, C, kT, thermal, short_tail_length, out, work):
    """Stretched run: the tail torque of the linking, ``g_s``, zeta, tail L."""
    m = sl.stop - sl.start
    nv, M, g, zeta = n[sl], out.torque[sl], out.free_energy[sl], out.zeta[sl]
    x, t1, t2, t3, t4 = (a[:m] for a in work.f[1:6])
    if thermal:
        np.multiply(nv, _TWO_PI, out=x)
        x /= length
        tail_torque(x, force, B, C, kT, M, (t1, t2, t3, t4))
        _tail_free_energy(force, M, B, C, kT, g, zeta, t1)
    else:  # the li-zhao expression: C_eff (2 pi / L) n with C_eff = C / 1.0
        np.multiply(nv, C / 1.0 * (_TWO_PI / length), out=M)
        np.multiply(M, M, out=t1)
        t1 /= 2.0 * C
        np.subtract(-force, t1, out=g)
        zeta.fill(1.0)
    np.multiply(zeta, length, out=out.extension[sl])
    _products(g, nv, M, length, t1)
    out.plectoneme_length[sl].fill(0.0)
    out.phase[sl].fill(STRETCHED)
    np.copysign(M, turns[sl], out=M)
    out.short_tail[sl].fill(length < short_tail_length)


def tail_torque(x, force, B, C, kT, out, work):
    """:func:`supercoil.core.dna.free_energy_tail.tail_torque` at one force, in place.

    The same Newton (same start, operations and stopping rule, bit for bit) in the
    buffers ``work`` (four of x's size); the torque into ``out``.
    """
    Q0 = B * force / (kT * kT) - 1.0 / 32.0
    if not Q0 > 0.0:
        _mn.check_bracket(Q0, force, 0.0, what="Moroz-Nelson tail free energy")
    r0 = np.sqrt(Q0)
    MQ = 2.0 * kT * r0
    a = 1.0 / C
    b = 1.0 / (4.0 * B * r0)
    v = out  # v = M / M_Q, scaled at the end
    w2, g, dv, y = work
    np.divide(x, MQ, out=y)
    np.divide(y, a + b, out=v)
    np.minimum(v, 1.0 - 2.0**-30, out=v)
    for _ in range(_TAIL_MAXITER):
        np.subtract(1.0, v, out=w2)
        np.add(1.0, v, out=g)
        w2 *= g  # w^2 = (1 - v)(1 + v)
        np.sqrt(w2, out=dv)
        np.divide(b, dv, out=dv)  # q = b / w
        np.add(dv, a, out=g)
        g *= v
        g -= y  # g = (q + a) v - y
        dv /= w2
        dv += a  # g' = q / w^2 + a
        np.divide(g, dv, out=dv)
        v -= dv
        if _tail.tail_settled(dv.max(), dv.min(), w2.min(), a, b, b):
            v *= MQ
            return v
    return _tail.tail_torque(x, force, B, C, kT)  # names the point (ValidityError)


def _tail_free_energy(force, M, B, C, kT, g, zeta, tmp):
    """``g_s`` and ``zeta_inf`` into g and zeta: the operations of
    :func:`supercoil.core.dna.free_energy_tail.tail_free_energy` (thermal)."""
    Q = zeta
    np.divide(M, kT, out=tmp)
    np.multiply(tmp, 0.25, out=Q)
    Q *= tmp
    np.subtract(B * force / (kT * kT), Q, out=Q)
    Q -= 1.0 / 32.0
    if not Q.min() > 0.0:
        _tail.tail_free_energy(force, M, B, C, kT)  # raises, naming force and torque
    r = np.sqrt(Q, out=Q)
    np.multiply(r, kT * kT / B, out=g)
    g += -force
    np.multiply(M, M, out=tmp)
    tmp /= 2.0 * C
    g -= tmp
    np.divide(0.5, r, out=zeta)
    np.subtract(1.0, zeta, out=zeta)


def _coiled(parts, n, turns, i, co, length, B, C, short_tail_length, equilibrium,
            trial_equilibrium, branch, one, out, work):
    """Fully coiled runs ``parts`` (solved together): the branch state, S = L, no tail."""
    sizes = [r.stop - r.start for r in parts]
    m = sum(sizes)
    x, T, z, tmp, c, Mb = (a[:m] for a in work.f[1:7])
    if len(parts) == 1:
        Mb, nv = out.torque[parts[0]], n[parts[0]]
    else:
        nv = np.concatenate([n[r] for r in parts])
    np.multiply(nv, _TWO_PI, out=x)
    x /= length
    got = False
    if isinstance(branch, _table.Inverse):
        x_lo, x_hi = branch.x_lo, branch.x_hi
        if x.max() <= x_hi and x.min() >= x_lo - 1e-9 * (x_hi - x_lo):
            _table.evaluate_inverse(branch, x, (Mb, T),
                                    (z, work.j[:m], c, *(a[:m] for a in work.c)))
            got = True
            if trial_equilibrium is not None:
                _points.record_extremes(equilibrium, T)
    if not got:
        inv = None if one else np.full(m, i, np.intp)
        Mc, Tc = _points.solve(nv, inv, slice(None), co, None, length, B, C, equilibrium,
                               trial_equilibrium, branch)
        Mb[...], T[...] = Mc, Tc
    at = 0
    for r, k in zip(parts, sizes, strict=True):
        M, g, Tr, t = out.torque[r], out.free_energy[r], T[at:at + k], tmp[at:at + k]
        if len(parts) > 1:
            M[...] = Mb[at:at + k]
        at += k
        np.multiply(M, M, out=t)
        t /= 2.0 * C
        np.negative(Tr, out=g)
        g -= t  # g = -T - M^2/(2C)
        _products(g, n[r], M, length, t)
        out.zeta[r].fill(0.0)
        out.extension[r].fill(0.0)
        out.plectoneme_length[r].fill(length)
        out.phase[r].fill(FULLY_COILED)
        np.copysign(M, turns[r], out=M)
        out.short_tail[r].fill(0.0 < short_tail_length)
