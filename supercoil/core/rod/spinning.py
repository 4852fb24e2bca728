r"""Twist-spinning: a short smooth helix held by a head tension T'. Float-only kernel.

docs/theory/spinning.md, paper Discussion and Appendix F [f1, 11, f4, f5].

Set-up and what is held fixed
-----------------------------
A rod of length L, twisted by N turns (n = N / L), has both ends held a
distance ``L - S`` apart (S, the slack, is fixed). A double helix of rod
length S' (both strands; S' << L) forms at the head, where a tension T' pulls
along the helix axis; the head may rotate freely. The two straight tails, of
length ``(L - S')/2`` each, run from the ends to the helix and make the angle
beta with the axis, so that (geometry of the isosceles V)

    sin(beta) = (L - S) / (L - S')                                          [11]

and the head sits at the height

    h = (S'/2) cos(alpha) + ((L - S')/2) cos(beta)
      = (S'/2) cos(alpha) + (L - S) / (2 tan(beta)).

(the paper's [f1] prints the helix part as ``S'/cos(alpha)``; the height of a
helix of strand length S'/2 and tilt alpha is ``(S'/2) cos(alpha)``, and only
this form reproduces the paper's own [f4], see below.) The surface is smooth,
so the twist density omega is uniform over the whole rod; the linking number
``N = [omega L + tau S'] / 2 pi`` [Eq Lk=Tw+Wr] gives
``omega = (2 pi N - tau S') / L``. Held fixed: L, N, S, T' and r (hard contact
R = r). Free: alpha and S' (beta follows from [11]). The energy is

    E_p(alpha, S') = (1/2) B kappa^2 S' + (1/2) C omega^2 L - T' h.

Stationarity, derived
---------------------
With ``d omega/d alpha = -tau_alpha S'/L`` and ``d omega/dS' = -tau/L``:

* dE_p/d alpha = S' [B kappa kappa_alpha - C omega tau_alpha] + T' (S'/2) sin(alpha) = 0;
* dE_p/dS' = (1/2) B kappa^2 - C omega tau - T' dh/dS' = 0, where
  ``d/dS' [((L - S')/2) cos beta] = d/dS' [(1/2) sqrt((L - S')^2 - (L - S)^2)]
  = -1 / (2 cos beta)``, so ``dh/dS' = (cos(alpha) - sec(beta)) / 2``.

In the limit S'/L -> 0, ``omega -> 2 pi n`` and these become the paper's

    B kappa kappa_alpha - 2 pi C n tau_alpha + (1/2) T' sin(alpha) = 0        [f4]
    B kappa^2 - 4 pi C n tau - T' (cos(alpha) - sec(beta)) = 0                [f5]

(their F is T'). With kappa = sin^2(a)/r, tau = sin(a)cos(a)/r, [f4] is

    G(alpha) = B sin^2(a) sin(2a) / r^2 + T' sin(a) / 2 - 2 pi C n cos(2a) / r = 0,

which increases strictly on [0, pi/4] from ``-2 pi C n / r`` to a positive
value: one root, found by bisection. Then [f5] gives beta explicitly,

    sec(beta) = cos(alpha) + 2 T_s / T',   T_s = 2 pi C n tau - B kappa^2 / 2 > 0,

(T_s is the smooth-helix tension formula of docs/theory/smooth.md#tension at omega = 2 pi n).
An equilibrium with tails needs ``sec(beta) >= 1``, i.e.
``2 T_s >= T' (1 - cos(alpha))``. This always holds: by [f4],
``2 pi C n = (B kappa kappa_alpha + T' sin(a)/2) / tau_alpha``, so
``2 T_s / T' >= sin^2(a) cos(a) / cos(2a)`` (the B terms are the positive
hard-contact tension), and ``cos(a) / cos(2a) >= 1 / (1 + cos(a))`` because
``1 + cos(a) - cos^2(a) >= 0``. Large T' only drives beta -> 0 and alpha -> 0
(``alpha ~ 4 pi C n / (r T')``). Rounding and underflow (|N| ~ 1e-300) can
still produce a tiny negative T_s or ``sec(beta) - 1``; :func:`spinning_state`
clamps both at 0 on the strength of this proof.

T' = 0 recovers the twist-slacking helix
----------------------------------------
At T' = 0, [f4] reads ``B kappa kappa_alpha = C (2 pi n) tau_alpha``, which is
(GE1)/(HC) with the straight rod's twist ``omega = 2 pi N / L``: exactly [eq ini],
the tilt alpha_0 of the first helix formed by twist-slacking (S -> 0). [f5]
with T' -> 0+ gives ``sec(beta) = cos(alpha) + 2 T_s / T' -> infinity``:
beta -> pi/2, the tails are collinear and the ends meet the helix as in the
twist-slacking scene. For T' > 0 the term ``T' sin(alpha) / 2 > 0`` moves the
root of [f4] to a smaller alpha: the pitch grows with T' (paper figure fbp).
"""

