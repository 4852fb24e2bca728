"""Fully coiled free-energy points from one Chebyshev table of the plectoneme branch. Float-only.

The fully coiled points of ``model="free-energy"`` (:mod:`supercoil.core.dna.free_energy`)
need the plectoneme state whose linking per length matches the applied turns,
``l_p(T) = M_p(T)/C + tau(T) = x`` (with the end loop ``loop = (B, L)``:
``M_p/C + tau (1 - l(T)/L) = x``, ``l(T) = 2 pi sqrt(B/(2T))``). ``l_p`` is smooth and
increasing in ``u = log T`` and the same for every point (it does not depend on the
force, which only sets where the branch starts, at ``T_eff``). So instead of a
secant per point (5-11 equilibrium calls on all of them), :func:`torque_at_linking`

1. takes the domain ``[u_lo, u_hi]`` that every root lies in (``l_p`` increasing):
   ``u_lo`` the smallest ``log T_eff``, ``u_hi`` the root of the largest ``x``, solved
   by the caller's secant, which raises the caller's errors (no plectoneme at that
   tension, no convergence) exactly as before;
2. tabulates ``l_p(u)`` and ``M_p(u)`` at Chebyshev-Lobatto nodes of the domain
   (one equilibrium call on :data:`START_DEGREE` + 1 nodes, :data:`NARROW_DEGREE` + 1 on a
   narrow domain, doubled on the nested new nodes until the trailing coefficients are
   converged, at most :data:`MAX_DEGREE`);
3. inverts the interpolant of ``l_p`` per point by Newton in the Chebyshev
   variable (started by linear interpolation of the node values) and evaluates
   the interpolant of ``M_p`` at the root; ``T = exp(u)``.

Accuracy: the interpolant is accepted once its last two coefficients are below
``TAIL_RTOL = 1e-14`` times the smallest slope ``|dl_p/du|`` on the nodes (an error
in u, i.e. relative in T, of ~1e-14) or below the equilibrium's own rounding noise
``NOISE max |l_p|`` (which any solver of the same equation inherits), and those of
``M_p`` below 1e-14 ``max |M|``. Measured against scipy ``brentq`` per point on the
real equilibrium, solved to 1e-15 in u (0.3-10 pN, full coiling to 3 times its
turns and 60-800 turns, with and without the loop): T and M within 6e-14 relative,
typically 5e-15, against 9e-14 for the secant it replaces (tests/dna/
test_coiled_table.py asserts 1e-13). Degree 16 suffices for ``|N| <= 25`` at 1.2 pN,
32 for three times full coiling, 64 for 800 turns (the table starts at 32).

Cost (1.2 pN, seed set, N in linspace(-25, 25, n), CPU, medians of 7): with 74 fully
coiled points (n = 1000) the table costs about a fifth of the secant, with 7,362 points
(n = 1e5) about 1/24; with the screened interaction (150 mM, where an equilibrium call is
expensive) 300 points cost about 1/18 of the secant. Fewer than :data:`MIN_POINTS` points:
the secant on all of them is cheaper (measured crossover 6-12 points; at 2 points the
table costs about 1.7 times the secant). Where the table does not converge by
:data:`MAX_DEGREE`, converges too slowly (a kink in ``l_p``: screened, 150 mM, 5 pN, where
the strands reach hard contact; the wasted table costs 13 % there) or Newton does not
settle, :func:`torque_at_linking` returns None and the caller falls back to its secant.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.polynomial import chebyshev as _ch

from supercoil.core.dna.coiled_secant import branch_linking, secant  # re-exported
from supercoil.core.numerics import chebval_rows, stacked

__all__ = [
    "DOMAIN_OVERSHOOT",
    "INVERSE_MIN_POINTS",
    "INVERSE_RTOL",
    "MAX_DEGREE",
    "MAX_PIECES",
    "MIN_POINTS",
    "NARROW_DEGREE",
    "NARROW_WIDTH",
    "NOISE",
    "START_DEGREE",
    "START_PIECES",
    "TAIL_RTOL",
    "Inverse",
    "Series",
    "branch_linking",
    "branch_series",
    "coefficients",
    "evaluate_inverse",
    "hermite",
    "interleave",
    "inverse_of",
    "inverse_table",
    "lobatto",
    "secant",
    "solve_series",
    "torque_at_linking",
]

#: first table degree (33 nodes in one equilibrium call: for hard-core about the cost of the
#: 9 + 8 nodes of degree 16 on the scalar path of <= 12 tensions, and of the 9 + 8 + 16 calls
#: up to degree 32 less than two thirds; for screened, whose calls cost more, one call for
#: up to three)
START_DEGREE = 32
#: a domain narrower than this in log T (a few turns past full coiling: degree 16 has
#: sufficed) starts at NARROW_DEGREE instead, 9 + 8 nodes on that scalar path
NARROW_WIDTH = 1.0
NARROW_DEGREE = 8
#: largest table degree tried before giving up (the caller's secant then solves)
MAX_DEGREE = 128
#: trailing coefficients accepted, relative to the smallest slope |dl_p/du| and max |M|
TAIL_RTOL = 1e-14
#: or (for l_p) below this fraction of max |l_p|: the equilibrium's own rounding noise
#: (measured plateau ~1e-16 max |l_p|, 800 turns at 1.2 pN), which any solver inherits
NOISE = 16.0 * np.finfo(float).eps
#: the domain's upper end may exceed the largest root by this fraction of its width
DOMAIN_OVERSHOOT = 0.15
#: fewer fully coiled points than this: the secant on all of them is cheaper (measured)
MIN_POINTS = 8
#: a doubling must shrink the trailing coefficients at least this much (from degree 32)
_SLOW_DECAY = 0.05
_NEWTON_MAXITER = 12
_NEWTON_TOL = 1e-14
_ROUNDING = 16.0 * np.finfo(float).eps
#: pieces of the first cubic inverse (:func:`inverse_table`); its error sets the final size
START_PIECES = 64
#: fewer fully coiled points in a call than this: Newton on the series solves them (the
#: inverse would solve 2 K + 1 >= 129 roots, typically 2,049, to build itself)
INVERSE_MIN_POINTS = 2048
#: largest number of pieces tried (the caller's secant solves beyond)
MAX_PIECES = 1 << 14
#: the inverse is accepted once at every piece's midpoint its T and M are within this
#: (relative; M relative to max |M|) of the table's own root
INVERSE_RTOL = 3e-14


def lobatto(degree):
    """Chebyshev-Lobatto nodes ``cos(pi j / degree)``, j = 0..degree (descending)."""
    return np.cos(np.pi * np.arange(degree + 1) / degree)


def coefficients(values):
    """Chebyshev coefficients of the interpolant through values at :func:`lobatto` nodes."""
    n = values.size - 1
    ext = np.concatenate([values, values[-2:0:-1]])
    c = np.fft.rfft(ext).real / n
    c[0] *= 0.5
    c[n] *= 0.5
    return c[:n + 1]


def _nodes(t, u_lo, half, C, equilibrium, loop):
    """``(M_p, l_p)`` at the Chebyshev variable's values t (one equilibrium call)."""
    T = np.exp(u_lo + half * (t + 1.0))
    st = equilibrium(T)
    M = np.asarray(st.torque, float)
    return M, branch_linking(M, np.asarray(st.torsion, float), T, C, loop)


