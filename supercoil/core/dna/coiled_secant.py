"""The fully coiled state of a linking per length, by a safeguarded secant per point. Float-only.

The reference solver of the fully coiled points of ``model="free-energy"``
(:mod:`supercoil.core.dna.coiled_table` tabulates the branch instead where a call has
enough points, and falls back to this secant where the table does not resolve it).
Re-exported by :mod:`supercoil.core.dna.coiled_table`.
"""

from __future__ import annotations

import numpy as np

from supercoil.core.dna import end_loop as _loop
from supercoil.exceptions import ValidityError

__all__ = ["branch_linking", "secant"]

_COILED_MAXITER = 60


def branch_linking(torque, torsion, tension, C, loop=None):
    """``l_p = M/C + tau`` (rad/m); with ``loop = (B, L)``: ``M/C + tau (1 - l(T)/L)``."""
    if loop is None:
        return torque / C + torsion
    return torque / C + torsion * (1.0 - _loop.loop_length(tension, loop[0]) / loop[1])


def secant(x, pull, helix_linking, C, equilibrium, loop, upper=None):
    """Safeguarded secant in ``u = log T`` for ``l_p(T) = x`` per point: ``(M, T)``.

    The algorithm of
    :func:`supercoil.core.dna.free_energy.plectoneme_torque_at_linking` (its
    docstring: 5-11 equilibrium calls, the state evaluated last within 1e-13 of
    the root in u), moved here unchanged.

    ``upper``: return ``(None, T_hi)`` as soon as every point has an evaluated
    ``T_hi`` above its root that exceeds the next estimate by at most ``upper``
    times ``log(T_hi/T_eff)`` (the domain of the Chebyshev table).
    """
    ua = np.log(np.asarray(pull, float))
    u0 = ua
    ra = np.asarray(helix_linking, float) - x
    ub = ua + np.maximum(2.0 * np.log(x / helix_linking), 1e-6)
    lo, hi = ua.copy(), np.full(x.shape, np.inf)
    act = np.ones(x.shape, bool)
    slow, ref = np.zeros(x.shape, int), np.full(x.shape, np.inf)
    r_lo, r_hi = np.zeros(x.shape), np.zeros(x.shape)
    M_out, T_out, res = np.empty(x.shape), np.empty(x.shape), np.zeros(x.shape)
    for _ in range(_COILED_MAXITER):
        T_out[act] = np.exp(ub[act])
        st = equilibrium(T_out[act])
        M, tau = np.asarray(st.torque, float), np.asarray(st.torsion, float)
        M_out[act] = M
        rb = np.zeros(x.shape)
        rb[act] = branch_linking(M, tau, T_out[act], C, loop) - x[act]
        res = np.where(act, rb, res)
        r_lo = np.where(act & (rb < 0.0), rb, r_lo)
        r_hi = np.where(act & (rb >= 0.0) & (ub <= hi), rb, r_hi)
        lo = np.where(act & (rb < 0.0), ub, lo)
        hi = np.where(act & (rb >= 0.0), np.minimum(hi, ub), hi)
        _check_no_jump(act & (hi - lo < 1e-6), r_hi - r_lo, x, np.exp(hi))
        with np.errstate(divide="ignore", invalid="ignore"):
            un = ub - rb * (ub - ua) / (rb - ra)
        bad = ~np.isfinite(un) | (un < lo) | (un > hi)
        # bracketed, but the bracket has not halved in 3 steps (a jump of l_p where the
        # strands snap into contact; a smooth root is found in fewer): bisect
        width = hi - lo
        halved = ~np.isfinite(ref) | (width <= 0.5 * ref)
        ref = np.where(halved, width, ref)
        slow = np.where(np.isfinite(hi) & ~halved, slow + 1, 0)
        bad |= slow >= 3
        slow = np.where(slow >= 3, 0, slow)
        un = np.where(bad & np.isfinite(hi), 0.5 * (lo + hi), un)
        un = np.where(bad & ~np.isfinite(hi), ub + 1.0, un)
        # until the root is bracketed, at most a factor e^2 in T per step: a secant
        # overshoot must not leave the interaction's range when the root is inside it
        un = np.where(np.isfinite(hi), un, np.minimum(un, ub + 2.0))
        un = np.where(act, un, ub)
        if upper is not None and np.all(np.isfinite(hi) & (hi - un <= upper * (hi - u0))):
            return None, np.exp(hi)
        ua, ra = np.where(act, ub, ua), np.where(act, rb, ra)
        # the evaluated state is kept once the next step is below 1e-13 in log T
        act &= np.abs(un - ub) > 1e-13
        ub = un
        if not np.any(act):
            _check_no_jump(np.abs(res) > 1e-6 * x, np.abs(res), x, T_out)
            return M_out, T_out
    raise ValidityError(  # pragma: no cover - bisection halves every third step at worst
        f"no fully coiled plectoneme state found in {_COILED_MAXITER} steps")


def _check_no_jump(closed, jump, x, T):
    """ValidityError where the secant closed on a jump of ``l_p`` instead of a root.

    ``closed``: points whose bracket is resolved (to 1e-6 in log T, or converged);
    ``jump``: the change of ``l_p - x`` across it. At a root it is ~1e-6 x or
    less (``dl_p/dlog T`` is of order x); across a discontinuity (the strands
    snapping into contact) a finite fraction of x remains.
    """
    bad = closed & (jump > 1e-3 * x)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        raise ValidityError(
            f"the plectoneme's linking per length jumps at tension {T[i] * 1e12:.6g} pN (the "
            f"strands snap into contact there): no uniform fully coiled plectoneme holds "
            f"{x[i] / (2.0 * np.pi) * 1e-6:.6g} turns per um, which lies inside the jump")
