"""Case II, rough surface: the frozen non-uniform double helix (MODEL.md section 4).

Public unit wrapper over :mod:`supercoil.core.rough_helix` and
:mod:`supercoil.core.self_contact`.
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

from .core import rough_helix as _rh
from .core import self_contact as _sc
from .exceptions import NoHelixError, ValidityWarning
from .tables import column_quantity, make_table, provenance
from .units import U, as_turns, magnitude, quantity

__all__ = ["PROFILE_UNITS", "RoughHelix", "rough_helix", "twist_rate_function"]

#: Units of the profile columns (display units of the rod scenes).
PROFILE_UNITS = {
    "s": "mm",
    "slack": "mm",
    "alpha": "rad",
    "pitch": "mm",
    "omega": "1/mm",
    "curvature": "1/mm",
    "torsion": "1/mm",
    "tension": "N",
    "torque": "N*mm",
    "normal_force": "N/m",
    "friction_torque_required": "N",
    "friction_torque_available": "N",
    "curvature_error": "",
    "curvature_error_flag": "",
    "turns": "turn",
    "twist": "turn",
    "writhe": "turn",
}

_SCALE = {  # SI -> display unit factor
    "s": 1e3, "slack": 1e3, "pitch": 1e3, "omega": 1e-3, "curvature": 1e-3,
    "torsion": 1e-3, "torque": 1e3,
}


@dataclasses.dataclass(frozen=True)
class RoughHelix:
    """The frozen helix of a rough rod (result of :func:`rough_helix`).

    Attributes
    ----------
    alpha0 : Quantity [rad]
        Tilt at the head, from [eq ini].
    s_max : Quantity [mm]
        End of the helix along one strand: where alpha -> 0 (pitch -> infinity)
        when ``end == "alpha->0"``; otherwise the last s integrated
        (``end == "s_stop"``: slack limit or end of the twisting schedule).
    slip_onset : Quantity [mm] or None
        First s where the no-slip condition [eq friction con] fails
        (``C |d omega/ds| > dM_fmax/ds``); None where it holds everywhere, or
        when the friction coefficient is unknown (then a ValidityWarning said so).
    method : str
        ``"closed_form"`` ([eq example k=0]) or ``"ode"`` ([eq da/ds], solve_ivp).
    profile : pandas.DataFrame
        Columns over s (see :data:`PROFILE_UNITS`), units in ``attrs["units"]``,
        provenance in ``attrs["provenance"]``. ``tension`` and ``torque`` are the
        values measured while the helix end was at s (slack S = 2 s).
    curvature_error_onset : Quantity [mm] or None
        First s where ``|e - 1|`` (Appendix A) exceeds ``curvature_tolerance``.
    curvature_tolerance : float
        The tolerance used for ``curvature_error_onset`` and the
        ``curvature_error_flag`` column.
    turns : float
        Signed turns N_0 applied before slacking.
    end : str
        ``"alpha->0"`` or ``"s_stop"``.
    solver : dict
        ``ode_method``, ``rtol``, ``atol``, ``nfev`` (ODE) or ``{}`` (closed form).
    """

    alpha0: object
    s_max: object
    slip_onset: object
    method: str
    profile: object
    curvature_error_onset: object
    curvature_tolerance: float
    turns: float
    end: str
    solver: dict


def twist_rate_function(twist_rate, sign=1.0):
    """SI callable ``k(S [m]) -> rad/m`` from a callable, a table or a pair of arrays.

    Returns ``(kfun, slack_limit, is_zero)``: ``slack_limit`` is the last slack
    (m) the schedule covers (None for callables), ``is_zero`` is True for None or
    a zero constant.
    """
    if twist_rate is None:
        return (lambda S: np.zeros_like(np.asarray(S, float))), None, True
    if hasattr(twist_rate, "attrs") and hasattr(twist_rate, "columns"):
        if "slack" not in twist_rate.columns or "twist_rate" not in twist_rate.columns:
            raise ValueError("twist_rate table needs columns 'slack' and 'twist_rate'")
        slack_q = column_quantity(twist_rate, "slack")
        k_q = column_quantity(twist_rate, "twist_rate")
        twist_rate = (slack_q, k_q)
    if isinstance(twist_rate, tuple | list) and len(twist_rate) == 2:
        S_tab = np.asarray(magnitude(twist_rate[0], U.m, "twist_rate slack"), float)
        k_tab = np.asarray(magnitude(twist_rate[1], U.per_m, "twist_rate"), float) * sign
        if S_tab.ndim != 1 or S_tab.shape != k_tab.shape or S_tab.size < 2:
            raise ValueError("twist_rate table: slack and twist_rate must be 1-D, same length >= 2")
        if np.any(np.diff(S_tab) <= 0):
            raise ValueError("twist_rate table: slack must increase strictly")
        if S_tab[0] > 0:
            raise ValueError("twist_rate table must start at slack 0")
        zero = bool(np.all(k_tab == 0))
        return (lambda S: np.interp(S, S_tab, k_tab)), float(S_tab[-1]), zero
    if callable(twist_rate):

        def kfun(S):
            S = np.asarray(S, float)
            k = magnitude(twist_rate(quantity(S, U.m)), U.per_m, "twist_rate(slack)")
            return sign * np.broadcast_to(np.asarray(k, float), S.shape)

        return kfun, None, False
    k = float(magnitude(twist_rate, U.per_m, "twist_rate"))
    return (lambda S: np.full_like(np.asarray(S, float), sign * k)), None, k == 0.0


def rough_helix(rod, turns, twist_rate=None, method="auto", *, s=None, n_points=801,
                curvature_tolerance=0.01, slack_max=None, ode_method="auto",
                rtol=_rh.RTOL, atol=_rh.ATOL, cos2a_min=_sc.COS2A_MIN):
    """The frozen non-uniform helix of a rough rod twisted by N_0 turns, then slacked.

    MODEL.md s.4. No relative slip: alpha(s) is frozen once formed. The initial
    tilt comes from [eq ini] ``(1 - cos 2a0) tan 2a0 = (C/B) 4 pi r N_0 / L``;
    alpha(s) then follows [eq da/ds] with twisting rate ``k(S) = 2 pi dN/dS``.

    Parameters
    ----------
    rod : ElasticRod
        Needs ``friction_coefficient`` for the no-slip check.
    turns : number or dimensionless/angle Quantity
        Turns N_0 applied before the helix starts to form (scalar; sign gives the
        handedness, the helix is mirrored for N_0 < 0).
    twist_rate : None, Quantity [1/length], callable, DataFrame or (slack, k) pair
        ``k(S) = 2 pi dN/dS`` in rad per length of slack (``turn/m`` is
        converted, 1 turn = 2 pi rad), with the sign of N: for N_0 < 0 a
        negative k adds twist. A callable takes a slack Quantity and
        returns a Quantity (called with arrays and scalars). A table is a
        DataFrame with columns ``slack`` and ``twist_rate`` and units in
        ``attrs["units"]`` (e.g. from :func:`supercoil.design_twist_schedule`),
        or a pair of quantity arrays; it is linearly interpolated and the
        integration stops at its last slack. None or 0: k = 0 (Example I).
    method : {"auto", "closed_form", "ode"}
        ``"auto"``: closed form when k is None or zero, else the ODE.
        ``"closed_form"`` needs k = 0 ([eq example k=0]); ``"ode"`` integrates
        [eq da/ds] with ``solve_ivp`` for any k, including 0: in the variable
        ``y = 1 - cos 2 alpha`` (regular where alpha -> 0), with terminal events
        at ``y = 0`` (alpha -> 0, the end s_max) and ``cos 2 alpha = cos2a_min``
        (alpha -> pi/4); once y < 1e-3 and falling it integrates s(y) down to
        y = 0 instead, which stays regular when untwisting (k < 0) makes
        d alpha/ds diverge faster (see :func:`supercoil.core.rough_helix.integrate`).
    s : Quantity [length] array, optional
        Arclength grid of the profile (one strand, from the head); default: about
        ``n_points`` uniform points on [0, s_max) plus 60 points clustered toward
        s_max. The row alpha = 0 (pitch = inf) at s_max itself is never in the table.
    n_points : int
        Size of the uniform part of the default grid.
    curvature_tolerance : float
        Tolerance on ``|e - 1|`` (Appendix A) for ``curvature_error_flag`` and
        ``curvature_error_onset`` (default 0.01 = 1 %).
    slack_max : Quantity [length], optional
        Stop the ODE at this slack if no event fires first (default: the rod
        length less ``1e-6 L``; the ODE has a factor 1/(L - S)).
    ode_method : str
        ``solve_ivp`` method ("DOP853", "RK45", "Radau", "BDF", "LSODA", ...).
        Default "auto": "DOP853" for k = 0 (non-stiff; best accuracy per cost)
        and "LSODA" for non-zero k, because a twisting rate k > 0 drives alpha
        toward the fixed point ``sin 2a* = 2 r k`` of [eq da/ds], which is stiff
        when alpha* is small (DOP853 needs ~1e6 steps at k = 1 rad/m, LSODA
        ~700).
    rtol, atol : float
        ODE tolerances on ``y = 1 - cos 2 alpha`` (defaults 1e-10, 1e-12). With
        DOP853 at these defaults the ODE agrees with the closed form to better
        than 1e-8 rad along the whole k = 0 helix.
    cos2a_min : float
        Singularity guard: ``cos 2 alpha < cos2a_min`` counts as alpha -> pi/4.

    Returns
    -------
    RoughHelix

    Raises
    ------
    NoHelixError
        N_0 = 0 (alpha_0 = 0), or a grid point beyond s_max.
    SingularityError
        alpha_0 or alpha(s) reaches pi/4 (tension ~ 1/cos 2 alpha diverges).
    ValueError
        ``method="closed_form"`` with a non-zero twist rate, unknown method.

    Warns
    -----
    ValidityWarning
        When the rod has no friction coefficient (no-slip not checked, the
        ``friction_torque_available`` column is NaN and ``slip_onset`` is None).

    Notes
    -----
    Units of the profile: s, slack, pitch in mm; omega, curvature, torsion in
    1/mm; tension in N; torque ``C omega(S/2)`` (the tail twist moment at the
    fixed end) in N mm; normal force in N/m; friction torques per length in N.
    The normal force is ``F = B (1 - c)^2 / (4 r^3 c)`` and the available
    friction torque ``mu r cos(a) F``: the paper's [eq normal reaction] is half
    of F and its [eq friction] has one power of R too many (derivations in
    :mod:`supercoil.core.self_contact`). ``twist`` and ``writhe`` are the
    Calugareanu split at slack S = 2 s [Eq Lk=Tw+Wr] (trapezoid integrals along
    the grid); ``turns`` is N(S) = N_0 + (1/2 pi) int_0^S k dS'.
    """
    si = rod.si
    r, L, B, C, mu = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity, \
        si.friction_coefficient
    n0 = as_turns(turns, "turns")
    if np.ndim(n0) != 0:
        raise ValueError("rough_helix takes one value of turns (the profile is per N_0)")
    n0 = float(n0)
    sign = 1.0 if n0 >= 0 else -1.0
    alpha0 = float(_sc.initial_tilt(abs(n0), r, L, B, C))
    _sc.check_tilt(alpha0, f"initial tilt [eq ini], N_0 = {n0:g}, N_0 r / L = "
                   f"{abs(n0) * r / L:.3g}", cos2a_min)
    kfun, slack_limit, k_zero = twist_rate_function(twist_rate, sign)
    if method == "auto":
        method = "closed_form" if k_zero else "ode"
    if method not in ("closed_form", "ode"):
        raise ValueError(f"method must be 'auto', 'closed_form' or 'ode', got {method!r}")
    if method == "closed_form" and not k_zero:
        raise ValueError("method='closed_form' is Example I (k = 0); a non-zero twist_rate "
                         "needs method='ode'")
    s_user = None if s is None else np.atleast_1d(np.asarray(magnitude(s, U.m, "s"), float))

    if method == "closed_form":
        s_end = float(_rh.k0_s_max(alpha0, L, B, C))
        end = "alpha->0"
        s_stop = 0.5 * L * (1.0 - _rh.TAIL_FRACTION_MIN)
        if s_end > s_stop:  # the helix would take (almost) the whole rod
            s_end, end = s_stop, "s_stop"
        if slack_max is not None:
            smax_user = 0.5 * float(magnitude(slack_max, U.m, "slack_max"))
            if smax_user < s_end:
                s_end, end = smax_user, "s_stop"

        def y_at(x):
            return _rh.k0_y_of_s(x, alpha0, L, B, C)

        def dy_at(x, y):
            return _rh.k0_dy_ds(x, y, L, B, C)

        solver = {}
    else:
        if ode_method == "auto":
            ode_method = "DOP853" if k_zero else "LSODA"
        s_stop = 0.5 * L * (1.0 - _rh.TAIL_FRACTION_MIN)
        if slack_max is not None:
            s_stop = min(s_stop, 0.5 * float(magnitude(slack_max, U.m, "slack_max")))
        if slack_limit is not None:
            s_stop = min(s_stop, 0.5 * slack_limit)
        integ = _rh.integrate(alpha0, None if k_zero else kfun, r, L, B, C, s_stop=s_stop,
                              ode_method=ode_method,
                              rtol=rtol, atol=atol, cos2a_min=cos2a_min)
        s_end, end = integ.s_end, integ.reason
        y_at, dy_at = integ.y, integ.dy
        solver = {"ode_method": ode_method, "rtol": rtol, "atol": atol, "nfev": int(integ.nfev)}

    if s_user is None:
        grid = _rh.profile_grid(s_end, n_points, 60 if end == "alpha->0" else 0,
                                include_end=(end != "alpha->0"))
    else:
        grid = s_user
        if np.any(grid < 0) or np.any(grid > s_end) or (
                end == "alpha->0" and np.any(grid >= s_end)):
            raise NoHelixError(
                f"profile grid s outside the helix [0, s_max = {s_end * 1e3:.9g} mm)"
                + (": alpha = 0 and the pitch is infinite at s_max" if end == "alpha->0" else "")
            )
    y = np.asarray(y_at(grid), float)
    dyds = np.asarray(dy_at(grid, y), float)
    k_grid = kfun(2.0 * grid)
    dN = np.concatenate(([0.0], np.cumsum(0.5 * (k_grid[1:] + k_grid[:-1]) * np.diff(grid))))
    turns_abs = abs(n0) + dN / np.pi  # (1/2pi) int k dS, dS = 2 ds

    cols = _rh.profile_columns(grid, y, dyds, turns_abs, r, L, B, C, mu)
    if mu is None:
        warnings.warn(
            "rod.friction_coefficient is None: the no-slip condition [eq friction con] is "
            "not checked; slip_onset is None and friction_torque_available is NaN",
            ValidityWarning, stacklevel=2)
        cols["friction_torque_available"] = np.full_like(grid, np.nan)
        slip = None
    else:
        g = cols["friction_torque_required"] - cols["friction_torque_available"]
        slip = _rh.first_crossing(grid, g, _rh.slip_function(y_at, dy_at, r, B, mu))
    err = np.abs(cols["curvature_error"] - 1.0)
    ce_onset = _rh.first_crossing(
        grid, err - curvature_tolerance,
        _rh.curvature_error_function(y_at, dy_at, r, curvature_tolerance))

    cols["torque"] = C * cols["omega"]
    for key in ("omega", "torque", "twist", "writhe", "turns"):
        cols[key] = sign * cols[key]
    cols["curvature_error_flag"] = err > curvature_tolerance
    order = ["s", "slack", "alpha", "pitch", "omega", "curvature", "torsion", "tension",
             "torque", "normal_force", "friction_torque_required", "friction_torque_available",
             "curvature_error", "curvature_error_flag", "turns", "twist", "writhe"]
    table = {c: cols[c] * _SCALE[c] if c in _SCALE else cols[c] for c in order}
    prov = provenance(rod, turns=n0, method=method, twist_rate=_describe(twist_rate),
                      curvature_tolerance=curvature_tolerance, end=end, **solver)
    profile = make_table(table, PROFILE_UNITS, prov)
    return RoughHelix(
        alpha0=quantity(alpha0, U.rad),
        s_max=quantity(s_end * 1e3, U.mm),
        slip_onset=None if slip is None else quantity(slip * 1e3, U.mm),
        method=method,
        profile=profile,
        curvature_error_onset=None if ce_onset is None else quantity(ce_onset * 1e3, U.mm),
        curvature_tolerance=float(curvature_tolerance),
        turns=n0,
        end=end,
        solver=solver,
    )


def _describe(twist_rate):
    if twist_rate is None:
        return "0 (k = 0)"
    if hasattr(twist_rate, "attrs"):
        return "table"
    if callable(twist_rate):
        return getattr(twist_rate, "__name__", "callable")
    if isinstance(twist_rate, tuple | list):
        return "table"
    return str(twist_rate)