def _table(u_lo, u_hi, C, equilibrium, loop):
    """``(c_l, c_M, l_p at the nodes)``: converged Chebyshev series on [u_lo, u_hi], or None.

    None also where the node values of ``l_p`` are not increasing, or from degree 32 on
    where a doubling shrinks the trailing coefficients (relative to their tolerance) by
    less than :data:`_SLOW_DECAY` (a kink, e.g. a switch between two branches: the
    coefficients fall as a power, not geometrically; the secant then solves).
    """
    half = 0.5 * (u_hi - u_lo)
    degree = min(START_DEGREE if u_hi - u_lo > NARROW_WIDTH else NARROW_DEGREE, MAX_DEGREE)
    M, lp = _nodes(lobatto(degree), u_lo, half, C, equilibrium, loop)
    err_prev = np.inf
    while True:
        if not np.all(np.diff(lp) < 0.0):  # nodes descend in t: l_p must rise with u
            return None
        cl, cM = coefficients(lp), coefficients(M)
        slope = np.min(-np.diff(lp) / np.diff(lobatto(degree))) / half  # min dl_p/du, node pairs
        scale_l = max(TAIL_RTOL * slope, NOISE * np.max(np.abs(lp)))
        err = max(max(abs(cl[-1]), abs(cl[-2])) / scale_l,
                  max(abs(cM[-1]), abs(cM[-2])) / (TAIL_RTOL * np.max(np.abs(M))))
        if err <= 1.0:
            return cl, cM, lp
        if degree >= MAX_DEGREE or (degree >= 32 and err > _SLOW_DECAY * err_prev):
            return None
        err_prev = err
        degree *= 2  # the nested new nodes are the odd ones of the doubled degree
        M_new, lp_new = _nodes(lobatto(degree)[1::2], u_lo, half, C, equilibrium, loop)
        M, lp = interleave(M, M_new), interleave(lp, lp_new)


