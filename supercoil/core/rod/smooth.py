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


def _h_df(a, a_coef, S, n, r):
    """:func:`_h` and its derivative in alpha (for the Newton estimate)."""
    # the double angles from sin a, cos a (an estimate only: the signs come from _h);
    # y = 1 - cos 2a = 2 sin^2 a without cancellation at small tilts
    sa, ca = np.sin(a), np.cos(a)
    c, s, y = (ca - sa) * (ca + sa), 2.0 * sa * ca, 2.0 * sa * sa
    k, m = S / (2.0 * r), TWO_PI * n
    f = a_coef * y * s + c * (k * s - m)
    df = 2.0 * (a_coef * (s * s + y * c) + k * (c * c - s * s) + m * s)
    return f, df


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
    return bisect_from_estimate(_h, _h_df, (a_coef, S, n, r), np.zeros(n.shape),
                                np.full(n.shape, sc.QUARTER_PI))


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
