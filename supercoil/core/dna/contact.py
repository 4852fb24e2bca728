"""Hard contact of the two plectoneme strands at R = a, for any repulsion w(alpha, R).
Float-only SI kernel (docs/theory/screened-interaction.md#5).

Equations
---------
The strands are cylinders of radius a: R >= a. At fixed torque M the plectoneme minimises
``f(alpha, R) = B kappa^2/2 + w - M tau`` (docs/theory/plectoneme.md) and its tension is
``T = -f_min``. On the boundary R = a only alpha is free:

* (GE1) ``M = a X / cos(2 alpha)``, ``X = B kappa kappa_alpha + w_alpha`` (df/dalpha = 0);
* tension ``T = -(1/2) B kappa^2 + M tau - w``;
* the contact holds while the strands press on each other,
  ``N = df/dR = Y + M sin(2 alpha) / (2 a^2) >= 0`` with ``Y = B kappa kappa_R + w_R``
  (N is the normal reaction per unit DNA length; (GE2) is ``N = 0``, where the contact
  branch meets the free branch at R = a).

This is the screened counterpart of the paper's hard-contact condition (HC) of the rod
(``w = 0`` for R > r: there the contact always holds). Along the branch ``dT = tau dM``
(T and M rise together). At a given tension the equilibrium is the state of lowest torque
among the candidates (free and contact): ``T(M) = -min f`` is the largest of the branches'
tensions at that torque, and each branch's T rises with M.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["TILTS", "ContactBranch", "contact_table", "normal_reaction", "solve_contact"]

_ALPHA_HI = 0.25 * np.pi * (1.0 - 1e-6)
_TABLE_POINTS = 401
#: the tilts (rad) at which :func:`contact_table` evaluates the contact states (read-only;
#: passed to ``partials`` as this very array, so a caller may memoise B-free parts)
TILTS = np.linspace(1e-3, _ALPHA_HI, _TABLE_POINTS)
TILTS.setflags(write=False)


class ContactBranch(NamedTuple):
    """Tabulated contact states at R = a: tilts (rad), tensions (N, increasing), torques."""

    radius: float
    alpha: np.ndarray
    tension: np.ndarray
    torque: np.ndarray


def _state(alpha, a, B, partials):
    s, c = np.sin(alpha), np.cos(alpha)
    R = np.full(np.shape(alpha), a)
    kappa, tau = s * s / a, s * c / a
    w, w_a, w_R = partials(alpha, R)
    X = B * kappa * 2.0 * s * c / a + w_a
    Y = -B * kappa * s * s / (a * a) + w_R
    M = a * X / np.cos(2.0 * alpha)
    T = -0.5 * B * kappa * kappa + M * tau - w
    N = Y + M * np.sin(2.0 * alpha) / (2.0 * a * a)
    return M, T, N


def normal_reaction(alpha, a, B, partials):
    """``(M, T, N)`` of the contact state at tilt alpha: torque (N m), tension (N) and
    normal reaction per unit DNA length ``N = df/dR`` (N/m; the contact holds for N >= 0)."""
    return _state(np.asarray(alpha, dtype=float), a, B, partials)


def contact_table(B, partials, a, points=_TABLE_POINTS):
    """The contact branch at R = a where it holds (N >= 0) and T rises; None if nowhere.

    The branch starts at the tilt where N changes sign (refined by root finding: there it
    meets the free branch at R = a) and runs up to alpha -> pi/4, where T diverges.
    """
    alpha = TILTS if points == _TABLE_POINTS else np.linspace(1e-3, _ALPHA_HI, points)
    M, T, N = _state(alpha, a, B, partials)
    holds = N >= 0.0
    if not np.any(holds):
        return None
    j = int(np.argmax(holds))
    if j > 0 and not np.all(holds[j:]):  # N must stay >= 0 once it holds
        holds[j:] &= np.cumprod(holds[j:]).astype(bool)
    k = j + int(np.sum(holds[j:]))
    alpha, M, T = alpha[j:k].copy(), M[j:k].copy(), T[j:k].copy()
    if j > 0:  # refine the start: N(alpha*) = 0, the free branch at R = a
        # a scalar root: brentq, a quarter of the CPU of the elementwise find_root here
        # (the same 6 evaluations; roots within 3e-16 rad of its over 21 buffers, 5 mM-1 M
        # with and without confinement, and the tables' CPU 0.67 of before)
        from scipy.optimize import brentq

        alpha[0] = brentq(lambda x: float(_state(np.float64(x), a, B, partials)[2]),
                          float(alpha[0] - (alpha[1] - alpha[0])), float(alpha[0]),
                          xtol=1e-15, rtol=4.0 * np.finfo(float).eps)
        M[0], T[0], _ = (float(v) for v in _state(alpha[0], a, B, partials))
    rising = np.nonzero(np.diff(T) <= 0.0)[0]
    if rising.size:
        alpha, M, T = alpha[: rising[0] + 1], M[: rising[0] + 1], T[: rising[0] + 1]
    if alpha.size < 2:
        return None
    for arr in (alpha, M, T):
        arr.setflags(write=False)
    return ContactBranch(float(a), alpha, T, M)


def solve_contact(force, B, partials, branch):
    """``(alpha, M)`` of the contact state at each tension inside ``branch`` (1-D arrays)."""
    force = np.asarray(force, dtype=float)
    T_t = branch.tension
    k = np.clip(np.searchsorted(T_t, force, side="left") - 1, 0, T_t.size - 2)
    lo, hi = branch.alpha[k], branch.alpha[k + 1]

    def g(x, target):
        return _state(x, branch.radius, B, partials)[1] - target

    from scipy.optimize.elementwise import find_root

    res = find_root(g, (lo, hi), args=(force,), tolerances=dict(xatol=1e-16, xrtol=1e-15),
                    maxiter=200)
    M = _state(res.x, branch.radius, B, partials)[0]
    return res.x, M
