"""The li-zhao hat-curve points in numpy, one block at a time (docs/theory/li-zhao.md#hat-curve).

:func:`fill_block` writes the points of one block of
:func:`supercoil.core.dna.li_zhao.hat_curve_points` into slices of its result: the
general per-point formulas, or, for a one-force block whose points are all in
one phase (decided on its extreme turns by the same floating-point
operations), the same operations with the phase's constants hoisted
(:func:`fill_stretched`, :func:`fill_plectoneme`, :func:`fill_coiled`):
bit-identical points, fewer passes. :func:`block_summary` gives the block's
reductions for the public checks. Float-only kernel.
"""

from __future__ import annotations

import numpy as np

from supercoil.core.dna import moroz_nelson as _mn
from supercoil.core.dna.interface import FULLY_COILED, PLECTONEME, STRETCHED

__all__ = ["UNIFORM", "block_summary", "fill_block", "fill_coiled", "fill_plectoneme",
           "fill_stretched", "one_phase"]



def block_summary(extension, torque, zeta, bracket, short_tail, turns_range, over=None,
                  q_lo=None, torque_range=None):
    """``PointSummary`` fields of one block (cache-resident reductions).

    ``turns_range``: the block's (min, max) turns (every filler has them). ``over``
    (zeta > 1 at a long tail), ``q_lo`` (the bracket's minimum) and ``torque_range``
    (min, max), if the caller already knows them.
    """
    e_lo, e_hi = extension.min(), extension.max()
    m_lo, m_hi = torque_range if torque_range is not None else (torque.min(), torque.max())
    finite = bool(np.isfinite(e_lo) and np.isfinite(e_hi) and np.isfinite(m_lo)
                  and np.isfinite(m_hi))
    if q_lo is None:
        q_lo = bracket.min() if bracket is not None else np.nan
    if over is None:
        over = bool(zeta.max() > 1.0) and bool(np.any((zeta > 1.0) & ~short_tail))
    return finite, e_lo, e_hi, m_lo, m_hi, q_lo, bool(over), *turns_range


def fill_block(turns, force, const, length, B, kT, thermal, short_tail_length, out, sl, zeta,
                bracket):
    """Hat-curve points of one block, written into the slices ``sl`` of ``out``.

    ``zeta`` and ``bracket`` (thermal; else None) are the block's arrays to fill:
    slices of the result, or reused buffers.

    Returns the block's summary (:func:`block_summary`).

    ``const``: per-force constants (scalars, or arrays of the block) ``N_b``,
    ``M_p``, ``2 pi / D``, ``C_eff 2 pi / L`` and ``B T / kT^2 - 1/32``. Each
    quantity is computed once, in place where possible (about 25 passes over the
    block, all cache-resident). Measured on a block of 32768 (numpy 2.4):
    ``np.maximum``/``np.minimum`` against a scalar cost about four times as much as
    against an array, hence the constant arrays; ``np.copysign`` costs as much as the
    scalar ``np.maximum``, and is skipped where the block has no negative turns.
    """
    Nb, Mp, k, c, s = const
    size = turns.shape[0]
    lo, hi = turns.min(), turns.max()  # NaN propagates into both, inf shows in one
    if not (np.isfinite(lo) and np.isfinite(hi)):
        raise ValueError("turns must be finite")
    n = turns if lo >= 0.0 else np.abs(turns)  # read only below
    kind = one_phase(lo, hi, const, length) if np.ndim(Nb) == 0 else None
    if kind is not None:
        done = UNIFORM[kind](n, turns, lo, hi, const, length, B, kT, thermal, short_tail_length,
                              out, sl, zeta, bracket)
        if done is not None:
            return done
    S = out.plectoneme_length[sl]
    np.subtract(n, Nb, out=S)
    np.maximum(S, np.zeros(size), out=S)
    np.multiply(S, k, out=S)  # S = 2 pi (|N| - N_b) / D in the plectoneme phase
    coiled = S >= length
    any_coiled = coiled.any()
    np.minimum(S, np.full(size, length), out=S)
    tail = np.subtract(length, S)
    phase = out.phase[sl]
    np.greater(n, Nb, out=phase.view(bool))  # 1 past buckling, 0 stretched
    phase += coiled.view(np.int8)  # fully coiled (S >= L) only past buckling: 2
    M = out.torque[sl]
    np.multiply(n, c, out=M)  # stretched tail C_eff 2 pi |N| / L, equal to M_p at N_b
    np.minimum(M, np.full(size, Mp) if np.ndim(Mp) == 0 else Mp, out=M)
    extension = out.extension[sl]
    if thermal:
        Q = _bracket(M, kT, s, bracket)
        q_lo = Q.min()
        if not q_lo > 0.0 and not np.all((Q > 0.0) | coiled):
            _mn.check_bracket(np.where(coiled, 1.0, Q), force, np.sign(turns) * M)
        _tail_zeta(Q, tail, B, kT, zeta, extension)
        if any_coiled:
            np.copyto(zeta, 0.0, where=coiled)
        np.multiply(zeta, tail, out=extension)
    else:
        zeta.fill(1.0)
        if any_coiled:
            np.copyto(zeta, 0.0, where=coiled)
        extension[:] = tail
    short = _signed_and_short(M, turns, lo, tail, short_tail_length, out.short_tail[sl])
    return block_summary(extension, M, zeta, Q if thermal else None, short, (lo, hi),
                          q_lo=q_lo if thermal else None)


