"""Helix geometry of one strand of a double helix (docs/theory/geometry.md). Float-only kernel.

All arguments are floats or numpy arrays in SI units (m, rad); everything
broadcasts. Nothing here imports pint.

One strand of a double helix of radius ``R`` (strand centre line to axis) and
pitch ``P``::

    r(theta) = (R cos theta, R sin theta, P theta / 2 pi)

has tilt angle, curvature and torsion [eq alpha def, Eq curvature1, Eq torsion1]

    alpha = arctan(2 pi R / P),
    kappa = sin^2(alpha) / R,
    tau   = sin(alpha) cos(alpha) / R,

so that ``kappa^2 + tau^2 = sin^2(alpha) / R^2`` and ``tau / kappa = cot(alpha)``.
The pitch is assumed to vary slowly (dP/ds neglected); :func:`curvature_error`
gives the exact-to-approximate curvature ratio of Appendix A.

Linking number of the twisted rod folded into a double helix [Eq Lk=Tw+Wr]::

    Lk = N,  Tw = (2/2pi) int_0^{L/2} omega ds,  Wr = (2/2pi) int_0^{S/2} tau ds

i.e. ``2 cos(alpha)`` of writhe per superhelical turn (verified against the
Gauss double integral in :mod:`supercoil.core.gauss_writhe`).

Sign convention: the package works with the magnitude of the turns N >= 0 and
attaches ``sign(N)`` to twist, writhe and torque. Positive N gives a plectoneme
with positive writhe: a *left-handed* interwound superhelix (right-handed
strands give negative Gauss writhe, as for negatively supercoiled DNA).
"""

from __future__ import annotations

import numpy as np

TWO_PI = 2.0 * np.pi


def tilt_angle(radius, pitch):
    """Tilt angle ``alpha = arctan(2 pi R / P)`` in rad [eq alpha def].

    Implements docs/theory/geometry.md (eq alpha def).
    """
    return np.arctan2(TWO_PI * np.asarray(radius, float), np.asarray(pitch, float))


def pitch_from_tilt(alpha, radius):
    """Pitch ``P = 2 pi R / tan(alpha)`` (m); infinite at alpha = 0."""
    with np.errstate(divide="ignore"):
        return TWO_PI * np.asarray(radius, float) / np.tan(alpha)


def radius_from_tilt(alpha, pitch):
    """Radius ``R = P tan(alpha) / (2 pi)`` (m)."""
    return np.asarray(pitch, float) * np.tan(alpha) / TWO_PI


def curvature(alpha, radius):
    """Curvature ``kappa = sin^2(alpha) / R`` (1/m) [Eq curvature1].

    Implements docs/theory/geometry.md (Eq curvature1).
    """
    return np.sin(alpha) ** 2 / radius


def torsion(alpha, radius):
    """Torsion ``tau = sin(alpha) cos(alpha) / R`` (1/m) [Eq torsion1].

    Implements docs/theory/geometry.md (Eq torsion1).
    """
    return np.sin(alpha) * np.cos(alpha) / radius


def curvature_partials(alpha, radius):
    """``(d kappa/d alpha, d kappa/d R) = (sin 2a / R, -sin^2 a / R^2)``."""
    return np.sin(2.0 * alpha) / radius, -(np.sin(alpha) ** 2) / radius**2


def torsion_partials(alpha, radius):
    """``(d tau/d alpha, d tau/d R) = (cos 2a / R, -sin 2a / (2 R^2))``."""
    return np.cos(2.0 * alpha) / radius, -np.sin(2.0 * alpha) / (2.0 * radius**2)


def curvature_error(dpitch_ds):
    """Appendix A: ``e = kappa_exact / kappa = sqrt(1 + (dP/ds)^2 / (4 pi^2))``.

    ``dpitch_ds`` is dimensionless (m/m). ``e >= 1``; ``e - 1`` is the relative
    error of the slowly-varying-pitch approximation. Evaluated as
    ``hypot(1, dP/ds / 2 pi)``, which stays finite wherever ``e`` is (the squared
    form overflows above |dP/ds| ~ 1e154).
    """
    d = np.asarray(dpitch_ds, float)
    return np.hypot(1.0, d / TWO_PI)


def curvature_error_profile(s, pitch):
    """Appendix A factor ``e(s)`` along a tabulated pitch profile ``P(s)``.

    dP/ds is taken with second-order finite differences (numpy.gradient) on
    the given, possibly non-uniform, grid ``s``.
    """
    return curvature_error(np.gradient(np.asarray(pitch, float), np.asarray(s, float)))


def superhelical_turns(alpha, radius, slack):
    """Number of superhelical turns of a uniform double helix of slack ``S``.

    Each strand has length S/2 and advances ``sin(alpha)/(2 pi R)`` turns per
    unit length: ``n = S sin(alpha) / (4 pi R)``.
    """
    return np.asarray(slack, float) * np.sin(alpha) / (2.0 * TWO_PI * radius)


def writhe_uniform(alpha, radius, slack):
    """Writhe of a uniform double helix: ``Wr = tau S / (2 pi)`` [Eq Lk=Tw+Wr].

    Implements docs/theory/geometry.md (Eq Lk=Tw+Wr).

    Equal to ``2 cos(alpha)`` per superhelical turn.
    """
    return torsion(alpha, radius) * np.asarray(slack, float) / TWO_PI


def writhe_one_view(alpha, radius, slack):
    """One-view crossing approximation: tau replaced by ``sin(alpha)/R``.

    Two crossings per superhelical turn; agrees with :func:`writhe_uniform`
    only for small alpha (relative error ``1 - cos(alpha)``). Not used by default.
    """
    return np.sin(alpha) / radius * np.asarray(slack, float) / TWO_PI


def twist_uniform(omega_helix, omega_tail, slack, length):
    """Twist ``Tw = [omega_h S + omega_t (L - S)] / (2 pi)`` of a rod with
    uniform twist density in the helix and in the tail [Eq Lk=Tw+Wr].

    Implements docs/theory/geometry.md (Eq Lk=Tw+Wr).
    """
    return (omega_helix * slack + omega_tail * (length - slack)) / TWO_PI


def strand_integral(s, f):
    """``(2/2pi) int_0^{s_end} f ds`` of a profile tabulated on one strand.

    Trapezoid rule on the grid ``s`` (one strand's arclength from the head);
    with ``f = tau`` this is the writhe, with ``f = omega`` the twist of the
    helix part [Eq Lk=Tw+Wr].
    """
    s = np.asarray(s, float)
    f = np.asarray(f, float)
    return np.trapezoid(f, s, axis=-1) / np.pi


def cumulative_strand_integral(s, f):
    """Running version of :func:`strand_integral`, 0 at ``s[0]``."""
    s = np.asarray(s, float)
    f = np.asarray(f, float)
    inc = 0.5 * (f[1:] + f[:-1]) * np.diff(s)
    return np.concatenate(([0.0], np.cumsum(inc))) / np.pi
