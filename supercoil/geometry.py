"""Helix geometry with units: thin wrappers over :mod:`supercoil.core.helix_geometry`.

MODEL.md section 1. Every function checks dimensions at the boundary (a wrong
dimension raises :class:`pint.DimensionalityError` naming the argument),
converts once to SI floats, calls the float kernel, and attaches units to the
result. Inputs broadcast like numpy arrays.
"""

from __future__ import annotations

import numpy as np

from .core import helix_geometry as _g
from .exceptions import SingularityError
from .units import U, magnitude, quantity

__all__ = [
    "curvature",
    "curvature_error",
    "curvature_partials",
    "linking_number",
    "pitch_from_tilt",
    "radius_from_tilt",
    "superhelical_turns",
    "tilt_angle",
    "torsion",
    "torsion_partials",
    "writhe",
]


def _alpha(alpha):
    return magnitude(alpha, U.rad, "alpha")


def _radius(radius):
    r = magnitude(radius, U.m, "radius")
    if np.any(np.asarray(r) <= 0):
        raise ValueError(f"radius must be positive, got {radius}")
    return r


def tilt_angle(radius, pitch):
    """Tilt angle ``alpha = arctan(2 pi R / P)`` [eq alpha def].

    Parameters
    ----------
    radius : Quantity [length]
        Helix radius R (strand centre line to axis).
    pitch : Quantity [length]
        Pitch P.

    Returns
    -------
    Quantity [rad]
    """
    return quantity(_g.tilt_angle(_radius(radius), magnitude(pitch, U.m, "pitch")), U.rad)


def pitch_from_tilt(alpha, radius):
    """Pitch ``P = 2 pi R / tan(alpha)`` (inverse of :func:`tilt_angle`).

    Raises
    ------
    SingularityError
        At alpha = 0, where the pitch is infinite (straight strands).
    """
    a = _alpha(alpha)
    if np.any(np.asarray(a) == 0):
        raise SingularityError("pitch diverges at alpha = 0 (straight strands)")
    return quantity(_g.pitch_from_tilt(a, _radius(radius)), U.m)


def radius_from_tilt(alpha, pitch):
    """Radius ``R = P tan(alpha) / (2 pi)``."""
    return quantity(_g.radius_from_tilt(_alpha(alpha), magnitude(pitch, U.m, "pitch")), U.m)


def curvature(alpha, radius):
    """Curvature ``kappa = sin^2(alpha) / R`` [Eq curvature1], in 1/m."""
    return quantity(_g.curvature(_alpha(alpha), _radius(radius)), U.per_m)


def torsion(alpha, radius):
    """Torsion ``tau = sin(alpha) cos(alpha) / R`` [Eq torsion1], in 1/m."""
    return quantity(_g.torsion(_alpha(alpha), _radius(radius)), U.per_m)


def curvature_partials(alpha, radius):
    """``(d kappa/d alpha [1/m/rad], d kappa/d R [1/m^2])``."""
    da, dr = _g.curvature_partials(_alpha(alpha), _radius(radius))
    return quantity(da, U.per_m / U.rad), quantity(dr, U.per_m / U.m)


def torsion_partials(alpha, radius):
    """``(d tau/d alpha [1/m/rad], d tau/d R [1/m^2])``."""
    da, dr = _g.torsion_partials(_alpha(alpha), _radius(radius))
    return quantity(da, U.per_m / U.rad), quantity(dr, U.per_m / U.m)


def curvature_error(dpitch_ds):
    """Appendix A factor ``e = sqrt(1 + (dP/ds)^2 / 4 pi^2)`` (dimensionless)."""
    return quantity(_g.curvature_error(magnitude(dpitch_ds, U.dimensionless, "dpitch_ds")),
                    U.dimensionless)


def superhelical_turns(alpha, radius, slack):
    """Superhelical turns ``n = S sin(alpha) / (4 pi R)`` of a uniform double helix."""
    n = _g.superhelical_turns(_alpha(alpha), _radius(radius), magnitude(slack, U.m, "slack"))
    return quantity(n, U.turn)


def writhe(alpha, radius, slack, method="exact"):
    """Writhe of a uniform double helix of slack S (both strands together).

    Parameters
    ----------
    alpha : Quantity [angle]
    radius : Quantity [length]
    slack : Quantity [length]
        Rod length taken into the helix, S.
    method : {"exact", "one_view"}
        ``"exact"``: ``Wr = tau S / 2 pi`` [Eq Lk=Tw+Wr], 2 cos(alpha) per
        superhelical turn, verified against the Gauss integral.
        ``"one_view"``: the crossing count of one view (tau -> sin(alpha)/R),
        valid only for small alpha.
    """
    a, r, s = _alpha(alpha), _radius(radius), magnitude(slack, U.m, "slack")
    if method == "exact":
        wr = _g.writhe_uniform(a, r, s)
    elif method == "one_view":
        wr = _g.writhe_one_view(a, r, s)
    else:
        raise ValueError(f"method must be 'exact' or 'one_view', got {method!r}")
    return quantity(wr, U.turn)


def linking_number(alpha, radius, slack, length, omega_helix, omega_tail=None):
    """``Lk = Tw + Wr`` of a rod of length L with a uniform double helix of slack S.

    ``Tw = [omega_h S + omega_t (L - S)] / 2 pi``, ``Wr = tau S / 2 pi``.
    ``omega_tail`` defaults to ``omega_helix`` (smooth surface).

    Returns
    -------
    (Lk, Tw, Wr) : tuple of Quantity [turn]
    """
    a, r = _alpha(alpha), _radius(radius)
    s = magnitude(slack, U.m, "slack")
    L = magnitude(length, U.m, "length")
    wh = magnitude(omega_helix, U.per_m, "omega_helix")
    wt = wh if omega_tail is None else magnitude(omega_tail, U.per_m, "omega_tail")
    tw = _g.twist_uniform(wh, wt, s, L)
    wr = _g.writhe_uniform(a, r, s)
    return (quantity(tw + wr, U.turn), quantity(tw, U.turn), quantity(wr, U.turn))