def _signed_and_short(M, turns, lo, tail, short_tail_length, short):
    """The torque takes the sign of N (skipped without negative turns); the short-tail flags."""
    if lo < 0.0 or np.signbit(lo):
        np.copysign(M, turns, out=M)
    return np.less(tail, short_tail_length, out=short)


def _bracket(M, kT, s, out):
    """The Moroz-Nelson bracket ``Q = B T/kT^2 - 1/32 - (M / 2 kT)^2`` into ``out``."""
    np.multiply(M, 0.5 / kT, out=out)
    np.square(out, out=out)
    return np.subtract(s, out, out=out)


def _tail_zeta(Q, tail, B, kT, zeta, extension):
    """``zeta = 1 - Q^(-1/2)/2 + B kT / ((B T - M^2/4) l)`` into ``zeta``, per point.

    ``B T - M^2/4 = kT^2 (Q + 1/32)``; ``tail`` is l (an array, or the scalar L);
    ``extension`` is the buffer of the finite-length term.
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        np.add(Q, 1.0 / 32.0, out=extension)
        extension *= tail
        np.divide(B / kT, extension, out=extension)
        np.sqrt(Q, out=zeta)
        np.divide(-0.5, zeta, out=zeta)
        zeta += 1.0
        zeta += extension
    return zeta


def one_phase(lo, hi, const, length):
    """The phase of every point of a one-force block with turns in ``[lo, hi]``, or None.

    Decided on the extreme points by the same floating-point operations as the
    per-point formulas of :func:`fill_block` (each monotone in |N|), so that a
    uniform block's points are those the general path would give.
    """
    Nb, Mp, k, c, _ = const
    n_lo = 0.0 if lo <= 0.0 <= hi else min(abs(lo), abs(hi))
    n_hi = max(abs(lo), abs(hi))
    if n_hi <= Nb and n_hi * c <= Mp:
        return STRETCHED  # S = 0, the tail torque C_eff 2 pi |N| / L below M_p
    if n_lo > Nb and n_lo * c >= Mp:  # past buckling, the torque at M_p
        if max(n_hi - Nb, 0.0) * k < length:
            return PLECTONEME  # none fully coiled
        if max(n_lo - Nb, 0.0) * k >= length:
            return FULLY_COILED
    return None


def fill_plectoneme(n, turns, lo, hi, const, length, B, kT, thermal, short_tail_length, out, sl,
                     zeta, bracket):
    """:func:`fill_block` for a block entirely in the plectoneme phase (one force).

    The torque is M_p at every point, so the bracket Q and the long-tail factor
    ``1 - Q^(-1/2)/2`` are one number each and only the tail length varies: 11
    passes instead of about 30, no square root per point (at 1e6 points of a hat
    curve to 25 turns at 1.2 pN, 68 % of them plectoneme, the kernel's time falls by
    40 % with the stretched and fully coiled fillers). The
    operations are those of the general path, so the points are bit-identical
    (tested). None if the bracket is not positive (the general path names it).
    """
    Nb, Mp, k, _, s = const
    S = out.plectoneme_length[sl]
    np.subtract(n, Nb, out=S)  # positive: no max(., 0)
    np.multiply(S, k, out=S)  # below L: no min(., L)
    tail = np.subtract(length, S)
    out.phase[sl].fill(PLECTONEME)
    M = out.torque[sl]
    M.fill(Mp)
    extension = out.extension[sl]
    q_lo = None
    over = False
    if thermal:
        q = Mp * (0.5 / kT)
        q_lo = s - q * q
        if not q_lo > 0.0:
            return None
        if out.bracket is not None:  # kept (diagnostics): else a buffer no one reads
            bracket.fill(q_lo)
        # zeta = 1 - Q^(-1/2)/2 + B kT / ((Q + 1/32) kT^2 l): one number plus a term in l
        z_inf = -0.5 / np.sqrt(q_lo) + 1.0
        np.multiply(tail, q_lo + 1.0 / 32.0, out=extension)
        with np.errstate(divide="ignore"):
            np.divide(B / kT, extension, out=extension)
        np.add(extension, z_inf, out=zeta)
        np.multiply(zeta, tail, out=extension)
        z_max = _zeta_max(lo, hi, const, length, B, kT, q_lo, z_inf)
    else:
        zeta.fill(1.0)
        extension[:] = tail
    short = _signed_and_short(M, turns, lo, tail, short_tail_length, out.short_tail[sl])
    if thermal and z_max > 1.0:  # the masks only where zeta's largest value exceeds 1
        over = bool(np.any((zeta > 1.0) & ~short))
    # M = sign(N) M_p: its extremes are those of the extreme turns (no reductions)
    return block_summary(extension, M, zeta, bracket if thermal else None, short, (lo, hi),
                          over=over, q_lo=q_lo,
                          torque_range=(np.copysign(Mp, lo), np.copysign(Mp, hi)))


def _zeta_max(lo, hi, const, length, B, kT, Q, z_inf):
    """zeta's largest value in a plectoneme block with turns in ``[lo, hi]``, bit for bit.

    Each step from |N| to zeta (subtract, multiply, subtract, multiply, divide, add)
    is one correctly rounded operation, monotone in its argument, so the largest
    value is the same operations on the largest |N| (the shortest tail): no pass.
    """
    Nb, _, k, _, _ = const
    tail = length - (max(abs(lo), abs(hi)) - Nb) * k
    with np.errstate(divide="ignore"):
        return B / kT / (tail * (Q + 1.0 / 32.0)) + z_inf


def fill_stretched(n, turns, lo, hi, const, length, B, kT, thermal, short_tail_length, out, sl,
                    zeta, bracket):
    """:func:`fill_block` for a block entirely in the stretched phase (one force).

    S = 0 and the tail is the whole molecule: the plectoneme length, phase,
    tail and short-tail flag are constants (about 9 passes fewer than the
    general path, the same operations per point, bit-identical: tested). None
    if the bracket is not positive (the general path names it).
    """
    c, s = const[3], const[4]
    out.plectoneme_length[sl].fill(0.0)
    out.phase[sl].fill(STRETCHED)
    M = out.torque[sl]
    np.multiply(n, c, out=M)  # C_eff 2 pi |N| / L, below M_p
    extension = out.extension[sl]
    q_lo = None
    if thermal:
        Q = _bracket(M, kT, s, bracket)
        q_lo = Q.min()
        if not q_lo > 0.0:
            return None
        _tail_zeta(Q, length, B, kT, zeta, extension)
        np.multiply(zeta, length, out=extension)
    else:
        zeta.fill(1.0)
        extension.fill(length)
    if lo < 0.0 or np.signbit(lo):
        np.copysign(M, turns, out=M)
    short = out.short_tail[sl]
    short.fill(length < short_tail_length)
    # M = sign(N) C_eff 2 pi |N| / L is monotone in N: its extremes at the extreme turns
    m_range = (np.copysign(abs(lo) * c, lo), np.copysign(abs(hi) * c, hi))
    return block_summary(extension, M, zeta, bracket if thermal else None, short, (lo, hi),
                          q_lo=q_lo, torque_range=m_range)


def fill_coiled(n, turns, lo, hi, const, length, B, kT, thermal, short_tail_length, out, sl,
                 zeta, bracket):
    """:func:`fill_block` for a block entirely fully coiled (one force): constants only.

    S = L, no tail (z = 0, zeta = 0), the torque held at M_p, the bracket at M_p.
    """
    Mp, s = const[1], const[4]
    out.plectoneme_length[sl].fill(length)
    out.phase[sl].fill(FULLY_COILED)
    M = out.torque[sl]
    M.fill(Mp)
    out.extension[sl].fill(0.0)
    if out.zeta is not None:  # kept (diagnostics): else buffers no one reads
        zeta.fill(0.0)
    q_lo = None
    if thermal:
        q = Mp * (0.5 / kT)
        q_lo = s - q * q
        if out.bracket is not None:
            bracket.fill(q_lo)
    if lo < 0.0 or np.signbit(lo):
        np.copysign(M, turns, out=M)
    short = out.short_tail[sl]
    short.fill(0.0 < short_tail_length)
    return block_summary(out.extension[sl], M, zeta, None, short, (lo, hi),
                          over=False,  # zeta = 0
                          q_lo=q_lo, torque_range=(np.copysign(Mp, lo), np.copysign(Mp, hi)))


#: the one-phase block fillers of :func:`fill_block`
UNIFORM = {STRETCHED: fill_stretched, PLECTONEME: fill_plectoneme,
            FULLY_COILED: fill_coiled}