from __future__ import annotations

import numpy as np

from supercoil.core.numerics import bisect_from_estimate
from supercoil.core.rod import contact as sc
from supercoil.core.rod.smooth import BLOCK
from supercoil.exceptions import NoHelixError

TWO_PI = 2.0 * np.pi


def spinning_tilt(turns_abs, head_tension, r, L, B, C):
    """Root alpha of [f4] (rad), broadcast over |N| and T' (N)."""
    n, Tp = np.broadcast_arrays(np.asarray(turns_abs, float) / L, np.asarray(head_tension, float))
    if np.any(~(n > 0)):
        raise NoHelixError("turns N = 0: no twist, no helix (twist-spinning needs |N| > 0)")
    if np.any(Tp < 0) or not np.all(np.isfinite(Tp)):
        raise NoHelixError("head tension T' must be finite and >= 0 (a push buckles the head)")

    out = np.empty(n.shape)
    flat = out.reshape(-1)
    for start in range(0, n.size, BLOCK):  # blocks: bounded temporaries
        nb, Tb = n.flat[start:start + BLOCK], Tp.flat[start:start + BLOCK]
        flat[start:start + BLOCK] = bisect_from_estimate(
            _G, _G_df, (nb, Tb, r, B, C), np.zeros(nb.shape), np.full(nb.shape, sc.QUARTER_PI),
            start=_small_tilt(Tb * r**2 / (4.0 * B), np.pi * C * nb * r / B))
    return out[()] if out.ndim == 0 else out


def _small_tilt(p, q):
    """Root of the small-tilt limit ``a^3 + p a = q`` of [f4] (p, q >= 0; Cardano), capped
    below pi/4: a start for Newton (sin a ~ a, sin 2a ~ 2a, cos 2a ~ 1), nothing more."""
    with np.errstate(all="ignore"):
        d = np.sqrt(0.25 * q * q + (p / 3.0) ** 3)
        a = np.cbrt(0.5 * q + d) + np.cbrt(0.5 * q - d)
    return np.where(np.isfinite(a), np.clip(a, 0.0, 0.99 * sc.QUARTER_PI), 0.5 * sc.QUARTER_PI)


def _G(a, n, Tp, r, B, C):
    """[f4] as G(alpha) of the module doc (n = |N| / L), as it is bisected."""
    sa = np.sin(a)  # once: the same floats as two calls
    return B * sa**2 * np.sin(2 * a) / r**2 + 0.5 * Tp * sa - TWO_PI * C * n * np.cos(2 * a) / r


def _G_df(a, n, Tp, r, B, C):
    """:func:`_G` and its derivative in alpha (for the Newton estimate)."""
    # two sines, the double angles from them: an estimate only (the signs come from _G)
    sa, ca = np.sin(a), np.cos(a)
    s2, c2 = 2.0 * sa * ca, (ca - sa) * (ca + sa)
    f = B * sa**2 * s2 / r**2 + 0.5 * Tp * sa - TWO_PI * C * n * c2 / r
    df = (B * (2.0 * sa * ca * s2 + 2.0 * sa**2 * c2) / r**2 + 0.5 * Tp * ca
          + 2.0 * TWO_PI * C * n * s2 / r)
    return f, df


def _h0(a, rhs):
    """[eq ini] as :func:`supercoil.core.rod.contact.initial_tilt` bisects it."""
    return sc.y_of_alpha(a) * np.sin(2.0 * a) - rhs * np.cos(2.0 * a)


