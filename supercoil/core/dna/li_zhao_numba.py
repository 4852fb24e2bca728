"""The li-zhao hat-curve points compiled (optional, numba): one fused loop over the points.

The same per-point formulas as :func:`supercoil.core.dna.li_zhao_numpy.fill_block`
(docs/theory/li-zhao.md#hat-curve), in the same order of operations, so both
agree to rounding; each point is read once and its seven outputs written once
instead of about 25 array passes. Used by
:func:`~supercoil.core.dna.li_zhao.hat_curve_points` only when asked
(``fast=True`` or the environment variable ``SUPERCOIL_FAST=1``) and numba is
installed (``pip install supercoil[fast]``); the numpy path stays the default.
The kernel is compiled on first use (about a second) and cached on disk.
"""

from __future__ import annotations

import os

import numpy as np

__all__ = ["BAD_BRACKET", "BAD_TURNS", "ENV", "OK", "available", "compiled", "fill", "wanted"]

#: environment variable asking for the compiled kernel ("1")
ENV = "SUPERCOIL_FAST"
_KERNEL = None

#: codes of :func:`fill`: all points done, a non-finite turns value, a bracket <= 0
OK, BAD_TURNS, BAD_BRACKET = -1, -2, -3


def wanted(fast):
    """Whether the compiled kernel is asked for: ``fast``, or (``None``) ``SUPERCOIL_FAST=1``."""
    if fast is None:
        return os.environ.get(ENV, "").strip() == "1"
    return bool(fast)


def available():
    """True if numba can be imported."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def compiled():
    """The compiled loop (compiled once per process, cached on disk by numba)."""
    global _KERNEL
    if _KERNEL is None:
        try:
            import numba
        except ImportError:
            raise ImportError(
                f"the compiled hat-curve kernel (fast=True or {ENV}=1) needs numba: "
                "pip install supercoil[fast]") from None
        try:
            _KERNEL = numba.njit(cache=True, nogil=True, error_model="numpy")(_loop)
        except RuntimeError:  # no writable cache location: compile in memory only
            _KERNEL = numba.njit(nogil=True, error_model="numpy")(_loop)
    return _KERNEL


def fill(turns, const, length, B, kT, thermal, short_tail_length, out, sl, zeta, bracket):
    """Points of one block into ``out[sl]``, ``zeta`` and ``bracket``, as the numpy ``fill_block``.

    Returns
    -------
    code : int
        :data:`OK`, or :data:`BAD_TURNS` / :data:`BAD_BRACKET` (the caller
        raises the numpy path's named error for the block).
    zeta_over_long_tail : bool
        zeta > 1 at a point not flagged ``short_tail`` (the other reductions
        of the block's summary are numpy's, on the cache-resident block: a
        min/max in the loop would stop its vectorisation and double its time).
    """
    Nb, Mp, k, c, s = (np.atleast_1d(np.asarray(a, dtype=float)) for a in const)
    Q = bracket if thermal else np.empty(0)
    bad_turns, bad_bracket, over = compiled()(
        turns, Nb, Mp, k, c, s, float(length), 0.5 / kT, B / kT, bool(thermal),
        float(short_tail_length), out.extension[sl], out.torque[sl], out.plectoneme_length[sl],
        out.phase[sl], out.short_tail[sl], zeta, Q)
    return BAD_TURNS if bad_turns else BAD_BRACKET if bad_bracket else OK, over


def _loop(turns, Nb_, Mp_, k_, c_, s_, length, half_over_kT, BkT, thermal, short, ext,
          torque, S_, phase, short_tail, zeta_, Q_):
    """The fused loop: the operations of ``li_zhao_numpy.fill_block``, point by point.

    No early exit and no branch on a point's phase (selects instead), so that
    LLVM vectorises it: into preallocated outputs it costs about two numpy ``sqrt``
    passes over the turns, against about five for the same loop with early returns.
    Returns the flags
    ``(bad_turns, bad_bracket, over)``: a non-finite turns value, a bracket <= 0
    at a point that is not fully coiled, zeta > 1 at a long tail.
    """
    step = 0 if Nb_.shape[0] == 1 else 1  # constants for the block, or one per point
    bad_turns = False
    bad_bracket = False
    over = False
    for i in range(turns.shape[0]):
        j = i * step
        Nb = Nb_[j]
        t = turns[i]
        n = abs(t)
        bad_turns |= not np.isfinite(n)
        S = max(n - Nb, 0.0) * k_[j]
        coiled = S >= length
        S = min(S, length)
        tail = length - S
        M = min(n * c_[j], Mp_[j])
        is_short = tail < short
        if thermal:
            q = M * half_over_kT
            Q = s_[j] - q * q
            Q_[i] = Q
            bad_bracket |= (not Q > 0.0) and not coiled
            e = BkT / ((Q + 1.0 / 32.0) * tail)
            zeta = -0.5 / np.sqrt(Q)
            zeta += 1.0
            zeta += e
            zeta = 0.0 if coiled else zeta
            ext[i] = zeta * tail
            over |= zeta > 1.0 and not is_short
        else:
            zeta = 0.0 if coiled else 1.0
            ext[i] = tail
        zeta_[i] = zeta
        S_[i] = S
        phase[i] = (n > Nb) + coiled
        torque[i] = np.copysign(M, t)
        short_tail[i] = is_short
    return bad_turns, bad_bracket, over