def interleave(old, new):
    out = np.empty(old.size + new.size)
    out[0::2], out[1::2] = old, new
    return out


def torque_at_linking(linking, extremes, C, equilibrium, loop=None):
    """Fully coiled ``(M, T)`` with ``l_p(T) = linking`` from one table, or None (not resolved).

    Parameters
    ----------
    linking : array
        Target ``x = 2 pi |N| / L`` (or with the loop's writhe removed), rad/m.
    extremes : tuple
        ``(T_lo, T_hi)`` (N): every root lies between them (the smallest ``T_eff``
        and the root of the largest target, solved by the caller).
    C : float
        Torsional rigidity (N m^2).
    equilibrium : callable
        ``T -> PlectonemeState``.
    loop : tuple, optional
        ``(B, L)``: the end-loop variant.

    Returns
    -------
    tuple or None
        ``(M, T)`` arrays of the shape of ``linking``, or None where the table
        does not converge by :data:`MAX_DEGREE` or Newton does not settle (the
        caller then solves by its secant).
    """
    series = branch_series(extremes, C, equilibrium, loop)
    return None if series is None else solve_series(series, linking)


class Series(NamedTuple):
    """Converged Chebyshev series of ``l_p`` and ``M_p`` in ``t`` on ``[u_lo, u_hi]``."""

    u_lo: float  # log T at t = -1
    half: float  # (u_hi - u_lo) / 2
    linking: np.ndarray  # coefficients of l_p, rad/m
    slope: np.ndarray  # of dl_p/dt
    torque: np.ndarray  # of M_p, N m
    nodes: np.ndarray  # l_p at the Lobatto nodes (descending t)


def branch_series(extremes, C, equilibrium, loop=None):
    """The :class:`Series` of the branch between the tensions ``extremes``, or None.

    None where ``T_hi <= T_lo`` or the table does not converge (see
    :func:`torque_at_linking`).
    """
    u_lo, u_hi = np.log(extremes[0]), np.log(extremes[1])
    if not u_hi > u_lo:  # all targets equal: the extremes are the answer
        return None
    table = _table(u_lo, u_hi, C, equilibrium, loop)
    if table is None:
        return None
    cl, cM, lp_nodes = table
    return Series(u_lo, 0.5 * (u_hi - u_lo), cl, _ch.chebder(cl), cM, lp_nodes)


def solve_series(series, linking):
    """``(M, T)`` with ``l_p(T) = linking`` by Newton on ``series``, or None (not settled)."""
    x = np.asarray(linking, float)
    t = _roots(x, series.linking, series.slope, series.nodes, series.half)
    if t is None:
        return None
    return _ch.chebval(t, series.torque), np.exp(series.u_lo + series.half * (t + 1.0))


