"""Optional compiled hat-curve kernel: one fused loop over the points (numba).

The same per-point formulas as :func:`supercoil.core.dna.hat._fill_block`
(docs/theory/li-zhao.md#hat-curve), in the same order of operations, so both
agree to rounding; each point is read once and its seven outputs written once
instead of about 25 array passes. Used by
:func:`~supercoil.core.dna.hat.hat_curve_points` only when asked
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


def fill(turns, const, length, B, kT, thermal, short_tail_length, out, sl):
    """Points of one block into ``out[sl]``; ``const`` as in ``hat._fill_block``.

    Returns
    -------
    int
        :data:`OK`, or :data:`BAD_TURNS` / :data:`BAD_BRACKET` (the caller
        raises the numpy path's named error for the block).
    """
    Nb, Mp, k, c, s = (np.atleast_1d(np.asarray(a, dtype=float)) for a in const)
    Q = out.bracket[sl] if thermal else np.empty(0)
    return compiled()(turns, Nb, Mp, k, c, s, float(length), 0.5 / kT, B / kT, bool(thermal),
                     float(short_tail_length), out.extension[sl], out.torque[sl],
                     out.plectoneme_length[sl], out.phase[sl], out.short_tail[sl],
                     out.zeta[sl], Q)


def _loop(turns, Nb_, Mp_, k_, c_, s_, length, half_over_kT, BkT, thermal, short, ext,
          torque, S_, phase, short_tail, zeta_, Q_):
    """The fused loop: the operations of ``hat._fill_block``, point by point."""
    one = Nb_.shape[0] == 1  # per-force constants: one for the block, or one per point
    for i in range(turns.shape[0]):
        j = 0 if one else i
        Nb = Nb_[j]
        t = turns[i]
        n = abs(t)
        if not np.isfinite(n):
            return BAD_TURNS
        S = max(n - Nb, 0.0) * k_[j]
        coiled = S >= length
        S = min(S, length)
        tail = length - S
        M = min(n * c_[j], Mp_[j])
        if coiled:
            zeta = 0.0
            if thermal:
                q = M * half_over_kT
                Q_[i] = s_[j] - q * q
        elif thermal:
            q = M * half_over_kT
            Q = s_[j] - q * q
            if not Q > 0.0:
                return BAD_BRACKET
            Q_[i] = Q
            e = BkT / ((Q + 1.0 / 32.0) * tail)
            zeta = -0.5 / np.sqrt(Q)
            zeta += 1.0
            zeta += e
        else:
            zeta = 1.0
        zeta_[i] = zeta
        ext[i] = zeta * tail if thermal else tail
        S_[i] = S
        phase[i] = (1 if n > Nb else 0) + (1 if coiled else 0)
        torque[i] = np.copysign(M, t)
        short_tail[i] = tail < short
    return OK