def _h0_df(a, rhs):
    """:func:`_h0` and its derivative (Newton estimate; double angles from sin a, cos a)."""
    sa, ca = np.sin(a), np.cos(a)
    s2, c2, y = 2.0 * sa * ca, (ca - sa) * (ca + sa), 2.0 * sa * sa
    return y * s2 - rhs * c2, 2.0 * (s2 * s2 + y * c2 + rhs * s2)


def slacking_tilt(turns_abs, r, L, B, C):
    """:func:`supercoil.core.rod.contact.initial_tilt` (alpha_0 of [eq ini]) in blocks.

    The tilts of the plain bisection by :func:`supercoil.core.numerics.bisect_from_estimate`.

    Raises
    ------
    NoHelixError
        If some ``|N_0| <= 0``.
    """
    n = np.asarray(turns_abs, float)
    if np.any(~(n > 0)):
        sc.initial_tilt(n, r, L, B, C)  # raises, with its message
    out = np.empty(n.shape)
    flat = out.reshape(-1)
    for start in range(0, n.size, BLOCK):
        rhs = (C / B) * 4.0 * np.pi * r * n.flat[start:start + BLOCK] / L
        flat[start:start + BLOCK] = bisect_from_estimate(
            _h0, _h0_df, (rhs,), np.zeros(rhs.shape), np.full(rhs.shape, sc.QUARTER_PI),
            start=_small_tilt(0.0, 0.25 * rhs))
    return out[()] if out.ndim == 0 else out


def spinning_state(turns_abs, head_tension, r, L, B, C):
    """alpha, beta (rad), pitch (m), omega = 2 pi n (rad/m) and T_s (N); see module doc.

    Raises
    ------
    NoHelixError
        N = 0 or T' < 0. (``sec beta >= 1`` holds for every root, see the module
        doc; rounding below it is clamped, so no input closes the tails.)
    """
    alpha = spinning_tilt(turns_abs, head_tension, r, L, B, C)
    Tp = np.broadcast_to(np.asarray(head_tension, float), alpha.shape)
    omega = TWO_PI * np.broadcast_to(np.asarray(turns_abs, float), alpha.shape) / L
    sa = np.sin(alpha)  # once: the same floats as one call per use
    kappa = sa**2 / r
    tau = sa * np.cos(alpha) / r
    # T_s > 0 and sec(beta) >= 1 for every root of [f4] (module doc); only rounding
    # or underflow (|N| ~ 1e-300) can push them below, so clamp instead of failing
    Ts = np.maximum(C * omega * tau - 0.5 * B * kappa**2, 0.0)
    # x = sec(beta) - 1 = 2 T_s / T' - (1 - cos alpha), written without cancellation
    # at small alpha; then 1 - cos(beta) = x / (1 + x) gives beta = 2 asin(sqrt(x/(2(1+x)))).
    # T' -> 0+ (even 5e-324 N) overflows 2 T_s / T' to inf: beta = pi/2, the T' = 0 limit.
    with np.errstate(divide="ignore", over="ignore"):
        x = np.where(Tp > 0, 2.0 * Ts / np.where(Tp > 0, Tp, 1.0)
                     - 2.0 * np.sin(0.5 * alpha) ** 2, np.inf)
    x = np.maximum(x, 0.0)
    # x / (2 (1 + x)) as 0.5 / (1 + 1/x): no overflow for x near the float maximum
    with np.errstate(invalid="ignore", divide="ignore"):
        beta = np.where(np.isinf(x), 0.5 * np.pi,
                        2.0 * np.arcsin(np.sqrt(0.5 / (1.0 + 1.0 / x))))
    return {
        "alpha": alpha,
        "beta": beta,
        "pitch": TWO_PI * r / np.tan(alpha),
        "omega": omega,
        "slacking_tension": Ts,
    }


def exact_energy(alpha, S_helix, turns_abs, head_tension, slack, r, L, B, C):
    """E_p(alpha, S') of the module doc without the S'/L -> 0 limit (J); for checks."""
    sa = np.sin(alpha)  # once: the same floats as one call per use
    kappa = sa**2 / r
    tau = sa * np.cos(alpha) / r
    omega = (TWO_PI * turns_abs - tau * S_helix) / L
    h = 0.5 * S_helix * np.cos(alpha) + 0.5 * np.sqrt((L - S_helix) ** 2 - (L - slack) ** 2)
    return 0.5 * B * kappa**2 * S_helix + 0.5 * C * omega**2 * L - head_tension * h