def _roots(x, cl, dcl, lp_nodes, half, t=None):
    """Chebyshev variable t in [-1, 1] with ``l_p(t) = x`` (Newton on the table), or None.

    Started from ``t`` if given, else from linear interpolation of the node values.
    Converged once the step is below the tolerance (1e-14 in u, or the rounding of
    ``l_p``), or once the error left after the step is: Newton's error after a step s is
    at most ``K s^2`` with ``K = max|l_p''| / (2 min|l_p'|)``, and on [-1, 1]
    ``max|l_p''| <= sum_k |c_k| k^2 (k^2 - 1) / 3`` (``T_k''`` is largest at the ends,
    ``T_k''(1) = k^2 (k^2 - 1) / 3``). From a close start (a coarser
    inverse's tension: steps of ~1e-9) that accepts the first step, one series evaluation
    instead of two.
    """
    if t is None:
        t = np.interp(x, lp_nodes[::-1], lobatto(cl.size - 1)[::-1])
    last = None
    both = stacked(cl, dcl)
    curvature = _derivative_bound(cl, 2)  # >= max |l_p''(t)| on [-1, 1]
    for _ in range(_NEWTON_MAXITER):
        lp, dlp = chebval_rows(t, both)
        step = np.abs((lp - x) / dlp)
        t = t - (lp - x) / dlp
        # converged: the step, or the next one predicted from quadratic convergence
        # (K s^2 with K = |s| / |s_prev|^2, 100 times over), below 1e-14 in u or at
        # the rounding of l_p (l_p / l_p' ulp)
        tol = _NEWTON_TOL / half + _ROUNDING * np.abs(lp / dlp)
        if np.all(step <= tol):
            break
        biggest, flattest = float(step.max()), float(np.abs(dlp).min())
        if biggest <= 1e-6 and curvature * biggest <= 0.5 * flattest and \
                curvature * biggest**2 <= flattest * _NEWTON_TOL / half:  # K s^2, K <= c''/|l'|
            break
        if last is not None and np.all((step <= 1e-6) & (100.0 * step ** 3 <= tol * last ** 2)):
            break
        last = step
    else:
        return None
    if np.any(np.abs(t) > 1.0 + 1e-9):  # a root of the polynomial outside the domain
        return None
    return t


class Inverse(NamedTuple):
    """Piecewise cubic ``M(x)`` and ``T(x)`` of the fully coiled branch (:func:`inverse_table`).

    ``x`` lies in piece ``floor((x - x_lo) scale)`` (``scale`` in pieces per rad/m);
    ``coefficients`` holds per piece those of the powers 0-3 of the position in the piece
    (0 to 1), of M as real and of T as imaginary parts: one gather per power serves both
    cubics (:func:`evaluate_inverse`).
    """

    x_lo: float  # rad/m
    x_hi: float  # rad/m
    scale: float  # pieces per rad/m
    coefficients: np.ndarray  # (4, pieces) complex: M's (N m) + 1j T's (N)

    @property
    def torque(self):
        """The torque's coefficient rows (4, pieces), N m."""
        return self.coefficients.real

    @property
    def tension(self):
        """The tension's coefficient rows (4, pieces), N."""
        return self.coefficients.imag


def inverse_table(extremes, C, equilibrium, loop=None):
    """The inverse ``x -> (M, T)`` of the branch on ``extremes`` as piecewise cubics, or None.

    One Chebyshev table of ``l_p`` and ``M_p`` (as :func:`torque_at_linking`), then
    the roots at ``K + 1`` equally spaced linkings from ``l_p(T_lo)`` to ``l_p(T_hi)``
    (Newton on the table) and on each piece the cubic Hermite interpolant of T and M
    from their values and exact slopes in x (``dT/dx = (dT/du) / (dl_p/du)``, ``dM/dx``
    likewise, from the series). A cubic Hermite piece errs most at its midpoint
    (``h^4 max|f^(4)| / 384``): the roots there are solved too, and from the error of
    :data:`START_PIECES` pieces K grows (as a power of 2, the error falling as
    ``K^-4``) until every midpoint agrees to :data:`INVERSE_RTOL`.
    A point then costs a few array operations instead of Newton on the series (two
    Chebyshev sums per step, 3-5 steps: 9x more CPU for 84,000 points). Seed set,
    1.2 pN, to 40 turns: 1024 pieces, within 7e-15 of the Newton roots.

    Parameters
    ----------
    extremes : tuple
        ``(T_lo, T_hi)`` (N), as in :func:`torque_at_linking`.
    C : float
        Torsional rigidity (N m^2).
    equilibrium : callable
        ``T -> PlectonemeState``.
    loop : tuple, optional
        ``(B, L)``: the end-loop variant.

    Returns
    -------
    Inverse or None
        None where the table is not resolved (as :func:`torque_at_linking`) or
        :data:`MAX_PIECES` pieces do not reach the tolerance.
    """
    series = branch_series(extremes, C, equilibrium, loop)
    return None if series is None else inverse_of(series)


