"""Example II: design the twisting schedule for a chosen pitch profile (docs/theory/design.md).

Public unit wrapper over :mod:`supercoil.core.rod.design`.
"""

from __future__ import annotations

import numpy as np

from supercoil._checks import check_callable, profile_values
from supercoil.core.rod import contact as _sc
from supercoil.core.rod import design as _dh
from supercoil.rod.material import check_rod
from supercoil.rod.validity import warn_hard_contact, warn_no_friction
from supercoil.tables import make_table, provenance
from supercoil.units import U, magnitude, quantity

__all__ = ["SCHEDULE_UNITS", "design_twist_schedule", "sinusoidal_pitch"]

SCHEDULE_UNITS = {
    "slack": "mm",
    "turns": "turn",
    "tension": "N",
    "s": "mm",
    "pitch": "mm",
    "alpha": "rad",
    "twist_rate": "rad/m",
    "torque": "N*mm",
    "friction_torque_required": "N",
    "friction_torque_available": "N",
}


def sinusoidal_pitch(p0, p1, wavenumber):
    """The paper's designed profile [eq sinp] ``P(s) = P0 + P1 sin(k s)`` as a callable.

    Parameters
    ----------
    p0, p1 : Quantity [length]
        Mean pitch and amplitude (paper: 16 mm and 4 mm; the figure caption's
        "cm" is a typo, docs/theory/corrections.md#typos).
    wavenumber : Quantity [1/length]
        k (paper: ``2 pi / (10 P0)``).
    """
    P0 = float(magnitude(p0, U.m, "p0"))
    P1 = float(magnitude(p1, U.m, "p1"))
    kw = float(magnitude(wavenumber, U.per_m, "wavenumber"))

    def pitch(s):
        x = magnitude(s, U.m, "s")
        return quantity(P0 + P1 * np.sin(kw * np.asarray(x, float)), U.m)

    return pitch


