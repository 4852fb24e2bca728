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
from supercoil.core.rod.smooth import BLOCK, S_MAX, sine_step_converged, small_tilt
from supercoil.exceptions import NoHelixError

TWO_PI = 2.0 * np.pi


def _checked(turns, head_tension, L, signed=False):
    """N and T' broadcast together (float arrays, views), after the checks of [f4].

    ``signed``: N may carry a sign (its magnitude is checked, without a temporary of
    the array's size); else it is |N|.
    """
    n = np.asarray(turns, float)
    t, Tp = np.broadcast_arrays(n, np.asarray(head_tension, float))
    # min(|N|) / L > 0 is all(|N| / L > 0): the division is monotone, a NaN propagates
    if t.size:
        flat = n.reshape(-1)
        least = (np.min([np.min(np.abs(flat[i:i + BLOCK])) for i in range(0, flat.size, BLOCK)])
                 if signed else np.min(flat))
        if not least / L > 0:
            raise NoHelixError("turns N = 0: no twist, no helix (twist-spinning needs |N| > 0)")
    if np.any(Tp < 0) or not np.all(np.isfinite(Tp)):
        raise NoHelixError("head tension T' must be finite and >= 0 (a push buckles the head)")
    return t, Tp


def spinning_tilt(turns_abs, head_tension, r, L, B, C):
    """Root alpha of [f4] (rad), broadcast over |N| and T' (N)."""
    t, Tp = _checked(turns_abs, head_tension, L)
    out = np.empty(t.shape)
    flat = out.reshape(-1)
    for start in range(0, t.size, BLOCK):  # blocks: bounded temporaries
        stop = start + BLOCK
        flat[start:stop] = _tilt_block(t.flat[start:stop] / L, Tp.flat[start:stop], r, B, C)
    return out[()] if out.ndim == 0 else out


def _tilt_block(n, Tp, r, B, C):
    """The root of [f4] on one block (1-D n = |N| / L > 0 and T'), as the bisection finds it."""
    k = TWO_PI * C * n  # the factors of _G, as it forms them
    h = 0.5 * Tp
    x0 = _tilt_estimate(2.0 * B / r**2, h, k / r,
                        small_tilt(Tp * r**2 / (4.0 * B), np.pi * C * n * r / B))
    return bisect_from_estimate(_G_signs, None, (k, h, B, r), np.zeros(n.shape),
                                np.full(n.shape, sc.QUARTER_PI), estimate=x0)


def _tilt_estimate(p, q, k, s):
    """Estimate of the tilt where ``p s^3 c + q s - k (c^2 - s^2) = 0`` (s = sin, c = cos).

    [f4] (p = 2 B / r^2, q = T'/2, k = 2 pi C n / r) and [eq ini] (p = 4, q = 0,
    k = rhs) in the variable s = sin(alpha), with ``c = sqrt(1 - s^2)`` and
    ``cos 2a = 1 - 2 s^2``: Newton's iteration then needs one square root and no
    sine per step, and one arcsine at the end. ``s``: the start (the small-tilt
    root). The bisection's cell check verifies the estimate, so it only saves work;
    the iteration stops at steps below 1e-8 relative (the next error is of the
    order of the rounding), or where a step is NaN (the cell check then fails and
    the element gets the plain bisection).
    """
    s = np.minimum(s, 0.99 * S_MAX)
    with np.errstate(all="ignore"):
        for _ in range(40):
            s2 = s * s
            c = np.sqrt(1.0 - s2)
            s2c = s2 * c
            f = p * s2c
            f += q
            f *= s
            df = 2.0 * s2
            df -= 1.0
            df *= k
            f += df  # p s^3 c + q s - k (1 - 2 s^2)
            df = s2 * s2
            df /= c
            np.multiply(3.0, s2c, out=s2c)
            s2c -= df
            s2c *= p
            s2c += q
            np.multiply(4.0 * s, k, out=df)
            df += s2c  # p (3 s^2 c - s^4 / c) + q + 4 k s
            f /= df  # the step
            if sine_step_converged(s, f):
                break
        return np.arcsin(s)


def _G(a, n, Tp, r, B, C):
    """[f4] as G(alpha) of the module doc (n = |N| / L): the bisected form (the solver
    evaluates it as :func:`_G_signs`, the same floats)."""
    sa = np.sin(a)  # once: the same floats as two calls
    return B * sa**2 * np.sin(2 * a) / r**2 + 0.5 * Tp * sa - TWO_PI * C * n * np.cos(2 * a) / r


def _G_signs(a, k, h, B, r):
    """:func:`_G` with ``k = TWO_PI * C * n`` and ``h = 0.5 * T'`` given: the same
    operations in the same order (the same floats), in place."""
    t = 2.0 * a
    c2 = np.cos(t)
    s2 = np.sin(t, out=t)
    sa = np.sin(a)
    g = np.square(sa)
    g *= B
    g *= s2
    g /= r**2
    sa *= h
    g += sa
    c2 *= k
    c2 /= r
    g -= c2
    return g


def _h0(a, rhs):
    """[eq ini] as :func:`supercoil.core.rod.contact.initial_tilt` bisects it (the solver
    evaluates it as :func:`_h0_signs`, the same floats)."""
    return sc.y_of_alpha(a) * np.sin(2.0 * a) - rhs * np.cos(2.0 * a)