def inverse_of(series):
    """The :class:`Inverse` of a :class:`Series` (see :func:`inverse_table`), or None."""
    u_lo, half, cl, dcl, cM, lp_nodes = series
    dcM = _ch.chebder(cM)
    three = stacked(cM, dcl, dcM)
    six = stacked(cl, dcl, _ch.chebder(dcl), cM, dcM, _ch.chebder(dcM))
    bounds = (_derivative_bound(cl, 2), _derivative_bound(cl, 3), _derivative_bound(cM, 3))
    x_lo, x_hi = lp_nodes[-1], lp_nodes[0]

    def level(pieces, guess=None):
        """``(Inverse, largest midpoint error)`` of ``pieces`` pieces, or ``(None, inf)``.

        Nodes and midpoints are solved in one Newton call, started from ``guess`` (a
        coarser inverse: its tension gives t to its error, so 1-2 steps) if given.
        """
        x = x_lo + (x_hi - x_lo) * (np.arange(2 * pieces + 1) / (2 * pieces))
        t0 = None if guess is None else \
            (np.log(evaluate_inverse(guess, x)[1]) - u_lo) / half - 1.0
        done = None if t0 is None else _one_step(x, t0, six, bounds, half)
        if done is None:
            t = _roots(x, cl, dcl, lp_nodes, half, t0)
            if t is None:
                return None, np.inf
            M, dl, dM = chebval_rows(t, three)  # dl_p/dt; dT/dt = half T
        else:
            t, M, dl, dM = done
        T = np.exp(u_lo + half * (t + 1.0))
        h = (x_hi - x_lo) / pieces  # from the width itself: a node spacing would add rounding
        cT = hermite(T[0::2], half * T[0::2] / dl[0::2], h)
        cM_ = hermite(M[0::2], dM[0::2] / dl[0::2], h)
        at_T, at_M = (c[0] + 0.5 * (c[1] + 0.5 * (c[2] + 0.5 * c[3])) for c in (cT, cM_))
        err = max(np.max(np.abs(at_T / T[1::2] - 1.0)),
                  np.max(np.abs(at_M - M[1::2])) / np.max(np.abs(M)))
        return Inverse(x_lo, x_hi, pieces / (x_hi - x_lo), cM_ + 1j * cT), err

    pieces = START_PIECES
    inverse, err = level(pieces)
    while inverse is not None and err > INVERSE_RTOL:
        if pieces >= MAX_PIECES:
            return None
        # the error falls as pieces^-4: straight to the estimated size (25 % margin)
        grow = 2 ** max(1, int(np.ceil(np.log2(1.25 * (err / INVERSE_RTOL) ** 0.25))))
        pieces = min(pieces * grow, MAX_PIECES)
        inverse, err = level(pieces, inverse)
    return inverse


def _derivative_bound(c, order):
    """A bound of ``|f^(order)(t)|`` on [-1, 1] for the Chebyshev series c: ``T_k^(n)`` is
    largest at t = 1, ``T_k^(n)(1) = prod_{m<n} (k^2 - m^2) / (2m + 1)``."""
    return float(np.abs(c) @ _derivative_weights(c.size, order))


@lru_cache(maxsize=32)
def _derivative_weights(size, order):
    """``T_k^(order)(1)`` for k < size (:func:`_derivative_bound`), read-only."""
    k2 = np.arange(size, dtype=float) ** 2
    weight = np.ones(size)
    for m in range(order):
        weight *= np.maximum(k2 - m * m, 0.0) / (2 * m + 1)
    weight.flags.writeable = False
    return weight


