"""Case I, smooth surface: the uniform hard-contact double helix. Float-only kernel.

docs/theory/smooth.md, paper [smooth surface]. Without friction the twist moment
``M_3 = C omega`` is the same everywhere, so omega and (by (HC)) alpha are
uniform along the helix, and the linking number gives

    omega = (2 pi N - tau S) / L                                 [smooth surface]

Together with (HC) ``omega = (B/C) (1 - cos 2a) tan 2a / (2 r)`` this is one
equation for alpha at given (N, S):

    F(alpha) = (B L / (2 C r)) (1 - cos 2a) tan 2a + S sin(a) cos(a) / r - 2 pi |N| = 0.

F increases strictly on [0, pi/4) (both terms do) from ``F(0) = -2 pi |N|``
to ``+inf``, so for every ``|N| > 0`` and ``0 <= S < L`` there is exactly one
root, found by bisection on ``cos(2a) F(a)`` (same sign, finite at pi/4).
The state depends only on (N, S): it is independent of the twisting history.
"""

from __future__ import annotations

import numpy as np

from supercoil.core.geometry import curvature, pitch_from_tilt, torsion
from supercoil.core.numerics import bisect_from_estimate
from supercoil.core.rod import contact as sc
from supercoil.exceptions import NoHelixError

TWO_PI = 2.0 * np.pi

#: Elements per block of the smooth and twist-spinning solvers: their temporaries (a few
#: tens of arrays of the block, 64 kB each) stay in the CPU cache, and the memory beyond
#: the output is bounded by the block, not by the input.
BLOCK = 8192


def _h(a, a_coef, S, n, r):
    """``cos(2a) F(a)`` of the module doc (sign of F), as :func:`solve_tilt` bisects it."""
    c = np.cos(2.0 * a)
    s2 = np.sin(2.0 * a)
    return a_coef * sc.y_of_alpha(a) * s2 + c * (S * s2 / (2.0 * r) - TWO_PI * n)


def _h_signs(a, a_coef, S, m, r):
    """:func:`_h` with ``m = TWO_PI * n`` given: the same operations in the same order
    (the same floats), in place."""
    t = 2.0 * a
    c = np.cos(t)
    s2 = np.sin(t, out=t)
    y = np.sin(a)
    np.square(y, out=y)
    y *= 2.0  # y_of_alpha
    y *= a_coef
    y *= s2
    np.multiply(S, s2, out=s2)
    s2 /= 2.0 * r
    s2 -= m
    c *= s2
    y += c
    return y


def small_tilt(p, q):
    """Root of a small-tilt limit ``a^3 + p a = q`` (p, q >= 0; Cardano), capped below
    pi/4: a start for Newton (sin a ~ a, sin 2a ~ 2a, cos 2a ~ 1), nothing more."""
    with np.errstate(all="ignore"):
        d = np.sqrt(0.25 * q * q + (p / 3.0) ** 3)
        a = np.cbrt(0.5 * q + d) + np.cbrt(0.5 * q - d)
    return np.where(np.isfinite(a), np.clip(a, 0.0, 0.99 * sc.QUARTER_PI), 0.5 * sc.QUARTER_PI)


#: sin(pi/4), the largest s = sin(alpha) of the Newton estimates.
S_MAX = np.sqrt(0.5)


