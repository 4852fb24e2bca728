"""Case II, rough surface: the frozen non-uniform double helix (docs/theory/rough.md).

Public unit wrapper over :mod:`supercoil.core.rod.rough` and
:mod:`supercoil.core.rod.contact`.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from supercoil._checks import profile_values
from supercoil.core.rod import contact as _sc
from supercoil.core.rod import rough as _rh
from supercoil.exceptions import DataError, ValidityError
from supercoil.records import Record
from supercoil.rod.material import check_rod
from supercoil.rod.smooth import checked_turns
from supercoil.rod.validity import check_finite, warn_hard_contact, warn_no_friction
from supercoil.tables import column_quantity, provenance
from supercoil.units import U, magnitude, quantity

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


class RoughHelix(Record):
    """The frozen helix of a rough rod (result of :func:`rough_helix`).

    Attributes
    ----------
    alpha0 : Quantity [rad]
        Tilt at the head, from [eq ini].
    s_max : Quantity [mm] or None
        End of the helix along one strand, where alpha -> 0 (pitch -> infinity),
        or the end of the rod if the helix takes it all. It is the true end, never
        the place where the computation stopped: ``s_end`` when ``end ==
        "alpha->0"``; [s_max] of the closed form when k = 0 and the run stopped
        earlier at ``slack_max`` (k = 0 beyond the stop, too); ``s_end`` when the
        run reached the rod's end ((L/2)(1 - 1e-6), the helix takes the whole
        rod). None when a non-zero twisting rate stopped at ``slack_max`` or at
        the last slack of a schedule table: the end then depends on how
        twisting continues.
    s_end : Quantity [mm]
        Last s integrated (the profile ends there or, for ``end == "alpha->0"``,
        just before it).
    slip_onset : Quantity [mm] or None
        First s >= 0 where the no-slip condition [eq friction con] fails
        (``C |d omega/ds| > dM_fmax/ds``), found on an internal grid from the
        head (independent of the profile grid ``s``); 0 if it fails at the head;
        None where it holds on [0, s_end], or when the friction coefficient is
        unknown (then a ValidityWarning said so).
    method : str
        ``"closed_form"`` ([eq example k=0]) or ``"ode"`` ([eq da/ds], solve_ivp).
    profile : pandas.DataFrame
        Columns over s (see :data:`PROFILE_UNITS`), units in ``attrs["units"]``,
        provenance in ``attrs["provenance"]``. ``tension`` and ``torque`` are the
        values measured while the helix end was at s (slack S = 2 s).
    curvature_error_onset : Quantity [mm] or None
        First s >= 0 where ``|e - 1|`` (Appendix A) exceeds ``curvature_tolerance``
        (internal grid from the head, like ``slip_onset``).
    curvature_tolerance : float
        The tolerance used for ``curvature_error_onset`` and the
        ``curvature_error_flag`` column.
    turns : Quantity [turn]
        Signed turns N_0 applied before slacking.
    end : str
        Why the integration ended: ``"alpha->0"`` (the helix end) or ``"s_stop"``
        (``slack_max``, the last slack of a schedule table, or the rod's end).
    solver : dict
        ``ode_method``, ``rtol``, ``atol``, ``nfev`` (ODE) or ``{}`` (closed form).
    """

    __slots__ = ()
    DOMAIN = "rod"
    FIELDS = ("alpha0", "s_max", "slip_onset", "curvature_error_onset", "turns", "s_end")
    EXTRA = ("method", "profile", "curvature_tolerance", "end", "solver")


def _is_table(x):
    return hasattr(x, "attrs") and hasattr(x, "columns")


def twist_rate_function(twist_rate, sign=1.0):
    """SI callable ``k(S [m]) -> rad/m`` from a callable, a table or a pair of arrays.

    Returns ``(kfun, slack_limit, is_zero, nodes)``: ``slack_limit`` is the last
    slack (m) the schedule covers (None for callables and constants),
    ``is_zero`` is True for None or a zero constant, ``nodes`` the table's slack
    values (m; empty otherwise), where the interpolated k has kinks.

    Raises
    ------
    ValueError
        A constant or a table entry that is NaN or infinite (message names
        ``twist_rate`` or its ``slack``), a table that is not 1-D, increasing
        and starting at slack 0, or a sequence that is not a (slack, k) pair.
    DataError
        A DataFrame without the columns ``slack`` and ``twist_rate`` or without
        their units in ``attrs["units"]``.
    ValidityError
        From the returned function, when a callable ``twist_rate`` returns NaN
        or inf (the message names the slack).
    """
    if twist_rate is None:
        return _zero_rate, None, True, np.empty(0)
    if _is_table(twist_rate):
        twist_rate = _table_pair(twist_rate)
    if isinstance(twist_rate, tuple | list):
        return _table_rate(twist_rate, sign)
    if callable(twist_rate):
        return _callable_rate(twist_rate, sign), None, False, np.empty(0)
    k = magnitude(twist_rate, U.per_m, "twist_rate")
    if np.ndim(k) != 0:
        raise ValueError("twist_rate must be a scalar quantity (constant rate), a callable, "
                         "a table or a (slack, twist_rate) pair; got an array of shape "
                         f"{np.shape(k)}")
    k = float(k)
    if not np.isfinite(k):
        raise ValueError(f"twist_rate must be finite, got {k!r} rad/m")
    return (lambda S: np.full_like(np.asarray(S, float), sign * k)), None, k == 0.0, np.empty(0)


def _zero_rate(S):
    return np.zeros_like(np.asarray(S, float))


def _table_pair(table):
    """(slack, twist_rate) quantities from a DataFrame with ``attrs["units"]``."""
    if "slack" not in table.columns or "twist_rate" not in table.columns:
        raise DataError("twist_rate table needs columns 'slack' and 'twist_rate', got "
                        f"{list(table.columns)}")
    units = table.attrs.get("units") or {}
    missing = [c for c in ("slack", "twist_rate") if c not in units]
    if missing:
        raise DataError(
            "twist_rate table needs its units in attrs['units'] for 'slack' and "
            f"'twist_rate' (missing: {missing}); e.g. the table of "
            "supercoil.design_twist_schedule, or a (slack, twist_rate) pair of quantities")
    return column_quantity(table, "slack"), column_quantity(table, "twist_rate")


def _table_rate(pair, sign):
    """Linear interpolation of a checked (slack, k) table: ``(kfun, S_last, zero, nodes)``."""
    if len(pair) != 2:
        raise ValueError(
            f"twist_rate given as a {type(pair).__name__} of length "
            f"{len(pair)}: a sequence must be a (slack, twist_rate) pair of quantity "
            "arrays (the schedule table); use a scalar quantity for a constant rate")
    S_tab = np.asarray(magnitude(pair[0], U.m, "twist_rate slack"), float)
    k_tab = np.asarray(magnitude(pair[1], U.per_m, "twist_rate"), float) * sign
    if S_tab.ndim != 1 or S_tab.shape != k_tab.shape or S_tab.size < 2:
        raise ValueError("twist_rate table: slack and twist_rate must be 1-D, same length >= 2")
    for name, arr in (("slack", S_tab), ("twist_rate", k_tab)):
        if not np.all(np.isfinite(arr)):
            i = int(np.flatnonzero(~np.isfinite(arr))[0])
            raise ValueError(f"twist_rate table: {name} must be finite, got "
                             f"{float(arr[i])!r} in row {i}")
    if np.any(np.diff(S_tab) <= 0):
        raise ValueError("twist_rate table: slack must increase strictly")
    if S_tab[0] > 0:
        raise ValueError("twist_rate table must start at slack 0")
    if S_tab[-1] <= 0:
        raise ValueError("twist_rate table must extend to a positive slack")
    zero = bool(np.all(k_tab == 0))
    return (lambda S: np.interp(S, S_tab, k_tab)), float(S_tab[-1]), zero, S_tab


def _callable_rate(twist_rate, sign):
    """SI wrapper of a twist-rate callable, refusing NaN/inf results (names the slack)."""

    def kfun(S):
        S = np.asarray(S, float)
        k = magnitude(twist_rate(quantity(S, U.m)), U.per_m, "twist_rate(slack)")
        k = profile_values(k, S.shape, "twist_rate(slack)")
        if not np.all(np.isfinite(k)):
            i = np.flatnonzero(~np.isfinite(k).reshape(-1))[0]
            raise ValidityError(
                f"twist_rate(slack) returned {float(k.reshape(-1)[i])!r} rad/m at slack S = "
                f"{float(np.broadcast_to(S, k.shape).reshape(-1)[i]):.9g} m: the "
                "twisting rate must be finite")
        return sign * k

    return kfun


#: Uniform points of the internal grid on which :func:`rough_helix` locates the
#: slip and curvature-error onsets and breaks the Tw, Wr, N quadratures (plus 60
#: points clustered toward s_max and the nodes of a twist-rate table).
INTERNAL_POINTS = _rh.INTERNAL_POINTS


def _user_grid(s):
    """The profile grid ``s`` in m, checked: 1-D, finite, strictly increasing, >= 1 point."""
    g = np.asarray(magnitude(s, U.m, "s"), float)
    if g.ndim > 1:
        raise ValueError(f"s must be a scalar or a 1-D array, got shape {g.shape}")
    g = np.atleast_1d(g)
    if g.size == 0:
        raise ValueError("s must contain at least one point")
    if not np.all(np.isfinite(g)):
        raise ValueError(f"s must be finite, got {float(g[~np.isfinite(g)][0])!r} m")
    if np.any(np.diff(g) <= 0):
        i = int(np.flatnonzero(np.diff(g) <= 0)[0])
        raise ValueError(f"s must increase strictly (sorted, no repeats): s[{i + 1}] = "
                         f"{g[i + 1] * 1e3:.9g} mm <= s[{i}] = {g[i] * 1e3:.9g} mm")
    return g


def rough_helix(rod, turns, twist_rate=None, method="auto", *, s=None, n_points=801,
                curvature_tolerance=0.01, slack_max=None, ode_method="auto",
                rtol=_rh.RTOL, atol=_rh.ATOL, cos2a_min=_sc.COS2A_MIN, max_nfev=_rh.MAX_NFEV):
    """The frozen non-uniform helix of a rough rod twisted by N_0 turns, then slacked.

    docs/theory/rough.md. No relative slip: alpha(s) is frozen once formed. The initial
    tilt comes from [eq ini] ``(1 - cos 2a0) tan 2a0 = (C/B) 4 pi r N_0 / L``;
    alpha(s) then follows [eq da/ds] with twisting rate ``k(S) = 2 pi dN/dS``.

    Parameters
    ----------
    rod : ElasticRod
        Needs ``friction_coefficient`` for the no-slip check.
    turns : number or dimensionless/angle Quantity
        Turns N_0 applied before the helix starts to form (scalar, finite; sign
        gives the handedness, the helix is mirrored for N_0 < 0).
    twist_rate : None, Quantity [1/length], callable, DataFrame or (slack, k) pair
        ``k(S) = 2 pi dN/dS`` in rad per length of slack (``turn/m`` is
        converted, 1 turn = 2 pi rad), with the sign of N: for N_0 < 0 a
        negative k adds twist. A callable takes a slack Quantity and
        returns a Quantity (called with arrays and scalars). A table is a
        DataFrame with columns ``slack`` and ``twist_rate`` and units in
        ``attrs["units"]`` (e.g. from :func:`supercoil.design_twist_schedule`),
        or a pair of quantity arrays; it is linearly interpolated and the
        integration stops at its last slack. None or 0: k = 0 (Example I).
        k must be finite everywhere (checked for constants and tables; a
        callable returning NaN or inf raises ValidityError naming the slack).
    method : {"auto", "closed_form", "ode"}
        ``"auto"``: closed form when k is None or zero, else the ODE.
        ``"closed_form"`` needs k = 0 ([eq example k=0]); ``"ode"`` integrates
        [eq da/ds] with ``solve_ivp`` for any k, including 0: in the variable
        ``y = 1 - cos 2 alpha`` (regular where alpha -> 0), with terminal events
        at ``y = 0`` (alpha -> 0, the end s_max) and ``cos 2 alpha = cos2a_min``
        (alpha -> pi/4); once y < 1e-3 and falling it integrates s(y) down to
        y = 0 instead, which stays regular when untwisting (k < 0) makes
        d alpha/ds diverge faster (see :func:`supercoil.core.rod.rough.integrate`).
    s : Quantity [length], scalar or 1-D array, optional
        Arclength points of the profile (one strand, from the head): finite,
        strictly increasing, within [0, s_max) (or [0, s_end] when the run
        stops before the helix ends). They may start anywhere and be coarse:
        every column, including the cumulative ``twist``, ``writhe`` and
        ``turns``, is exact at each point (see Notes). Default: about
        ``n_points`` uniform points on [0, s_max) plus 60 points clustered
        toward s_max. The row alpha = 0 (pitch = inf) at s_max itself is never
        in the table.
    n_points : int
        Size of the uniform part of the default grid, >= 2 (the grid only
        chooses where the profile is reported; no reported number depends on it).
    curvature_tolerance : float
        Tolerance on ``|e - 1|`` (Appendix A) for ``curvature_error_flag`` and
        ``curvature_error_onset`` (default 0.01 = 1 %); finite and > 0.
    slack_max : Quantity [length], optional
        Stop at this slack (> 0) if the helix does not end first (default: the
        rod length less ``1e-6 L``; the ODE has a factor 1/(L - S)).
    ode_method : str
        ``solve_ivp`` method ("DOP853", "RK45", "Radau", "BDF", "LSODA", ...).
        Default "auto": "DOP853" for k = 0 (non-stiff; best accuracy per cost)
        and "LSODA" for non-zero k, because a twisting rate k > 0 drives alpha
        toward the fixed point ``sin 2a* = 2 r k`` of [eq da/ds], which is stiff
        when alpha* is small (DOP853 needs ~1e6 steps at k = 1 rad/m, LSODA
        ~700).
    rtol, atol : float
        ODE tolerances on ``y = 1 - cos 2 alpha`` (defaults 1e-10, 1e-12);
        ``0 < rtol <= 0.1`` (looser steps can leave [0, 1]) and ``atol > 0``;
        atol is capped at ``rtol * y_0`` (y at the head), which matters only
        for a tiny N_0 (``solver["atol"]`` reports the value used).
        With DOP853 at the defaults the ODE agrees with the closed form along
        the whole k = 0 helix (default grid, to s_max (1 - 1e-7)) to 1e-8 rad
        on the paper's rods, and to 1.3e-8 rad at worst over 391 random rods
        (N_0 2-300, r 0.3-3 mm, L 0.3-3 m; the worst at N_0 r / L = 0.44, at
        the last grid point); y = 1 - cos 2 alpha to 2e-10, the end s_max
        to 3e-12 relative (measured).
    cos2a_min : float
        Singularity guard in (0, 1): ``cos 2 alpha < cos2a_min`` counts as
        alpha -> pi/4.
    max_nfev : int
        Budget of ODE right-side evaluations (>= 1; default 100 000, about 30
        times the longest typical run): a run that needs more ends in a SingularityError naming
        the twisting rate and the slack reached, never in an endless solver
        call (typical runs need 50-3000; ``solver["nfev"]`` reports them).

    Returns
    -------
    RoughHelix

    Raises
    ------
    NoHelixError
        N_0 = 0 (alpha_0 = 0), or a grid point beyond the helix (at or beyond
        s_max, where alpha = 0, or beyond s_end).
    SingularityError
        alpha_0 or alpha(s) reaches pi/4 (tension ~ 1/cos 2 alpha diverges),
        the ODE solver fails, or it spends its budget ``max_nfev`` (e.g.
        ``twist_rate = 1e300 rad/m``); the message names the twisting rate.
    ValidityError
        A callable twist rate returns NaN or inf (the message names the slack);
        a profile column would not be finite (floating-point range exceeded).
    DataError
        A twist-rate DataFrame without the columns or their ``attrs["units"]``.
    ValueError
        ``method="closed_form"`` with a non-zero twist rate, an unknown method;
        a non-finite turns or twist rate; a grid ``s`` that is not finite and
        strictly increasing; n_points < 2; max_nfev < 1; curvature_tolerance, slack_max,
        rtol, atol or cos2a_min out of range (the message names the argument
        and the limit).
    TypeError
        turns None or text, n_points or max_nfev not an integer.

    Warns
    -----
    ValidityWarning
        When the rod has no friction coefficient (no-slip not checked, the
        ``friction_torque_available`` column is NaN and ``slip_onset`` is None).
        When hard contact fails somewhere on the helix long before the pi/4
        singularity: the Hertz contact half-width exceeds the rod radius,
        ``b / r = sin^2 a / sqrt(cos 2a) > 1`` (alpha > 0.699 rad; see
        :func:`supercoil.core.rod.contact.contact_width_ratio`).

    Notes
    -----
    Units of the profile: s, slack, pitch in mm; omega, curvature, torsion in
    1/mm; tension in N; torque ``C omega(S/2)`` (the tail twist moment at the
    fixed end) in N mm; normal force in N/m; friction torques per length in N.
    The normal force is ``F = B (1 - c)^2 / (4 r^3 c)`` and the available
    friction torque ``mu r cos(a) F``: the paper's [eq normal reaction] is half
    of F and its [eq friction] has one power of R too many (derivations in
    :mod:`supercoil.core.rod.contact`). ``twist`` and ``writhe`` are the
    Calugareanu split at slack S = 2 s [Eq Lk=Tw+Wr],
    ``Tw = (1/pi) int_0^s omega + omega(s) (L - 2s) / 2 pi`` and
    ``Wr = (1/pi) int_0^s tau``; ``turns`` is N(S) = N_0 + (1/2 pi) int_0^S k dS'.
    The three integrals run from the head on an internal grid (801 uniform
    points, 60 toward s_max and the nodes of a twist-rate table), and from
    the nearest internal node to every point of ``s``, by adaptive
    Gauss-Legendre quadrature (:func:`supercoil.core.rod.rough.strand_integrals`),
    so ``Tw + Wr = N`` holds to the solver's accuracy (1e-9 relative, ~5e-8 turns at
    N_0 = 40 with LSODA at the default tolerances) on any grid ``s``. The slip
    and curvature-error onsets are searched on the same internal grid from s = 0.

    The algorithm is :func:`supercoil.core.rod.rough.rough_profile` (this
    function checks the units and arguments, calls it and wraps the result).
    The profile is computed in chunks of 4096 points: beyond the table (129
    bytes per point) it needs a bounded working set, 27 bytes per point at
    n_points = 2e5 and 5 at 1e6 (measured with tracemalloc).
    """
    si = check_rod(rod)
    n0 = checked_turns(turns, "turns")
    if np.ndim(n0) != 0:
        raise ValueError("rough_helix takes one value of turns (the profile is per N_0)")
    n0 = float(n0)
    _check_count(n_points, "n_points", 2, " (the default grid spans [0, s_max) with "
                 "n_points uniform points)")
    _check_count(max_nfev, "max_nfev", 1, " (the budget of ODE right-side evaluations)")
    curvature_tolerance = _sc.check_scalar(curvature_tolerance, "curvature_tolerance",
                                           0.0, np.inf, what=" (a tolerance on |e - 1|)")
    cos2a_min = _sc.check_cos2a_min(cos2a_min)
    kfun, slack_limit, k_zero, k_nodes = twist_rate_function(twist_rate, 1.0 if n0 >= 0 else -1.0)
    method = _resolve_method(method, k_zero)
    res = _rh.rough_profile(
        n0, si.radius, si.length, si.bending_rigidity, si.torsional_rigidity,
        si.friction_coefficient, kfun=None if k_zero else kfun, k_zero=k_zero, method=method,
        grid=None if s is None else _user_grid(s), n_points=int(n_points),
        slack_max=_slack_max(slack_max), slack_table=slack_limit, k_nodes=k_nodes,
        curvature_tolerance=curvature_tolerance, ode_method=ode_method, rtol=rtol, atol=atol,
        cos2a_min=cos2a_min, max_nfev=int(max_nfev))
    warn_hard_contact(res.alpha_max, f"rough helix, N_0 = {n0:g}, max over [0, s_end]")
    if si.friction_coefficient is None:
        warn_no_friction("rough helix", "slip_onset is None and friction_torque_available is NaN")
    profile = _profile_table(res, rod, n0, method, twist_rate, curvature_tolerance)

    return RoughHelix(
        alpha0=res.alpha0, s_max=res.s_max, slip_onset=res.slip_onset,
        curvature_error_onset=res.curvature_error_onset, turns=float(n0), s_end=res.s_end,
        method=method, profile=profile, curvature_tolerance=float(curvature_tolerance),
        end=res.end, solver=res.solver)


def _check_count(value, name, least, what):
    if isinstance(value, bool) or not isinstance(value, int | np.integer):
        raise TypeError(f"{name} must be an integer >= {least}, got {value!r}")
    if value < least:
        raise ValueError(f"{name} must be >= {least}{what}, got {value}")


def _resolve_method(method, k_zero):
    if method == "auto":
        method = "closed_form" if k_zero else "ode"
    if method not in ("closed_form", "ode"):
        raise ValueError(f"method must be 'auto', 'closed_form' or 'ode', got {method!r}")
    if method == "closed_form" and not k_zero:
        raise ValueError("method='closed_form' is Example I (k = 0); a non-zero twist_rate "
                         "needs method='ode'")
    return method


def _slack_max(slack_max):
    """slack_max in m (or None), checked > 0 and finite."""
    if slack_max is None:
        return None
    S = magnitude(slack_max, U.m, "slack_max")
    if np.ndim(S) != 0 or not np.isfinite(S) or not S > 0:
        raise ValueError(f"slack_max must be > 0 and finite (the slack at which to stop), "
                         f"got {slack_max!r}")
    return float(S)


def _profile_table(res, rod, n0, method, twist_rate, curvature_tolerance):
    """The profile DataFrame in display units, built without copying the columns.

    Like :func:`supercoil.tables.make_table` (units in ``attrs["units"]``,
    provenance in ``attrs["provenance"]``), but the kernel's column arrays are
    scaled in place and handed to pandas uncopied: a profile of n points then
    needs the output (129 bytes per point) plus a bounded working set.
    """
    cols = res.columns
    with np.errstate(over="ignore", invalid="ignore"):
        for c, factor in _SCALE.items():
            cols[c] *= factor
    checked = [c for c in cols if c != "curvature_error_flag"
               and not (c == "friction_torque_available" and rod.si.friction_coefficient is None)]
    check_finite({f"{c} [{PROFILE_UNITS[c]}]": cols[c] for c in checked},
                 f"rough helix, N_0 = {n0!r}")
    prov = provenance(rod, turns=n0, method=method, twist_rate=_describe(twist_rate),
                      curvature_tolerance=curvature_tolerance, end=res.end, **res.solver)
    df = pd.DataFrame(cols, copy=False)
    df.attrs["units"] = {c: PROFILE_UNITS[c] for c in cols}
    df.attrs["provenance"] = prov
    return df


def _describe(twist_rate):
    if twist_rate is None:
        return "0 (k = 0)"
    if _is_table(twist_rate):
        return "table"
    if callable(twist_rate):
        return getattr(twist_rate, "__name__", "callable")
    if isinstance(twist_rate, tuple | list):
        return "table"
    return str(twist_rate)
