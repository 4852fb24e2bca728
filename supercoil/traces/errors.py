"""Standard error of the mean of serially correlated frames (blocking).

Consecutive tracker frames of a tethered bead are correlated: the bead's
Brownian motion relaxes with the trap's time constant (tens of ms at pN forces),
so ``std / sqrt(n)`` underestimates the error of a plateau mean by the square
root of the number of frames per correlation time. :func:`blocking_error`
estimates the true error with the blocking (renormalisation-group) method of
H. Flyvbjerg and H. G. Petersen, "Error estimates on averages of correlated
data", J. Chem. Phys. 91, 461 (1989): the series is repeatedly halved by
averaging neighbouring pairs; the naive error estimate of the blocked series
grows with the block size and levels off once blocks are longer than the
correlation time. The block size is chosen automatically with the criterion of
R. M. Lee, G. J. Conduit, N. Nemec, P. Lopez Rios and N. D. Drummond,
Phys. Rev. E 83, 066706 (2011), Eq. 14, in the form used by pyblock (J. Spencer,
``pyblock.blocking.find_optimal_block``, read there): the smallest block size
``B = 2**k`` with ``B**3 > 2 n (SE_k / SE_0)**4``. See docs/theory/recordings.md#error.

The analysis is float-only (numpy); a pint quantity is analysed on its
magnitude and the results carry its unit.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["BlockingResult", "blocking_error", "blocking_levels", "error_from_inefficiency",
           "pooled_inefficiency"]


class BlockingResult(NamedTuple):
    """Result of :func:`blocking_error` (same unit as the data)."""

    mean: float
    #: standard error of the mean with the correlation taken into account
    error: float
    #: naive ``std / sqrt(n)`` (uncorrelated frames)
    naive_error: float
    #: chosen block size in frames (a power of two)
    block_size: int
    #: ``(error / naive_error)**2``: the statistical inefficiency, about
    #: ``2 tau_int`` in frames (1 for uncorrelated frames)
    inefficiency: float
    #: False when no blocking level met the criterion (series too short for
    #: its correlation time); ``error`` is then the largest level estimate
    converged: bool


def blocking_levels(x):
    """Blocking transformation of Flyvbjerg & Petersen (1989), Eqs. 20-27.

    Parameters
    ----------
    x : array_like, 1-D, finite, at least 2 values

    Returns
    -------
    sizes : ndarray of int
        Block size (frames per block) of every level, ``1, 2, 4, ...``.
    se : ndarray of float
        Naive standard error ``sqrt(c0 / (n' - 1))`` of the blocked series at
        every level (``n'`` blocks, ``c0`` their biased variance), the
        estimate of the error of the mean at that level.
    se_err : ndarray of float
        Its own standard error, ``se / sqrt(2 (n' - 1))`` (Gaussian data).
    """
    x = np.asarray(x, dtype=float)
    if x.ndim != 1 or x.size < 2:
        raise ValueError(f"blocking needs a 1-D series of at least 2 values, got shape {x.shape}")
    if not np.all(np.isfinite(x)):
        raise ValueError("blocking needs finite values")
    sizes, se, se_err = [], [], []
    size = 1
    while x.size >= 2:
        n = x.size
        c0 = np.var(x)  # biased, as in Flyvbjerg & Petersen Eq. 24
        s = np.sqrt(c0 / (n - 1))
        sizes.append(size)
        se.append(s)
        se_err.append(s / np.sqrt(2.0 * (n - 1)))
        m = n // 2
        x = 0.5 * (x[: 2 * m : 2] + x[1 : 2 * m : 2])
        size *= 2
    return np.array(sizes), np.array(se), np.array(se_err)


def blocking_error(x) -> BlockingResult:
    """Mean of a correlated series and its standard error by blocking.

    Parameters
    ----------
    x : array_like or Quantity, 1-D
        The frames of one plateau (at least 2 finite values). For a quantity,
        ``mean``, ``error`` and ``naive_error`` carry its unit.

    Returns
    -------
    BlockingResult
        ``error`` is the blocking estimate at the block size chosen by the
        criterion of Lee et al. (2011), Eq. 14. If no level meets it (the
        plateau holds fewer than about ``2 (2 tau)^2`` frames per correlation
        time ``tau`` ...), ``converged`` is False and ``error`` is the largest
        estimate over the levels with at least 4 blocks (a conservative
        value; the caller should warn).

    Notes
    -----
    For uncorrelated frames the criterion picks ``B`` just above
    ``(2 n)**(1/3)`` and the result agrees with ``std(ddof=1)/sqrt(n)`` within
    its own statistical error ``~ error / sqrt(2 n / B)``. For an AR(1) series
    with lag-1 correlation ``phi`` it tends to ``naive * sqrt((1 + phi) / (1 - phi))``
    (both tested in tests/traces).
    """
    unit = getattr(x, "units", None)
    if unit is not None:  # a pint quantity: the same analysis on the magnitude, in its unit
        r = blocking_error(np.asarray(x.magnitude, dtype=float))
        return r._replace(mean=r.mean * unit, error=r.error * unit,
                          naive_error=r.naive_error * unit)
    x = np.asarray(x, dtype=float)
    sizes, se, _ = blocking_levels(x)
    n = x.size
    mean = float(np.mean(x))
    naive = float(se[0])
    if naive == 0.0:
        return BlockingResult(mean, 0.0, 0.0, 1, 1.0, True)
    ratio = se / naive
    ok = sizes.astype(float) ** 3 > 2.0 * n * ratio**4
    blocks = n // sizes
    usable = blocks >= 4
    hit = np.flatnonzero(ok & usable)
    if hit.size:
        k = int(hit[0])
        converged = True
    else:
        k = int(np.argmax(np.where(usable, se, -np.inf))) if usable.any() else 0
        converged = False
    err = float(se[k])
    return BlockingResult(mean, err, naive, int(sizes[k]), (err / naive) ** 2, converged)


def pooled_inefficiency(series, c=5.0):
    """Statistical inefficiency shared by several short series (plateaus of one bead and height).

    The autocovariance of every series about its own mean is summed lag by lag
    over the series (``sum_i sum_j d_ij d_i(j+t) / sum_i (n_i - t)``), and the
    inefficiency ``g(M) = 1 + 2 sum_(t=1..M) rho(t)`` is summed up to the
    window ``M`` of Sokal's automatic windowing: the smallest ``M >= c g(M)``
    (A. D. Sokal, "Monte Carlo methods in statistical mechanics", NATO ASI
    Series B 361, 131 (1997); ``c = 5`` as emcee's ``integrated_time``). The
    bias of subtracting each series' own mean (every autocovariance is low by
    the variance of that mean, ``sigma**2 g / n``) is removed to first order:
    ``g = g_hat / (1 - (2 M + 1) / n + g_hat / n)`` with ``n`` the series'
    mean length (docs/theory/recordings.md#error).

    Parameters
    ----------
    series : sequence of 1-D arrays
        Finite values, each at least 4 long.
    c : float
        Window factor.

    Returns
    -------
    g : float
        The inefficiency (>= 1/n); the error of a series' mean is
        ``std(ddof=1) / sqrt(n) * sqrt(g (n - 1) / (n - g))``
        (:func:`error_from_inefficiency`).
    window : int
        ``M``.
    converged : bool
        False if no window up to a quarter of the shortest series met the
        criterion (``g`` is then the value at that largest window).
    """
    xs = [np.asarray(s, dtype=float) for s in series]
    if not xs or any(s.ndim != 1 or s.size < 4 for s in xs):
        raise ValueError("pooled_inefficiency needs series of at least 4 values")
    m_max = max(1, min(s.size for s in xs) // 4)
    acov = np.zeros(m_max + 1)
    count = np.zeros(m_max + 1)
    for s in xs:
        d = s - s.mean()
        nfft = 1 << int(2 * s.size - 1).bit_length()
        f = np.fft.rfft(d, nfft)
        full = np.fft.irfft(f * np.conj(f), nfft)[: m_max + 1]
        acov += full
        count += s.size - np.arange(m_max + 1)
    acov /= count
    if acov[0] <= 0:
        return 1.0, 0, True
    rho = acov / acov[0]
    g_of_m = 1.0 + 2.0 * np.cumsum(rho[1:])
    m = np.arange(1, m_max + 1)
    ok = np.flatnonzero(m >= c * g_of_m)
    converged = ok.size > 0
    k = int(ok[0]) if converged else m_max - 1
    window, g_hat = int(m[k]), float(g_of_m[k])
    n = float(np.mean([s.size for s in xs]))
    g = g_hat / (1.0 - (2 * window + 1) / n + g_hat / n)
    return max(g, 1.0 / n), window, converged


def error_from_inefficiency(x, g):
    """Standard error of the mean of ``x`` given its statistical inefficiency ``g``.

    ``std(ddof=1)`` of correlated frames is low by ``(n - g) / (n - 1)`` in
    variance, so the error is ``std / sqrt(n) * sqrt(g (n - 1) / (n - g))``.
    """
    x = np.asarray(x, dtype=float)
    n = x.size
    naive = float(np.std(x, ddof=1) / np.sqrt(n))
    g = min(float(g), 0.5 * n)  # (n - g) stays positive
    return naive * np.sqrt(g * (n - 1) / (n - g)), naive
