"""Helix geometry with units: thin wrappers over :mod:`supercoil.core.geometry`.

docs/theory/geometry.md. Every function checks dimensions at the boundary (a wrong
dimension raises :class:`pint.DimensionalityError` naming the argument) and
values (NaN, inf, a negative radius, pitch or slack, a tilt outside
[0, pi/2] raise ValueError naming the argument and the limit), converts once
to SI floats, calls the float kernel, and attaches units to the result.
Inputs broadcast like numpy arrays.
"""

from __future__ import annotations

import numpy as np

from supercoil._checks import broadcast_shape, check_finite_output
from supercoil.core import geometry as _g
from supercoil.exceptions import SingularityError
from supercoil.units import U, magnitude, quantity

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


def _out(value, unit, name, **inputs):
    """``value`` with ``unit``; ValidityError naming ``name`` and the inputs if not finite."""
    with np.errstate(over="ignore", invalid="ignore", divide="ignore"):
        a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        given = ", ".join(f"{k} = {v!r}" for k, v in inputs.items())
        check_finite_output(a, name, given)
    return quantity(value, unit)


def _alpha_radius(alpha, radius):
    """Checked (alpha, radius) that broadcast together."""
    a, r = _alpha(alpha), _radius(radius)
    broadcast_shape(alpha=a, radius=r)
    return a, r


def _finite(x, name, given):
    a = np.asarray(x, float)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must be finite, got {given!r}")
    return a


def _quiet():
    """numpy's float errors off around a kernel call: :func:`_out` names a non-finite result.

    The checked scalars are numpy floats (``a[()]``), not Python floats: Python's
    ``1e297 ** 2`` raises a bare OverflowError (and ``x / 0.0`` a
    ZeroDivisionError) where numpy gives inf, which :func:`_out` turns into a
    ValidityError naming the result and the inputs; a result
    below the float range underflows to 0, its value to rounding.
    """
    return np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore")


def _alpha(alpha, hi_open=False):
    """Tilt in rad, finite and in [0, pi/2] (``[0, pi/2)`` with ``hi_open``)."""
    a = _finite(magnitude(alpha, U.rad, "alpha"), "alpha", alpha)
    top = np.pi / 2
    if np.any(a < 0) or np.any(a >= top if hi_open else a > top):
        raise ValueError(f"alpha must lie in [0, pi/2{')' if hi_open else ']'} (tilt "
                         f"arctan(2 pi R / P) with R, P > 0; the handedness is the sign of "
                         f"the turns N, not of alpha), got {alpha!r}")
    return a if a.ndim else a[()]


def _radius(radius):
    r = _finite(magnitude(radius, U.m, "radius"), "radius", radius)
    if np.any(r <= 0):
        raise ValueError(f"radius must be positive, got {radius!r}")
    return r if r.ndim else r[()]


