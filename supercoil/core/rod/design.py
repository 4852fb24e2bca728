"""Example II: the twisting/slacking schedule that produces a chosen pitch profile.

Float-only kernel (SI units), docs/theory/design.md, paper "Example II" [eq sinp].

Inverting the ODE
-----------------
Given the pitch P(s) along the finished helix (one strand, s from the head),
the tilt and its slope follow from [eq alpha def]:

    alpha(s) = arctan(2 pi r / P(s)),
    d alpha/ds = -2 pi r P'(s) / (P^2 + 4 pi^2 r^2).

[eq da/ds] is linear in k, so it can be solved for the twisting rate at the
moment the helix end passes s (slack S = 2 s), with ``c = cos 2 alpha``:

    k(2 s) = [sin 2a - (d alpha/ds) B (L - 2 s) (c^3 - 1) / (C c^2)] / (2 r).

The schedule then is

    N_0  = (B/C) (1 - cos 2a0) tan 2a0 L / (4 pi r)          [eq ini]
    N(S) = N_0 + (1/2 pi) int_0^S k dS'                      [k]
    T(S) = B/(8 r^2) (1 - c)^2 (2 + c) / c  at s = S/2       [eq tension]

:func:`schedule` evaluates N(S) through the linking identity Lk = Tw + Wr at
S = 2s, ``N = (1/pi) int_0^s (omega + tau) ds' + omega(s) (L - 2s) / 2 pi``
(whose derivative in S is k / 2 pi), by cumulative Simpson quadrature (4th
order) on the grid: its integrand grows like 1/cos 2a near pi/4, while k
itself grows like 1/cos^2 2a.
"""

from __future__ import annotations

import numpy as np
from scipy.integrate import cumulative_simpson

from supercoil.core.numerics import finite_difference as derivative  # noqa: F401 (old home)
from supercoil.core.rod import contact as sc
from supercoil.exceptions import SingularityError

TWO_PI = 2.0 * np.pi


def tilt_from_pitch(pitch, r):
    """alpha = arctan(2 pi r / P) (rad) [eq alpha def]."""
    return np.arctan2(TWO_PI * r, np.asarray(pitch, float))


def tilt_slope(pitch, dpitch_ds, r):
    """d alpha/ds = -2 pi r P' / (P^2 + 4 pi^2 r^2) (1/m)."""
    P = np.asarray(pitch, float)
    return -TWO_PI * r * np.asarray(dpitch_ds, float) / (P * P + (TWO_PI * r) ** 2)


def twist_rate_for(s, alpha, dalpha_ds, r, L, B, C):
    """k(2s) (rad/m) that makes [eq da/ds] produce the slope ``dalpha_ds`` at s.

    Implements docs/theory/design.md (eq da/ds).
    """
    c = np.cos(2.0 * alpha)
    return (np.sin(2.0 * alpha)
            - dalpha_ds * B * (L - 2.0 * np.asarray(s, float)) * (c**3 - 1.0) / (C * c * c)) \
        / (2.0 * r)


def schedule(s, pitch, dpitch_ds, r, L, B, C, cos2a_min=sc.COS2A_MIN):
    """The schedule (N, T versus S) for a pitch profile tabulated on the grid ``s`` (m).

    Returns
    -------
    dict of numpy.ndarray
        ``s, slack, pitch, alpha, dalpha_ds, twist_rate, turns, tension`` in SI
        (turns unsigned: N >= 0 by construction).

    Raises
    ------
    SingularityError
        If the pitch is not positive and finite, or ``P <= 2 pi r`` somewhere
        (alpha >= pi/4, where the hard-contact helix does not exist).
    """
    s = np.asarray(s, float)
    P = np.asarray(pitch, float)
    if not np.all(np.isfinite(P)) or np.any(P <= 0):
        raise SingularityError("designed pitch P(s) must be finite and positive on the grid "
                               "(alpha -> 0 where P -> infinity ends the helix)")
    alpha = tilt_from_pitch(P, r)
    if np.any(P <= TWO_PI * r) or np.any(np.cos(2 * alpha) < cos2a_min):
        i = int(np.argmin(P))
        raise SingularityError(
            f"designed pitch P = {P[i]:.6g} m at s = {s[i]:.6g} m is <= 2 pi r = "
            f"{TWO_PI * r:.6g} m: alpha reaches the limit pi/4 where the tension diverges"
        )
    da = tilt_slope(P, dpitch_ds, r)
    k = twist_rate_for(s, alpha, da, r, L, B, C)
    # N(S) from the linking identity Lk = Tw + Wr at S = 2s (the integral of
    # dN/dS = k/2pi, rearranged): N = (1/pi) int_0^s (omega + tau) ds'
    # + omega(s) (L - 2s) / 2pi. Its integrand grows like 1/cos 2a near pi/4,
    # where k itself grows like 1/cos^2 2a, so it integrates far more accurately
    # (cumulative Simpson, 4th order); at s = 0 it is N_0 of [eq ini].
    omega = sc.twist_density(alpha, r, B, C)
    integrand = omega + np.sin(alpha) * np.cos(alpha) / r
    if s.size >= 3:
        helix = cumulative_simpson(integrand, x=s, initial=0.0)
    else:
        helix = np.concatenate(([0.0], np.cumsum(0.5 * (integrand[1:] + integrand[:-1])
                                                 * np.diff(s))))
    turns = helix / np.pi + omega * (L - 2.0 * s) / TWO_PI
    return {
        "s": s,
        "slack": 2.0 * s,
        "pitch": P,
        "alpha": alpha,
        "dalpha_ds": da,
        "twist_rate": k,
        "turns": turns,
        "tension": sc.tension(alpha, r, B),
    }