def _tilt_estimate(a4, k, m, s):
    """Estimate of the root of :func:`_h` by Newton's iteration on s = sin(alpha).

    ``_h = a4 s^3 c + (c^2 - s^2) (k s c - m)`` with ``c = sqrt(1 - s^2)``,
    ``a4 = 4 a_coef``, ``k = S / r``, ``m = 2 pi n``: one square root and no sine per
    step, one arcsine at the end. ``s``: the start. The bisection's cell check
    verifies the estimate, so it only saves work; the iteration stops at steps below
    1e-8 relative (the next error is of the order of the rounding), or where a step
    is NaN (the cell check then fails and the element gets the plain bisection).
    """
    s = np.minimum(s, 0.99 * S_MAX)
    with np.errstate(all="ignore"):
        for _ in range(40):
            s2 = s * s
            c = np.sqrt(1.0 - s2)
            d = 1.0 - 2.0 * s2  # cos 2a
            u = k * s
            u *= c
            u -= m  # k s c - m
            f = a4 * s2
            f *= s
            f *= c
            df = d * u
            f += df  # _h
            u *= 4.0
            u *= s  # 4 s (k s c - m)
            df = s2 * s2
            df /= c
            np.multiply(3.0 * s2, c, out=s2)
            s2 -= df
            s2 *= a4  # a4 (3 s^2 c - s^4 / c)
            s2 -= u
            d *= d
            d *= k
            d /= c  # k (1 - 2 s^2)^2 / c
            s2 += d
            f /= s2  # the step
            if sine_step_converged(s, f):
                break
        return np.arcsin(s)


def sine_step_converged(s, step):
    """One Newton step on ``s = sin(alpha)`` in place (``s -= step``, clipped to
    ``[0, S_MAX]``); True once every step is below ``1e-8 s`` (``step`` is overwritten)."""
    s -= step
    np.clip(s, 0.0, S_MAX, out=s)
    np.abs(step, out=step)
    return not np.any(step > 1e-8 * s)


def check_inputs(turns_abs, slack, L):
    """Raise :class:`NoHelixError` naming the failed condition (N = 0, S < 0, S >= L).

    Non-finite N or S raise ValueError ("turns N must be finite").
    """
    n = np.asarray(turns_abs, float)
    S = np.asarray(slack, float)
    for name, x in (("turns N", n), ("slack S", S)):
        if not np.all(np.isfinite(x)):
            raise ValueError(f"{name} must be finite, got {float(x[~np.isfinite(x)][0])!r}")
    if np.any(S < 0):
        raise NoHelixError(
            f"slack S = {float(np.min(S)):.6g} m < 0: the ends are pulled apart, no helix"
        )
    if np.any(S >= L):
        raise NoHelixError(
            f"slack S = {float(np.max(S)):.6g} m >= rod length L = {L:.6g} m: "
            "the whole rod would be in the helix, no tail is left (need 0 <= S < L)"
        )
    if np.any(n == 0):
        raise NoHelixError(
            "turns N = 0: too few turns for contact; with no twist alpha = 0, the pitch "
            "is infinite and the slack forms a flat hairpin, not a double helix (need |N| > 0)"
        )


def solve_tilt(turns_abs, slack, r, L, B, C):
    """Tilt alpha (rad) of the uniform helix for |N| and S (broadcast), see module doc.

    The bisection of ``cos(2a) F(a)`` on [0, pi/4], computed in blocks of
    :data:`BLOCK` by :func:`bisect_from_estimate` (the same roots, bit for bit).
    """
    check_inputs(turns_abs, slack, L)
    n, S = np.broadcast_arrays(np.asarray(turns_abs, float), np.asarray(slack, float))
    out = np.empty(n.shape)
    flat = out.reshape(-1)
    for start in range(0, n.size, BLOCK):
        flat[start:start + BLOCK] = _solve_block(n.flat[start:start + BLOCK],
                                                 S.flat[start:start + BLOCK], r, L, B, C)
    return out[()] if out.ndim == 0 else out


def _solve_block(n, S, r, L, B, C):
    """The tilt of one block (1-D |N| and S), unchecked."""
    a_coef = B * L / (2.0 * C * r)
    m = TWO_PI * n  # as _h forms it
    # start: the small-tilt limit 4 a_coef a^3 + (S / r) a = 2 pi n of F
    x0 = _tilt_estimate(4.0 * a_coef, S / r, m,
                        small_tilt(S / (4.0 * a_coef * r), m / (4.0 * a_coef)))
    return bisect_from_estimate(_h_signs, None, (a_coef, S, m, r), np.zeros(n.shape),
                                np.full(n.shape, sc.QUARTER_PI), estimate=x0)