def _one_step(x, t0, six, bounds, half):
    """``(t, M_p, dl_p/dt, dM_p/dt)`` at the roots of ``l_p(t) = x`` by one Newton step from
    a close start ``t0`` (a coarser inverse's), or None (the start is not close enough).

    One series evaluation at t0 gives ``l_p, M_p`` and their first two derivatives. The
    step d is accepted where Newton's error after it, ``max|l_p''| d^2 / (2 min|l_p'|)``,
    is below a hundredth of the roots' tolerance (1e-16 in u: the roots of :func:`_roots`
    to rounding; seed set, 1.2 pN, to 40 turns: steps of 2e-10). The values then move to
    the root by Taylor's rule (``M_p + d M_p' + d^2 M_p''/2``, ``l_p' + d l_p''``,
    ``M_p' + d M_p''``), whose remainders (the third derivatives' bounds times ``d^2/2``)
    must lie below 1e-14 of ``min|l_p'|`` and of ``max|M_p|``: the slopes enter the
    cubic pieces times the piece's width in t (``2 / pieces``), so they move the inverse
    by less than 1e-16 (the M value's remainder, ``d^3/6``, is smaller still). The
    second series evaluation at the roots is saved.
    """
    lp, dl, ddl, M, dM, ddM = chebval_rows(t0, six)
    step = (lp - x) / dl
    biggest, flattest = float(np.abs(step).max()), float(np.abs(dl).min())
    curvature, third_l, third_M = bounds
    scale_M = float(np.abs(M).max())
    if not (biggest <= 1e-6 and curvature * biggest <= 0.5 * flattest
            and curvature * biggest**2 <= 0.01 * flattest * _NEWTON_TOL / half
            and 0.5 * third_l * biggest**2 <= 1e-14 * flattest
            and 0.5 * third_M * biggest**2 <= 1e-14 * scale_M):
        return None
    t = t0 - step
    if np.any(np.abs(t) > 1.0 + 1e-9):
        return None
    d = -step
    return t, M + d * (dM + 0.5 * d * ddM), dl + d * ddl, dM + d * ddM


def hermite(y, dy, h):
    """Coefficient rows (4, K) of the cubic Hermite pieces through values y and slopes dy."""
    out = np.empty((4, y.size - 1))
    c0, m0, c2, c3 = out
    c0[...] = y[:-1]
    np.multiply(dy[:-1], h, out=m0)
    m1 = h * dy[1:]
    np.subtract(y[1:], c0, out=c3)  # y1 - y0
    np.multiply(c3, 3.0, out=c2)
    c2 -= 2.0 * m0
    c2 -= m1  # 3 (y1 - y0) - 2 m0 - m1
    np.multiply(c3, -2.0, out=c3)
    c3 += m0
    c3 += m1  # 2 (y0 - y1) + m0 + m1
    return out


def evaluate_inverse(inverse, x, out=None, work=None):
    """``(M, T)`` at the linkings x (rad/m, within ``[x_lo, x_hi]``) of :func:`inverse_table`.

    Per point: the piece index, the position in it and both cubics by Horner's rule in
    complex arithmetic (M + 1j T times the real position: each part is the real
    operation, bit for bit), four gathers from coefficient rows that stay in cache, into
    ``out = (M, T)`` and the buffers ``work = (z, j, p, v, c)`` (float, index, float,
    complex, complex) if given (a block's fresh temporaries cost page faults:
    :mod:`supercoil.core.dna.free_energy_fill`). Measured at 42,000 points and 1024
    pieces: 0.84 of the CPU of two real cubics with eight gathers, the piece found in
    floats (truncation and the last piece's bound, one cast) 0.92 of it in integers.
    """
    x = np.asarray(x, float)
    M, T = out or (np.empty(x.shape), np.empty(x.shape))
    z, j, p, v, gathered = work or (np.empty(x.shape), np.empty(x.shape, np.intp),
                                    np.empty(x.shape), np.empty(x.shape, complex),
                                    np.empty(x.shape, complex))
    c = inverse.coefficients
    np.subtract(x, inverse.x_lo, out=z)
    z *= inverse.scale
    np.trunc(z, out=p)  # toward zero: piece 0 for x a rounding below x_lo (z > -1)
    np.minimum(p, c.shape[1] - 1, out=p)  # x_hi: the last piece at position 1
    z -= p  # the position in the piece
    j[...] = p
    c[3].take(j, out=v, mode="clip")  # j is in range: mode "clip" is unbuffered
    for k in (2, 1, 0):
        v *= z
        v += c[k].take(j, out=gathered, mode="clip")
    M[...] = v.real
    T[...] = v.imag
    return M, T