def design_twist_schedule(rod, pitch, *, slack_max=None, n_points=2001, pitch_derivative=None,
                          cos2a_min=_sc.COS2A_MIN):
    """The twisting/slacking schedule (N and T versus S) that produces a pitch profile.

    Inverts [eq da/ds] for the twisting rate (see :mod:`supercoil.core.rod.design`):
    with alpha(s) = arctan(2 pi r / P(s)),

    ``k(2s) = [sin 2a - alpha'(s) B (L - 2s)(c^3 - 1) / (C c^2)] / (2 r)``,
    ``N(S) = N_0 + (1/2 pi) int_0^S k dS'`` with N_0 from [eq ini] at alpha(0),
    and ``T(S)`` from [eq tension] at alpha(S/2). N(S) is evaluated through the
    linking identity Lk = Tw + Wr [Eq Lk=Tw+Wr] at S = 2s,
    ``N = (1/pi) int_0^s (omega + tau) ds' + omega(s) (L - 2s) / 2 pi``
    (equal to the integral of k; its integrand grows only like 1/cos 2a near
    pi/4 where k grows like 1/cos^2 2a), by cumulative Simpson quadrature
    (4th order) on the grid.

    Feeding the returned table back as ``twist_rate`` of
    :func:`supercoil.rough_helix` (with ``turns = table["turns"][0]``) reproduces
    P(s); the tests check this round trip.

    Parameters
    ----------
    rod : ElasticRod
    pitch : callable
        ``pitch(s) -> Quantity [length]`` for an arclength Quantity array s (one
        strand, from the head), vectorised. Evaluated only on [0, slack_max / 2].
    slack_max : Quantity [length], optional
        Last slack of the schedule (default: ``L (1 - 1e-6)``, the whole rod).
    n_points : int
        Grid size (uniform in s), >= 10. N(S) comes from cumulative Simpson
        quadrature on this grid (error ~ h^4), and the table is meant to be fed
        back to :func:`supercoil.rough_helix`, which interpolates k linearly
        between its rows (error ~ h^2). For the paper's sinusoid over S = 50 cm
        the round trip misses P(s) by 4 % with 10 rows, 25 % with 7, 300 % with 5
        (and with 3 the helix ends after 36 mm); 2001 rows give 2e-5.
    pitch_derivative : callable, optional
        ``dP/ds(s)`` (dimensionless Quantity, finite); default: 4th-order finite
        differences of ``pitch`` with step 1e-4 (slack_max / 2).
    cos2a_min : float
        alpha -> pi/4 guard, in (0, 1).

    Returns
    -------
    pandas.DataFrame
        Columns ``slack`` [mm], ``turns``, ``tension`` [N], ``s`` [mm], ``pitch``
        [mm], ``alpha`` [rad], ``twist_rate`` [rad/m] (k at this slack),
        ``torque`` [N mm] (``C omega`` at the helix end), and the friction check
        of the designed helix ``friction_torque_required`` = ``C |d omega/ds|``
        and ``friction_torque_available`` [N] (the latter only if the rod has a
        friction coefficient). Units in ``attrs["units"]``. N > 0 (right-handed
        sense of the package); negate ``turns`` and ``twist_rate`` for the mirror.

    Raises
    ------
    SingularityError
        If P(s) <= 2 pi r somewhere (alpha >= pi/4), or P is not positive/finite.
    ValueError
        slack_max outside (0, L); n_points < 10; a pitch_derivative value that
        is NaN or infinite (the message names the s); cos2a_min outside (0, 1);
        pitch(s) or pitch_derivative(s) returning neither a scalar nor one
        value per s (the message names the shape expected).
    TypeError
        n_points not an integer; pitch (or pitch_derivative) not callable.

    Warns
    -----
    ValidityWarning
        No friction coefficient; or the pitch is so small that hard contact fails
        (Hertz contact half-width above the rod radius, alpha > 0.699 rad, i.e.
        P < 2 pi r / tan(0.699) = 7.5 r; see
        :func:`supercoil.core.rod.contact.contact_width_ratio`).
    """
    si = check_rod(rod)
    r, L, B, C, mu = (si.radius, si.length, si.bending_rigidity, si.torsional_rigidity,
                      si.friction_coefficient)
    if isinstance(n_points, bool) or not isinstance(n_points, int | np.integer):
        raise TypeError(f"n_points must be an integer >= 10, got {n_points!r}")
    if n_points < 10:
        raise ValueError(f"n_points must be >= 10 (grid of the schedule: Simpson quadrature "
                         f"of N(S), linear interpolation of k in rough_helix), got {n_points}")
    cos2a_min = _sc.check_cos2a_min(cos2a_min)
    S_end = L * (1.0 - 1e-6) if slack_max is None else float(
        magnitude(slack_max, U.m, "slack_max"))
    if not 0 < S_end < L:
        raise ValueError(f"slack_max must lie in (0, L = {L:.6g} m), got {S_end:.6g} m")
    s_end = 0.5 * S_end
    s = np.linspace(0.0, s_end, int(n_points))

    check_callable(pitch, "pitch", "pitch(s) -> Quantity [length]")
    if pitch_derivative is not None:
        check_callable(pitch_derivative, "pitch_derivative",
                       "pitch_derivative(s) -> dimensionless Quantity")

    def P_si(x):
        x = np.asarray(x, float)
        p = magnitude(pitch(quantity(x, U.m)), U.m, "pitch(s)")
        return profile_values(p, x.shape, "pitch(s)").astype(float)

    P = P_si(s)
    if pitch_derivative is None:
        dP = _dh.derivative(P_si, s, 1e-4 * s_end, 0.0, s_end)
    else:
        d = magnitude(pitch_derivative(quantity(s, U.m)), U.dimensionless, "pitch_derivative(s)")
        dP = profile_values(d, s.shape, "pitch_derivative(s)")
        if not np.all(np.isfinite(dP)):
            i = int(np.flatnonzero(~np.isfinite(dP))[0])
            raise ValueError(f"pitch_derivative(s) must be finite, got {float(dP[i])!r} at "
                             f"s = {s[i] * 1e3:.9g} mm")
    out = _dh.schedule(s, P, dP, r, L, B, C, cos2a_min)
    a = out["alpha"]
    warn_hard_contact(a, "designed helix, pitch down to "
                         f"{float(np.min(out['pitch'])) * 1e3:.6g} mm")
    omega = _sc.twist_density(a, r, B, C)
    cols = {
        "slack": out["slack"] * 1e3,
        "turns": out["turns"],
        "tension": out["tension"],
        "s": out["s"] * 1e3,
        "pitch": out["pitch"] * 1e3,
        "alpha": a,
        "twist_rate": out["twist_rate"],
        "torque": C * omega * 1e3,
        "friction_torque_required": np.abs(C * _sc.dtwist_dalpha(a, r, B, C) * out["dalpha_ds"]),
    }
    units = dict(SCHEDULE_UNITS)
    if mu is not None:
        cols["friction_torque_available"] = _sc.friction_torque_available(a, r, B, mu)
    else:
        warn_no_friction("designed helix", "the schedule has no friction_torque_available "
                         "column")
        units.pop("friction_torque_available")
    return make_table(cols, units, provenance(rod, scene="design_twist_schedule",
                                              slack_max=f"{S_end:.12g} m", n_points=n_points))