def smooth_state(turns, slack, r, L, B, C, cos2a_min=sc.COS2A_MIN):
    """The uniform helix for signed turns N and slack S (SI floats, broadcast).

    Computed in blocks of :data:`BLOCK` elements (temporaries bounded by the block;
    the same values, bit for bit, as on the whole array).

    Returns
    -------
    dict of numpy.ndarray
        ``alpha`` [rad], ``pitch`` [m], ``omega`` [rad/m] (signed), ``curvature``,
        ``torsion`` [1/m], ``tension`` [N], ``torque`` ``C omega`` [N m] (signed),
        ``normal_force`` [N/m], ``twist``, ``writhe``, ``linking_number`` and
        ``superhelical_turns`` (signed turns, like N; ``Wr = 2 cos(alpha) n``).

    Raises
    ------
    NoHelixError
        N = 0, S < 0 or S >= L (message names the condition).
    SingularityError
        cos 2 alpha < ``cos2a_min`` (alpha -> pi/4, large |N| r / L).
    """
    n = np.asarray(turns, float)
    S = np.asarray(slack, float)
    check_inputs(np.abs(n), S, L)
    shape = np.broadcast_shapes(n.shape, S.shape)
    n_b, S_b = np.broadcast_to(n, shape), np.broadcast_to(S, shape)
    out = {k: np.empty(shape) for k in STATE_FIELDS}
    flat = {k: v.reshape(-1) for k, v in out.items()}
    a_max = -np.inf
    for start in range(0, n_b.size, BLOCK):
        stop = start + BLOCK
        part = _state_block(n_b.flat[start:stop], S_b.flat[start:stop], r, L, B, C)
        a_max = max(a_max, float(np.max(part["alpha"])))
        for k, v in flat.items():
            v[start:stop] = part[k]
        del part
    if n_b.size:  # (an empty input gives empty results)
        # the tilt limit on the largest tilt: cos 2 alpha decreases with alpha
        n_max = max(float(np.max(n)), -float(np.min(n)))
        sc.check_tilt(np.float64(a_max), f"smooth helix, |N| r / L up to {n_max * r / L:.3g}",
                      cos2a_min)
    return {k: v[()] if v.ndim == 0 else v for k, v in out.items()}


#: The fields of :func:`smooth_state`, in order.
STATE_FIELDS = ("alpha", "pitch", "omega", "curvature", "torsion", "tension", "torque",
                "normal_force", "twist", "writhe", "linking_number", "superhelical_turns")


def _state_block(n, S, r, L, B, C):
    """:func:`smooth_state` of one block (1-D signed turns and slack), unchecked."""
    sign = np.sign(n)
    alpha = _solve_block(np.abs(n), S, r, L, B, C)
    tau = torsion(alpha, r)
    omega = (TWO_PI * np.abs(n) - tau * S) / L
    twist = omega * L / TWO_PI
    writhe = tau * S / TWO_PI
    return {
        "alpha": alpha,
        "pitch": pitch_from_tilt(alpha, r),
        "omega": sign * omega,
        "curvature": curvature(alpha, r),
        "torsion": tau,
        "tension": sc.smooth_tension(alpha, omega, r, B, C),
        "torque": sign * C * omega,
        "normal_force": sc.normal_force(alpha, r, B),
        "twist": sign * twist,
        "writhe": sign * writhe,
        "linking_number": sign * (twist + writhe),
        "superhelical_turns": sign * S * np.sin(alpha) / (2.0 * TWO_PI * r),
    }


def energy(turns, slack, r, L, B, C):
    """Elastic energy ``E_p = S B kappa^2 / 2 + C omega^2 L / 2`` (J) of the uniform helix."""
    st = smooth_state(turns, slack, r, L, B, C)
    S = np.broadcast_to(np.asarray(slack, float), st["alpha"].shape)
    return 0.5 * S * B * st["curvature"] ** 2 + 0.5 * C * st["omega"] ** 2 * L
