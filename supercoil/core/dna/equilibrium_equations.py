"""Equations of the uniform plectoneme for any interaction ``w(alpha, R)``. Float-only SI.

The solvers of :mod:`supercoil.core.dna.equilibrium` (docs/theory/plectoneme.md;
docs/theory/screened-interaction.md#5) work on these.

For a uniform double helix of tilt alpha and radius R, stationarity of the energy
[Eq Ep1] gives (GE1) ``C omega = X / tau_alpha`` and (GE2)
``tau_R X - tau_alpha Y = 0`` with ``X = B kappa kappa_alpha + w_alpha`` and
``Y = B kappa kappa_R + w_R``; the tension is ``T = -(1/2) B kappa^2 + C omega tau - w``.
With ``kappa = sin^2 a / R`` and ``tau = sin a cos a / R`` (docs/theory/plectoneme.md),
``-R^2 (GE2)`` reads

    h(alpha, R) = (sin 2alpha / 2) X + R cos(2alpha) Y = 0,

which does not contain C: the torque ``M = C omega = X / tau_alpha``, alpha and R at a
given tension are independent of C. Along the solution curve ``dT = tau dM``
(the state is a stationary point of ``f = B kappa^2/2 + w - M tau`` at fixed torque
and ``T = -f``), so the stable branch is the one on which T decreases monotonically
as R grows (M grows with T).
"""

from __future__ import annotations

import numpy as np

__all__ = ["equilibrium_residuals", "tension", "tilt_residual", "torque", "xy_terms"]


def xy_terms(alpha, R, B, partials):
    """``(X, Y, w, kappa)`` at (alpha, R): ``X = B kappa kappa_alpha + w_alpha`` (N),
    ``Y = B kappa kappa_R + w_R`` (N/m), one call of ``partials``."""
    s = np.sin(alpha)
    c = np.cos(alpha)
    kappa = s * s / R
    w, w_a, w_R = partials(alpha, R)
    X = B * kappa * 2.0 * s * c / R + w_a
    Y = -B * kappa * s * s / (R * R) + w_R
    return X, Y, w, kappa


def tilt_residual(alpha, R, B, partials):
    """``h = -R^2 (GE2) = (sin 2a / 2) X + R cos(2a) Y`` (N).

    Implements docs/theory/plectoneme.md (GE2).
    """
    X, Y, _, _ = xy_terms(alpha, R, B, partials)
    return np.sin(2.0 * alpha) * 0.5 * X + R * np.cos(2.0 * alpha) * Y


def torque(alpha, R, B, partials):
    """(GE1) torque ``M = C omega = X / tau_alpha = R X / cos(2 alpha)`` (N m).

    Implements docs/theory/plectoneme.md (GE1).
    """
    X, _, _, _ = xy_terms(alpha, R, B, partials)
    return R * X / np.cos(2.0 * alpha)


def tension(alpha, R, B, partials):
    """``T = -(1/2) B kappa^2 + M tau - w`` with M from (GE1) (N)."""
    X, _, w, kappa = xy_terms(alpha, R, B, partials)
    M = R * X / np.cos(2.0 * alpha)
    tau = np.sin(alpha) * np.cos(alpha) / R
    return -0.5 * B * kappa * kappa + M * tau - w


def equilibrium_residuals(force, alpha, R, omega, B, C, partials):
    """Relative residuals ``(GE1, GE2, tension)`` from the un-reduced equations of
    docs/theory/plectoneme.md (geometry partials written out here, not the solver's ``h``)."""
    s, c = np.sin(alpha), np.cos(alpha)
    kappa, tau = s * s / R, s * c / R
    k_a, k_r = np.sin(2 * alpha) / R, -s * s / R**2
    t_a, t_r = np.cos(2 * alpha) / R, -np.sin(2 * alpha) / (2 * R**2)
    w, w_a, w_r = partials(alpha, R)
    X = B * kappa * k_a + w_a
    Y = B * kappa * k_r + w_r
    ge1 = (C * omega * t_a - X) / (np.abs(C * omega * t_a) + np.abs(B * kappa * k_a)
                                   + np.abs(w_a))
    ge2 = (t_r * X - t_a * Y) / (np.abs(t_r * X) + np.abs(t_a * B * kappa * k_r)
                                 + np.abs(t_a * w_r))
    terms = (0.5 * B * kappa**2, C * omega * tau, w, force)
    ten = (-terms[0] + terms[1] - terms[2] - force) / sum(np.abs(x) for x in terms)
    return ge1, ge2, ten
