"""Generic numerics of the kernels: bisection, safeguarded Newton, running integrals, crossings.

Float-only (numpy, scipy); no physics here. Every helper is vectorised and ends
in a bounded number of iterations. Whether a hand-written solver stays or is
replaced by scipy's elementwise solvers was decided by measurement (best of
5-7 runs on the 2-core development machine, numpy 2.4, scipy 1.17; the
measuring code is ``measure()`` in ``tests/core/test_numerics.py``, run it
with ``python tests/core/test_numerics.py``); the rule: scipy wherever it is
no more than 1.5x slower.

=============================  ================================  ==============  ========
solver                         workload                          scipy time /    kept
                                                                 own time
=============================  ================================  ==============  ========
:func:`bisect_increasing`      [eq ini], 1000 N_0 in 1e-6..2000  1.22x raw,      own
                               (find_root)                       1.53-1.60x
                                                                 sign-exact
:func:`safe_newton`            (GE2) tilt, 600 reduced radii     3.7x            own
                               (find_root)
k = 0 rough tilt, Newton in y  2000 arclengths (find_root)       12.8x           own
(core/rod/rough.k0_y_of_s)
s(y) inversion, Newton         2000 points, k = 0 / -20 rad/m    2.8x / 5.5x     own
(core/rod/rough_solution)           (find_root)
WLC inversion, safe_newton     1, 20, 1000 forces 0-100 pN       7-19x           own
(core/dna/phases)                   (find_root)
:func:`cumulative_integrals`   Tw, Wr of the k = 0 helix on      177x            own
                               860 panels (tanhsinh)
:func:`finite_difference`      designed pitch P(s), 2001 points  17x             own
                               (scipy.differentiate.derivative)
:func:`first_crossing`         scalar refinement                 scipy brentq    scipy
=============================  ================================  ==============  ========

scipy's find_root and tanhsinh agree with the hand-written solvers to 4e-16
(roots) and 2e-14 (integrals) relative on these workloads. "Sign-exact": the
root depends only on the sign of the function (see :func:`bisect_increasing`).
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "bisect_from_estimate",
    "bisect_increasing",
    "chebval_rows",
    "cumulative_integrals",
    "find_root",
    "finite_difference",
    "first_crossing",
    "safe_newton",
    "single_thread_product",
    "stacked",
    "table_cubic",
]


def bisect_increasing(fun, lo, hi, n_iter=1100, xtol=0.0):
    """Vectorised bisection for the sign change of an increasing function.

    Kept hand-written by measurement. scipy.optimize.elementwise.find_root
    (Chandrupatla) on [eq ini] for 1000 values of N_0 from 1e-6 to 2000 takes
    1.22x the time of this bisection, but its roots depend on the rounding of
    ``fun``'s values: inputs that differ in the last bit (the same rod given in
    mm and in m) then give tilts that differ in the last bit, where bisection,
    which uses only the sign, gives identical ones (a tested unit invariance).
    find_root followed by a sign-only bisection of its final bracket restores
    that and takes 1.53-1.60x (three runs; 1.8x for a single point), over the
    1.5x limit. ``fun(x)`` is called with arrays of the full shape of ``lo``.

    Parameters
    ----------
    fun : callable
        ``fun(x) -> array`` broadcasting like ``lo``; ``fun(lo) <= 0 <= fun(hi)``
        elementwise, with exactly one sign change in between (only the sign is
        used, so ``fun`` may be any positive multiple of a monotone function).
    lo, hi : array_like
        Brackets (broadcast together).
    n_iter : int
        Maximum halvings; stops early once every bracket has collapsed to
        adjacent floats (or is narrower than ``xtol``). The default 1100 lets a
        bracket [0, x] reach a root anywhere down to the smallest subnormal
        (about 1075 halvings from 1 to 5e-324, plus 53 for the mantissa); a
        root near the top of the bracket takes about 55.

    Returns
    -------
    numpy.ndarray
        Midpoints of the final brackets (accurate to about one float spacing).
    """
    lo, hi = np.broadcast_arrays(np.asarray(lo, float), np.asarray(hi, float))
    lo, hi = lo.copy(), hi.copy()
    for _ in range(n_iter):
        mid = 0.5 * (lo + hi)
        f = np.asarray(fun(mid), float)
        up = f > 0
        hi = np.where(up, mid, hi)
        lo = np.where(up, lo, mid)
        mid2 = 0.5 * (lo + hi)
        if np.all((mid2 == lo) | (mid2 == hi) | (hi - lo <= xtol)):
            break
    return 0.5 * (lo + hi)


def safe_newton(fun, x, lo, hi, xtol, maxiter=100):
    """Root of an increasing ``fun`` in ``[lo, hi]`` (``fun(lo) <= 0 <= fun(hi)``).

    ``fun(x) -> (f, df)``. Newton steps that leave the current bracket, or are
    not finite, are replaced by bisection; the bracket shrinks with every sign
    evaluation, so the iteration cannot fail once bracketed. Ends after
    ``maxiter`` steps at most.

    Kept hand-written by measurement: on the (GE2) tilt of the DNA plectoneme
    (600 reduced radii, :func:`supercoil.core.dna.plectoneme.reduced_tilt`)
    scipy.optimize.elementwise.find_root takes 3.7x its time for the same roots
    (2e-16 apart): Newton uses the analytic
    derivative the caller already has.
    """
    x = np.array(x, dtype=float, copy=True)
    lo = np.array(lo, dtype=float, copy=True)
    hi = np.array(hi, dtype=float, copy=True)
    for _ in range(maxiter):
        f, df = fun(x)
        neg = f < 0.0
        lo = np.where(neg, x, lo)
        hi = np.where(neg, hi, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            xn = x - f / df
        ok = (xn >= lo) & (xn <= hi)
        xn = np.where(ok, xn, 0.5 * (lo + hi))
        xn = np.where(f == 0.0, x, xn)
        dx = np.abs(xn - x)
        x = xn
        if np.all(dx <= xtol * (1.0 + np.abs(x))):
            break
    return x


def find_root(f, init, args=(), **kwargs):
    """``scipy.optimize.elementwise.find_root`` (Chandrupatla) without its stray warning.

    scipy's post-termination check takes the square root of a negative interpolation
    ratio on some collapsed brackets ("invalid value encountered in sqrt"); the NaN only
    turns the next step into a bisection, so it is silenced here and nowhere else (the
    caller checks ``res.success`` and the values).
    """
    from scipy.optimize import elementwise

    with np.errstate(invalid="ignore"):
        return elementwise.find_root(f, init, args=args, **kwargs)


#: Width of the cell of :func:`bisect_from_estimate`, in float spacings of the estimate
#: (2^2 = 4 spacings; the rod tilt equations' signs are exact to within one spacing).
CELL_BITS = 2

_EXPONENT_BITS = np.int64(0x7FF0000000000000)  # the exponent field of a float64
_CELL_MASK = np.int64(~((1 << CELL_BITS) - 1))  # all bits but the mantissa's last CELL_BITS
_CELL_SCALE = 2.0 ** (CELL_BITS - 52)  # from 2^(e-1), the binade's start, to the cell width


def bisect_from_estimate(fun, fun_df, args, lo, hi, start=None, estimate=None):
    """The sign change of an increasing ``fun(x, *args)``, bisected in a cell at a Newton estimate.

    :func:`bisect_increasing` halves ``[lo, hi]`` about 55 times, evaluating ``fun``
    each time; here a safeguarded Newton iteration (``fun_df(x, *args) -> (f, df)``,
    :func:`safe_newton`) estimates the root x0, and the bisection runs only inside the
    cell ``[k g, (k + 1) g]`` of the fixed grid of spacing ``g`` = :data:`CELL_BITS`
    float spacings of x0's binade that holds x0 (``k = floor(x0 / g)``); the cell is
    verified by the signs of ``fun`` at its ends and moved by one cell where they show
    that the sign change lies next door. The cell's ends are grid points, not values
    derived from x0, so the result, like the plain bisection's, depends only on the
    signs of ``fun`` at fixed points (inputs that differ in the last bit give the same
    tilts where the signs agree). Where the cell cannot be verified (estimate not
    finite, a root at or below the smallest normal float, or more than one cell off)
    the element gets the plain bisection of ``[lo, hi]``.

    Kept hand-written by measurement: on the smooth, twist-spinning and slacking tilt
    equations of the rods (14 blocks of 8192 values, turns 1e-3 to 55, slack 0-30 cm,
    head tension 0-17 N, the bisection's bracket [0, pi/4]) it returns the plain
    bisection's roots bit for bit for 0.27 of its CPU time (the earlier replay of the
    whole bisection from a Newton window took 0.63; ratios of one run; the bench's rod
    rows measure the scenes). 1-D arrays ``lo``,
    ``hi`` and ``args`` of one length (scalars in ``args`` allowed); ``start``, the
    Newton iteration's first point (default: the bracket's midpoint), only saves
    iterations. The iteration stops at steps below 1e-8 relative: Newton's next error
    is then of the order of the rounding (quadratic convergence), and the cell check
    catches any element for which it is not. ``estimate``, if given, is x0 itself (the
    caller's own cheaper estimate; ``fun_df`` and ``start`` are then not used).

    Work saved without changing a sign evaluation's outcome: a moved cell shares one
    end with the first cell (the grid points are exact multiples of ``g``), whose sign
    is known, so only its other end is evaluated; and the last halving, needed only
    where the cell reaches below x0's binade (twice the spacings), runs only on the
    elements whose bracket is not yet two adjacent floats (elsewhere it is a no-op).
    """
    with np.errstate(all="ignore"):
        if estimate is None:
            x_start = 0.5 * (lo + hi) if start is None else start
            x0 = safe_newton(lambda x: fun_df(x, *args), x_start, lo, hi, 1e-8, maxiter=40)
        else:
            x0 = np.array(estimate, dtype=float)  # a contiguous copy (its bits are read)
        # for a positive normal x0 (all others fail the check below): g = 2^(e - 53 +
        # CELL_BITS) for x0 = m 2^e, 1/2 <= m < 1 (the exponent bits, scaled by a power
        # of two), and a = floor(x0 / g) g (the mantissa's last CELL_BITS bits cleared)
        bits = x0.view(np.int64)
        g = (bits & _EXPONENT_BITS).view(float) * _CELL_SCALE
        a = (bits & _CELL_MASK).view(float)
        b = a + g
        left = fun(a, *args) > 0
        right = ~(fun(b, *args) > 0)
        right &= ~left  # (both: the cell moves left)
        np.subtract(a, g, out=a, where=left)
        np.copyto(a, b, where=right)
        b = a + g
        ok = np.isfinite(x0) & (x0 >= np.finfo(float).tiny) & (a >= lo) & (b <= hi)
        moved = np.flatnonzero(left | right)
        if moved.size:  # a moved cell is verified again (it may be off by more)
            sub = tuple(v[moved] if np.ndim(v) else v for v in args)
            # moved left: its right end is the old left end (sign > 0 known); moved
            # right: its left end is the old right end (sign <= 0 known)
            to_left = left[moved]
            up = fun(np.where(to_left, a[moved], b[moved]), *sub) > 0
            ok[moved] &= up != to_left
        mid = np.empty_like(a)
        for _ in range(CELL_BITS):  # 2^CELL_BITS spacings (twice that below the binade)
            np.add(a, b, out=mid)
            mid *= 0.5
            up = fun(mid, *args) > 0
            np.copyto(b, mid, where=up)
            np.invert(up, out=up)
            np.copyto(a, mid, where=up)
        out = np.add(a, b, out=mid)
        out *= 0.5
        adjacent = out == a
        adjacent |= out == b
        wide = np.flatnonzero(~adjacent)
        if wide.size:  # the last halving (below the binade), where it is not a no-op
            sub = tuple(v[wide] if np.ndim(v) else v for v in args)
            aw, bw = a[wide], b[wide]
            mw = 0.5 * (aw + bw)
            up = fun(mw, *sub) > 0
            aw, bw = np.where(up, aw, mw), np.where(up, mw, bw)
            ow = 0.5 * (aw + bw)
            out[wide] = ow
            adjacent[wide] = (ow == aw) | (ow == bw)
        ok &= adjacent
    if not np.all(ok):
        bad = ~ok
        sub = tuple(v[bad] if np.ndim(v) else v for v in args)
        out[bad] = bisect_increasing(lambda x: fun(x, *sub), lo[bad], hi[bad])
    return out


#: Gauss-Legendre rules of :func:`cumulative_integrals` (8 points, and 4 for the error estimate).
_GL8 = np.polynomial.legendre.leggauss(8)
_GL4 = np.polynomial.legendre.leggauss(4)


def _gl_panels(fun, lo, hi):
    """8-point integrals, 4-point error estimates and ``int |f|`` of every panel."""
    x8, w8 = _GL8
    x4, w4 = _GL4
    half, mid = 0.5 * (hi - lo), 0.5 * (hi + lo)
    nodes = np.concatenate([(mid[:, None] + half[:, None] * x8).ravel(),
                            (mid[:, None] + half[:, None] * x4).ravel()])
    f = np.asarray(fun(nodes), float)
    m, n8 = f.shape[0], lo.size * 8
    f8 = f[:, :n8].reshape(m, lo.size, 8)
    i8 = (f8 @ w8) * half
    err = np.abs(i8 - (f[:, n8:].reshape(m, lo.size, 4) @ w4) * half)
    return i8, err, (np.abs(f8) @ w8) * half


def cumulative_integrals(fun, breaks, rtol=1e-12, max_depth=60, max_panels=20000, atol=0.0):
    """Running integrals ``int_{b_0}^{b_j} f ds`` of a vector integrand at sorted breakpoints.

    Adaptive composite Gauss-Legendre quadrature: every panel between two
    breakpoints is integrated with 8 points; the 4-point rule gives a
    (pessimistic) error estimate. A panel is accepted when its estimate is below
    its share of ``rtol`` times the integral of ``|f|`` (in proportion to its
    width), or of ``atol`` if that is larger; the rest are halved, level by
    level, until the estimates of all panels together are below that budget
    (so rounding noise of the integrand does not force endless halving), at
    most ``max_depth`` times and while fewer than ``max_panels`` panels are
    pending. The 8-point rule is exact for
    polynomials of degree 15, so smooth integrands converge at once, and a jump
    of a twisting-rate callable is localised by the halving.

    Kept hand-written by measurement: for the twist and writhe integrals of
    the k = 0 rough helix on its 860-point internal grid, scipy.integrate.
    tanhsinh (vectorised over the panels, rtol 1e-12) takes 177x the time for
    results 2e-14 apart.

    Parameters
    ----------
    fun : callable
        ``fun(x) -> array (m, x.size)``, vectorised over a 1-D array x.
    breaks : array_like
        Strictly increasing breakpoints (1-D, at least one).
    atol : float or array of shape (m,)
        Absolute error budget per component over the whole range (default 0).
        Give it when the range is a short piece of a longer integral (the
        relative budget of a tiny piece is below the rounding noise of the
        integrand, and the halving would run to ``max_depth``).

    Returns
    -------
    numpy.ndarray, shape (m, breaks.size)
        The integrals from ``breaks[0]``, 0 in the first column.
    """
    b = np.asarray(breaks, float)
    if b.size < 2:
        m = np.asarray(fun(b[:1])).shape[0]
        return np.zeros((m, b.size))
    lo, hi = b[:-1], b[1:]
    owner = np.arange(lo.size)
    span = b[-1] - b[0]
    totals = budget = spent = None
    for depth in range(max_depth + 1):
        i8, err, absint = _gl_panels(fun, lo, hi)
        if totals is None:
            totals = np.zeros((i8.shape[0], b.size - 1))
            budget = np.maximum(rtol * np.sum(absint, axis=1), atol)
            spent = np.zeros(i8.shape[0])
        ok = np.all(err <= (budget / span)[:, None] * (hi - lo), axis=0)
        ok |= ~np.all(np.isfinite(i8), axis=0)  # NaN/inf: no refinement helps; caller checks
        if (depth == max_depth or np.count_nonzero(~ok) > max_panels
                or np.all(spent + err.sum(axis=1) <= budget)):
            ok[:] = True
        np.add.at(totals, (slice(None), owner[ok]), i8[:, ok])
        spent = spent + np.where(np.isfinite(err), err, 0.0)[:, ok].sum(axis=1)
        if np.all(ok):
            break
        lo, hi, owner = lo[~ok], hi[~ok], owner[~ok]
        mid = 0.5 * (lo + hi)
        lo, hi, owner = (np.concatenate([lo, mid]), np.concatenate([mid, hi]),
                         np.concatenate([owner, owner]))
    return np.concatenate([np.zeros((totals.shape[0], 1)), np.cumsum(totals, axis=1)], axis=1)


def first_crossing(s, g, g_at, xtol=1e-15, rtol=1e-13):
    """First s where ``g`` (tabulated on grid ``s``) turns positive, refined by brentq.

    ``g_at(s_scalar)`` evaluates the same function anywhere. Returns None if
    ``g <= 0`` on the whole grid, ``s[0]`` if already positive there: pass a
    grid that starts where the search must start, or a crossing before
    ``s[0]`` is reported at ``s[0]``. The refinement is scipy's brentq on the
    first bracketing grid interval (bounded: at most 100 iterations); if
    ``g_at`` does not reproduce the sign change (grid rounding), the right
    end of that interval is returned.
    """
    g = np.asarray(g, float)
    idx = np.flatnonzero(g > 0)
    if idx.size == 0:
        return None
    i = int(idx[0])
    if i == 0:
        return float(s[0])
    a, b = float(s[i - 1]), float(s[i])
    try:
        from scipy.optimize import brentq

        return float(brentq(g_at, a, b, xtol=xtol, rtol=rtol))
    except (ValueError, RuntimeError):  # sign change not reproduced, or no convergence
        return b


def finite_difference(fun, x, h, lo, hi):
    """4th-order finite-difference derivative of a vectorised ``fun`` on [lo, hi].

    Central 5-point stencil inside, one-sided 5-point stencils within 2 h of
    the ends (so ``fun`` is never evaluated outside [lo, hi]). Five
    evaluations per point, no iteration.

    Kept hand-written by measurement: for ``P(s) = 16 + 4 sin(2 pi s / 0.16 m)``
    mm on 2001 points of [0, 0.2 m] (the designed-helix scene) with
    ``h = 1e-4 s_end``, scipy.differentiate.derivative (one-sided within 2 mm
    of the ends) takes 17x the time and is less accurate
    at its defaults (3e-9 vs 2e-12 relative to the exact derivative).
    """
    x = np.asarray(x, float)
    d = np.empty_like(x)
    mid = (x - 2 * h >= lo) & (x + 2 * h <= hi)
    left = (~mid) & (x - 2 * h < lo)
    right = (~mid) & ~left
    if np.any(mid):
        xm = x[mid]
        d[mid] = (fun(xm - 2 * h) - 8 * fun(xm - h) + 8 * fun(xm + h) - fun(xm + 2 * h)) / (12 * h)
    for sel, sgn in ((left, 1.0), (right, -1.0)):
        if np.any(sel):
            xs = x[sel]
            hh = sgn * h
            d[sel] = (-25 * fun(xs) + 48 * fun(xs + hh) - 36 * fun(xs + 2 * hh)
                      + 16 * fun(xs + 3 * hh) - 3 * fun(xs + 4 * hh)) / (12 * hh)
    return d


def table_cubic(x, k, nodes, *values):
    """Each of ``values`` at x by Lagrange interpolation through the four table rows
    ``j..j+3`` around the interval ``[nodes[k], nodes[k+1]]`` (x and k 1-D; a table of
    fewer rows: through all of them). ``nodes`` need not be ascending (the branch tables
    run down in tension). The starts of the plectoneme solvers: within 2e-5 of the
    root where linear interpolation between two rows is within 4e-4 (hard-core branch
    table, b from 0.3 to 3 times the seed set's).
    """
    j = np.clip(k - 1, 0, max(nodes.size - 4, 0))[:, None] + np.arange(min(4, nodes.size))
    xs = nodes[j]
    basis = np.ones(j.shape)
    for m in range(j.shape[1]):
        for q in range(j.shape[1]):
            if q != m:
                basis[:, m] *= (x - xs[:, q]) / (xs[:, m] - xs[:, q])
    return tuple(np.sum(basis * v[j], axis=1) for v in values)


def stacked(*series):
    """Chebyshev coefficient columns of several series, zero-padded to one length.

    ``chebval(t, stacked(a, b))`` is ``(chebval(t, a), chebval(t, b))`` bit for bit (a
    leading zero coefficient leaves Clenshaw's recurrence exactly as it was: ``c - 0``
    and ``c + 0 x`` are c) in one recurrence over both, half the calls.
    """
    out = np.zeros((max(c.size for c in series), len(series)))
    for k, c in enumerate(series):
        out[:c.size, k] = c
    return out


def chebval_rows(t, coefficients):
    """The series of the columns of ``coefficients`` (:func:`stacked`) at t: ``(m, t.size)``.

    The Chebyshev polynomials ``T_k(t)`` as rows and one matrix product for all series,
    instead of numpy's ``chebval`` (Clenshaw, three temporaries per degree and series
    block). The rows double in blocks by the product rule ``T_{m+j} = 2 T_m T_j - T_{m-j}``
    (j = 1..m: two in-place operations per block, 3 log2(degree) array calls in all,
    instead of two per degree by the three-term recurrence). Kept hand-written by
    measurement: for 2 series of degree 32 it takes about 0.8 of the three-term rows'
    CPU at 2049 points and 0.35 at 129 (there the per-call overhead dominates), and half
    of ``chebval``'s or less. The rows' rounding (against ``cos(k arccos t)`` in long
    double, 2049 points on [-1, 1]): at most 11 ulp to degree 33 (the three-term rows:
    25), 33 at 64 and 104 at 128 (three-term: 28 and 41); the sums stay within
    ``(degree + 1) eps sum|c|`` of ``chebval`` (tested at degrees 0-128).
    """
    t = np.asarray(t, dtype=float)
    n = coefficients.shape[0]
    rows = np.empty((n, t.size))
    rows[0] = 1.0
    if n > 1:
        rows[1] = t
    m = 1  # rows 0..m are filled
    while m + 1 < n:
        k = min(m, n - 1 - m)  # the block m+1 .. m+k from T_1..T_k and T_{m-1}..T_{m-k}
        block = rows[m + 1:m + 1 + k]
        np.multiply(rows[1:k + 1], 2.0 * rows[m], out=block)
        block -= rows[m - k:m][::-1]
        m += k
    return single_thread_product(coefficients.T, rows)


#: multiply-adds per matrix product that BLAS libraries run on one thread: OpenBLAS
#: threads a product from 65,536 x its ``GEMM_MULTITHREAD_THRESHOLD`` (4 by default; 1 is
#: its lowest setting, so this bound holds for every build)
SINGLE_THREAD_PRODUCT = 65536


def single_thread_product(a, b):
    """``a @ b`` (a: ``(m, n)``, b: ``(n, N)``, ``m >= 2``) in column blocks of ``b``, each
    product below :data:`SINGLE_THREAD_PRODUCT` multiply-adds, so that BLAS never starts
    its threads.

    Kept by measurement (OpenBLAS 0.3.31, 2 cores): the series rows of a branch table,
    ``(4 x 33) @ (33 x 4097)``, ran threaded and cost 3.8x the CPU of one thread (the wall
    time 1.2x), and the idle BLAS threads then spin until OpenBLAS's thread timeout,
    which doubled the CPU of the whole free-energy fit that built the table (and of
    whatever ran next within the timeout). In blocks it costs 1.1-1.3x the
    single-thread product. Each column is the same dot products as in the whole product;
    the sums agree with ``a @ b`` to a few ulp (the micro-kernel of the last, narrower
    block may order them differently).
    """
    width = max(SINGLE_THREAD_PRODUCT // (a.shape[0] * a.shape[1]), 1)
    if b.shape[1] <= width:
        return a @ b
    out = np.empty((a.shape[0], b.shape[1]))
    for start in range(0, b.shape[1], width):
        np.matmul(a, b[:, start:start + width], out=out[:, start:start + width])
    return out