def _length(value, name, positive=True):
    """A length in m, finite and > 0 (``positive``) or >= 0."""
    x = _finite(magnitude(value, U.m, name), name, value)
    if np.any(x <= 0) if positive else np.any(x < 0):
        raise ValueError(f"{name} must be {'positive' if positive else '>= 0'} (the package "
                         f"carries the handedness in the sign of N), got {value!r}")
    return x if x.ndim else x[()]


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
        In (0, pi/2).

    Raises
    ------
    ValueError
        radius or pitch not finite or not positive (a negative pitch would give
        alpha > pi/2; the handedness is the sign of the turns N).
    """
    r, p = _radius(radius), _length(pitch, "pitch")
    broadcast_shape(radius=r, pitch=p)
    return _out(_g.tilt_angle(r, p), U.rad, "alpha",
                radius=radius, pitch=pitch)


def pitch_from_tilt(alpha, radius):
    """Pitch ``P = 2 pi R / tan(alpha)`` (inverse of :func:`tilt_angle`), alpha in [0, pi/2].

    Raises
    ------
    SingularityError
        At alpha = 0, where the pitch is infinite (straight strands).
    ValueError
        alpha or radius not finite or out of range.
    """
    a = _alpha(alpha)
    broadcast_shape(alpha=a, radius=_radius(radius))
    if np.any(np.asarray(a) == 0):
        raise SingularityError("pitch diverges at alpha = 0 (straight strands)")
    with _quiet():
        p = _g.pitch_from_tilt(a, _radius(radius))
    return _out(p, U.m, "pitch", alpha=alpha, radius=radius)


def radius_from_tilt(alpha, pitch):
    """Radius ``R = P tan(alpha) / (2 pi)``, alpha in [0, pi/2), pitch > 0 (finite)."""
    a = _alpha(alpha, hi_open=True)
    broadcast_shape(alpha=a, pitch=_length(pitch, "pitch"))
    with _quiet():
        r = _g.radius_from_tilt(a, _length(pitch, "pitch"))
    return _out(r, U.m, "radius", alpha=alpha, pitch=pitch)


def curvature(alpha, radius):
    """Curvature ``kappa = sin^2(alpha) / R`` [Eq curvature1], in 1/m."""
    with _quiet():
        k = _g.curvature(*_alpha_radius(alpha, radius))
    return _out(k, U.per_m, "curvature", alpha=alpha, radius=radius)


def torsion(alpha, radius):
    """Torsion ``tau = sin(alpha) cos(alpha) / R`` [Eq torsion1], in 1/m."""
    with _quiet():
        t = _g.torsion(*_alpha_radius(alpha, radius))
    return _out(t, U.per_m, "torsion", alpha=alpha, radius=radius)


def curvature_partials(alpha, radius):
    """``(d kappa/d alpha [1/m/rad], d kappa/d R [1/m^2])``."""
    with _quiet():
        da, dr = _g.curvature_partials(*_alpha_radius(alpha, radius))
    return (_out(da, U.per_m / U.rad, "d kappa/d alpha", alpha=alpha, radius=radius),
            _out(dr, U.per_m / U.m, "d kappa/d R", alpha=alpha, radius=radius))


def torsion_partials(alpha, radius):
    """``(d tau/d alpha [1/m/rad], d tau/d R [1/m^2])``."""
    with _quiet():
        da, dr = _g.torsion_partials(*_alpha_radius(alpha, radius))
    return (_out(da, U.per_m / U.rad, "d tau/d alpha", alpha=alpha, radius=radius),
            _out(dr, U.per_m / U.m, "d tau/d R", alpha=alpha, radius=radius))


def curvature_error(dpitch_ds):
    """Appendix A factor ``e = sqrt(1 + (dP/ds)^2 / 4 pi^2)`` (dimensionless)."""
    d = _finite(magnitude(dpitch_ds, U.dimensionless, "dpitch_ds"), "dpitch_ds", dpitch_ds)
    with _quiet():
        e = _g.curvature_error(d if d.ndim else d[()])
    return _out(e, U.dimensionless, "curvature_error", dpitch_ds=dpitch_ds)


def superhelical_turns(alpha, radius, slack):
    """Superhelical turns ``n = S sin(alpha) / (4 pi R)`` of a uniform double helix.

    Unsigned (alpha >= 0, S >= 0): the magnitude of the count; the rod scenes
    attach sign(N) (see :class:`supercoil.SmoothHelix`).
    """
    with _quiet():
        a, r = _alpha_radius(alpha, radius)
        s = _length(slack, "slack", positive=False)
        broadcast_shape(alpha=a, radius=r, slack=s)
        n = _g.superhelical_turns(a, r, s)
    return _out(n, U.turn, "superhelical_turns", alpha=alpha, radius=radius, slack=slack)


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
    a, r, s = _alpha(alpha), _radius(radius), _length(slack, "slack", positive=False)
    broadcast_shape(alpha=a, radius=r, slack=s)
    if method not in ("exact", "one_view"):
        raise ValueError(f"method must be 'exact' or 'one_view', got {method!r}")
    with _quiet():
        wr = (_g.writhe_uniform if method == "exact" else _g.writhe_one_view)(a, r, s)
    return _out(wr, U.turn, "writhe", alpha=alpha, radius=radius, slack=slack)


def linking_number(alpha, radius, slack, length, omega_helix, omega_tail=None):
    """``Lk = Tw + Wr`` of a rod of length L with a uniform double helix of slack S.

    ``Tw = [omega_h S + omega_t (L - S)] / 2 pi``, ``Wr = tau S / 2 pi``.
    ``omega_tail`` defaults to ``omega_helix`` (smooth surface).

    Returns
    -------
    (Lk, Tw, Wr) : tuple of Quantity [turn]
    """
    a, r = _alpha(alpha), _radius(radius)
    s = _length(slack, "slack", positive=False)
    L = _length(length, "length")
    broadcast_shape(alpha=a, radius=r, slack=s, length=L)
    if np.any(np.asarray(s) > np.asarray(L)):
        raise ValueError(f"slack must not exceed length (S <= L), got S = {slack!r}, "
                         f"L = {length!r}")
    wh = _finite(magnitude(omega_helix, U.per_m, "omega_helix"), "omega_helix", omega_helix)
    wt = wh if omega_tail is None else _finite(
        magnitude(omega_tail, U.per_m, "omega_tail"), "omega_tail", omega_tail)
    broadcast_shape(alpha=a, radius=r, slack=s, length=L, omega_helix=wh, omega_tail=wt)
    with _quiet():
        tw = _g.twist_uniform(wh, wt, s, L)
        wr = _g.writhe_uniform(a, r, s)
        lk = tw + wr
    given = {"alpha": alpha, "radius": radius, "slack": slack, "length": length}
    return (_out(lk, U.turn, "linking_number", **given), _out(tw, U.turn, "twist", **given),
            _out(wr, U.turn, "writhe", **given))