def _h0_signs(a, rhs):
    """:func:`_h0` in place (the same operations in the same order: the same floats)."""
    t = 2.0 * a
    c2 = np.cos(t)
    s2 = np.sin(t, out=t)
    y = np.sin(a)
    np.square(y, out=y)
    y *= 2.0
    y *= s2
    c2 *= rhs
    y -= c2
    return y


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
        flat[start:start + BLOCK] = _slacking_block(n.flat[start:start + BLOCK], r, L, B, C)
    return out[()] if out.ndim == 0 else out


def _slacking_block(t, r, L, B, C):
    """alpha_0 of [eq ini] on one block of |N_0| > 0 (1-D)."""
    rhs = (C / B) * 4.0 * np.pi * r * t / L
    # start: the small-tilt root a^3 = rhs / 4 (small_tilt(0, rhs / 4) without its algebra)
    x0 = _tilt_estimate(4.0, 0.0, rhs, np.cbrt(0.25 * rhs))
    return bisect_from_estimate(_h0_signs, None, (rhs,), np.zeros(rhs.shape),
                                np.full(rhs.shape, sc.QUARTER_PI), estimate=x0)


def spinning_state(turns_abs, head_tension, r, L, B, C):
    """alpha, beta (rad), pitch (m), omega = 2 pi n (rad/m) and T_s (N); see module doc.

    Computed in blocks of :data:`BLOCK` elements (temporaries bounded by the block).

    Raises
    ------
    NoHelixError
        N = 0 or T' < 0. (``sec beta >= 1`` holds for every root, see the module
        doc; rounding below it is clamped, so no input closes the tails.)
    """
    return _in_blocks(turns_abs, head_tension, r, L, B, C, STATE_FIELDS, False)


#: The fields of :func:`spinning_state`, in order.
STATE_FIELDS = ("alpha", "beta", "pitch", "omega", "slacking_tension")

#: The fields of :func:`spinning_scene`, in order.
SCENE_FIELDS = ("alpha", "beta", "pitch", "omega", "alpha_slacking", "pitch_slacking",
                "pitch_increase")


def spinning_scene(turns, head_tension, r, L, B, C):
    """The twist-spinning helix of signed N and the twist-slacking helix at the same N.

    :data:`SCENE_FIELDS`: alpha, beta (rad), pitch (m) and omega = 2 pi N / L (rad/m,
    signed like N) of :func:`spinning_state`, alpha_0 of :func:`slacking_tilt`
    (rad), its pitch ``2 pi r / tan(alpha_0)`` (m) and ``pitch / pitch_0 - 1``;
    computed together in blocks of :data:`BLOCK` elements (temporaries bounded by
    the block, the values of the whole-array formulas bit for bit). A pitch beyond
    the float range is inf (the caller checks).

    Raises
    ------
    NoHelixError
        N = 0 or T' < 0.
    """
    return _in_blocks(turns, head_tension, r, L, B, C, SCENE_FIELDS, True)


def _in_blocks(turns, head_tension, r, L, B, C, fields, scene):
    """The block loop of :func:`spinning_state` (|N|) and :func:`spinning_scene` (signed N)."""
    n, Tp = _checked(turns, head_tension, L, signed=scene)
    out = {k: np.empty(n.shape) for k in fields}
    flat = {k: v.reshape(-1) for k, v in out.items()}
    for start in range(0, n.size, BLOCK):
        stop = start + BLOCK
        nb = n.flat[start:stop]
        t = np.abs(nb) if scene else nb
        part = _state_block(t, Tp.flat[start:stop], r, L, B, C)
        if scene:
            _add_slacking(part, nb, t, r, L, B, C)
        for k, v in flat.items():
            v[start:stop] = part[k]
    return {k: v[()] if v.ndim == 0 else v for k, v in out.items()}


def _state_block(t, Tp, r, L, B, C):
    """:func:`spinning_state` of one block (1-D |N| > 0 and T')."""
    alpha = _tilt_block(t / L, Tp, r, B, C)
    omega = TWO_PI * t / L
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
    with np.errstate(over="ignore", divide="ignore"):
        pitch = TWO_PI * r / np.tan(alpha)
    return {"alpha": alpha, "beta": beta, "pitch": pitch, "omega": omega,
            "slacking_tension": Ts}


def _add_slacking(part, n, t, r, L, B, C):
    """Signed omega and the twist-slacking fields of one block (``part`` of |N| = t)."""
    part["omega"] = np.sign(n) * part["omega"]
    a0 = _slacking_block(t, r, L, B, C)
    with np.errstate(over="ignore", divide="ignore", invalid="ignore"):
        p0 = 2 * np.pi * r / np.tan(a0)
        part["pitch_increase"] = part["pitch"] / p0 - 1.0
    part["alpha_slacking"], part["pitch_slacking"] = a0, p0


def exact_energy(alpha, S_helix, turns_abs, head_tension, slack, r, L, B, C):
    """E_p(alpha, S') of the module doc without the S'/L -> 0 limit (J); for checks."""
    sa = np.sin(alpha)  # once: the same floats as one call per use
    kappa = sa**2 / r
    tau = sa * np.cos(alpha) / r
    omega = (TWO_PI * turns_abs - tau * S_helix) / L
    h = 0.5 * S_helix * np.cos(alpha) + 0.5 * np.sqrt((L - S_helix) ** 2 - (L - slack) ** 2)
    return 0.5 * B * kappa**2 * S_helix + 0.5 * C * omega**2 * L - head_tension * h
