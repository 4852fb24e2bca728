"""Stability map: where each solver fails or loses accuracy over its inputs (issue 5).

Every public solver is evaluated on a 2-D grid of its natural inputs that runs
well into its failure regions, and every cell is classified:

``ok``
    a finite result, no warning, and (where an independent reference is cheap)
    accurate to the tolerance stated below for that solver;
``flagged``
    a :class:`~supercoil.exceptions.SupercoilWarning` (``ValidityWarning``) was
    issued, or a flag of the result is set (``curvature_error_flag``, the rough
    helix slips at this s, ``short_tail``, the designed helix needs more
    friction than available);
``named error: <Class>``
    a supercoil exception, a ``pint.DimensionalityError`` or a plain
    ``ValueError`` with a message;
``WRONG``
    a NaN or inf returned silently, an unnamed exception (``ZeroDivisionError``,
    ``IndexError``, ...), a numpy floating-point ``RuntimeWarning`` or another
    foreign warning, or a number that misses its reference.

Grids and references (``quick=True`` uses coarser grids of the same ranges).
For the rods, a tilt returned with ``cos 2 alpha`` below the package's own
singularity guard (1e-9) is WRONG: the solver should have raised.

* ``smooth_helix``: turns N (0 and 1e-3 .. 1e13) x slack S/L (-0.05 .. 1.1).
  Reference: the hard-contact relation (HC) must hold for the omega of the
  linking balance, ``|omega - omega_HC| <= 1e-6 |omega_HC|`` (the tilt is
  solved to one float spacing; within ``cos 2 alpha ~ 1e-9`` of pi/4 that
  alone is ~1e-7), and ``Lk = Tw + Wr = N`` to 1e-12.
* ``rough_helix`` (closed form; ODE with k = 0, k = +100 and -100 rad/m):
  twist load N r / L (0 and 1e-9 .. 1e10) x s/s_max (0 .. 1 - 1e-9, and 1,
  1.01 beyond the end). References: the closed form for the ODE at k = 0, a
  DOP853 integration at rtol 1e-13 for the closed form, and LSODA at rtol
  1e-13 (checked against Radau) for k != 0. A cell is accurate when
  ``y = 1 - cos 2 alpha`` lies within 1e-8 of the reference curve in y or in
  s/L, i.e. ``|dy| <= 1e-8 + |dy/ds| 1e-8 L`` (alpha(s) has a vertical tangent
  at s_max); [eq ini] must hold for alpha_0 to a backward error of 1e-12.
* ``design_twist_schedule``: the paper's sinusoidal profile
  ``P = P0 + P1 sin(2 pi s / (10 P0))`` over P0 / (2 pi r) (0.5 .. 1000) x
  P1 / P0 (0 .. 1.2), whole rod. Reference: the linking number of the designed
  helix at the last slack, ``N = (1/pi) int (omega + tau) ds + omega (L - 2s)
  / 2 pi`` (adaptive quadrature of the analytic profile), to 1e-6 relative.
* ``twist_spinning``: turns N (0 and 1e-4 .. 1e13) x head tension T'
  (-1, 0 and 1e-6 .. 1e6 N). Reference: [f4] to a backward error of 1e-12,
  beta from the cancellation-free form ``sec(beta) - 1 = 2 T_s / T' -
  2 sin^2(alpha/2)`` to 1e-6 relative, and T' = 0 giving the slacking helix.
* ``plectoneme_equilibrium``: force (-1, 0 and 1e-4 .. 1e6 pN) x bending
  persistence A (2 .. 2000 nm; the molecule length does not enter).
  Reference: the residuals of (GE1), (GE2) and the tension equation in their
  unreduced form, each <= 1e-10.
* ``extension_factor``: force (0 and 1e-3 .. 1e6 pN) x torque (0 and
  1e-2 .. 1e5 pN nm), tail 750 nm. Reference: the formula in 40-digit decimal
  arithmetic, ``|d zeta| <= 1e-12 max(1, |zeta|)``.
* ``hat_curve`` (thermal and athermal): force (0 and 1e-3 .. 1e6 pN) x molecule
  length (20 nm .. 50 um). Each cell is one hat curve over 17 turns from 0 to
  the point where the plectoneme holds half the molecule (S = L/2). Reference:
  every point rebuilt from its phase (stretched: torque ``C_eff 2 pi N / L``,
  ``z = zeta L``; plectoneme: the linking balance and ``z = zeta (L - S)``)
  to 1e-9, and unflagged points physical: ``0 <= z <= L``, z not increasing
  with N.

:func:`run` returns the convention table, :func:`plot` draws the maps,
:func:`summary` counts outcomes and :func:`regions` gives the input ranges of
every outcome.
"""

from __future__ import annotations

import dataclasses
import decimal
import time
import warnings

import numpy as np

__all__ = ["CATEGORIES", "COLORS", "Axis", "plot", "regions", "run", "summary"]

#: the four outcome categories, in legend order
CATEGORIES = ("ok", "flagged", "named error", "WRONG")
#: colour of each category in :func:`plot`
COLORS = {"ok": "#4daf4a", "flagged": "#ffbf00", "named error": "#377eb8", "WRONG": "#e41a1c"}

_IGNORED_WARNINGS = (DeprecationWarning, PendingDeprecationWarning, FutureWarning)

# rough-helix accuracy: distance to the reference curve in y and in s/L
ROUGH_TOL_Y = 1e-8
ROUGH_TOL_S = 1e-8


@dataclasses.dataclass(frozen=True)
class Axis:
    """One input axis of a map: table column, plot label, unit, grid values."""

    column: str
    label: str
    unit: str
    values: np.ndarray


# ---------------------------------------------------------------------------
# calling a solver and classifying what came out
# ---------------------------------------------------------------------------


def _call(func):
    """``func()`` with every warning recorded: ``(value, exception, warnings)``."""
    with warnings.catch_warnings(record=True) as rec, \
            np.errstate(divide="warn", over="warn", invalid="warn", under="ignore"):
        warnings.simplefilter("always")
        try:
            value, exc = func(), None
        except Exception as e:  # classified by the caller
            value, exc = None, e
    return value, exc, [w for w in rec if not issubclass(w.category, _IGNORED_WARNINGS)]


def _named(exc):
    """Exception class name if ``exc`` is a named error, else None."""
    import pint

    from supercoil.exceptions import SupercoilError

    if isinstance(exc, SupercoilError | pint.DimensionalityError):
        return type(exc).__name__
    if type(exc) is ValueError and str(exc).strip():
        return "ValueError"
    return None


def _verdict(exc=None, warns=(), problems=(), flags=(), soft=()):
    """``(outcome, detail)`` from an exception, recorded warnings, problems and flags.

    ``soft`` problems (a number outside its physical range) make the cell WRONG only
    if the solver issued no :class:`~supercoil.exceptions.SupercoilWarning`.
    """
    from supercoil.exceptions import SupercoilWarning

    foreign = [w for w in warns if not issubclass(w.category, SupercoilWarning)]
    ours = [w for w in warns if issubclass(w.category, SupercoilWarning)]
    if foreign:
        w = foreign[0]
        return "WRONG", f"unnamed warning {w.category.__name__}: {w.message}"
    if exc is not None:
        name = _named(exc)
        if name is None:
            return "WRONG", f"unnamed exception {type(exc).__name__}: {exc}"
        return f"named error: {name}", str(exc)
    if problems or (soft and not ours):
        return "WRONG", "; ".join([*problems, *soft])
    if ours or flags:
        parts = [f"{w.category.__name__}: {w.message}" for w in ours] + list(flags)
        return "flagged", "; ".join(parts)
    return "ok", ""


def _category(outcome):
    return "named error" if outcome.startswith("named error") else outcome


def _root_ok(h, a, scale, rtol=1e-12, ulps=4):
    """Backward-error test of a root ``a`` of ``h``: ``|h(a)| <= rtol scale`` or within
    ``ulps`` float spacings of ``a`` times ``|h'(a)|`` (near pi/4 the equations are so
    steep that the best float tilt leaves a larger residual)."""
    with np.errstate(all="ignore"):
        d = 1e-7 * abs(a) if a != 0 else 1e-300
        slope = abs(h(a + d) - h(a - d)) / (2 * d)
        return abs(h(a)) <= rtol * scale + ulps * np.spacing(abs(a)) * slope


def _finite_problems(values):
    """Problems for non-finite numbers among ``{name: array}``."""
    out = []
    for name, v in values.items():
        v = np.asarray(v, float)
        if not np.all(np.isfinite(v)):
            out.append(f"non-finite {name} returned ({v.ravel()[~np.isfinite(v.ravel())][0]})")
    return out


# ---------------------------------------------------------------------------
# grids
# ---------------------------------------------------------------------------


def _log(lo, hi, n):
    return np.geomspace(lo, hi, max(int(n), 2))


def _end_fractions(quick):
    """s/s_max: uniform, then clustered toward 1 (down to 1 - 1e-9), then 1 and 1.01."""
    if quick:
        inner = np.concatenate([np.linspace(0.0, 0.8, 3), 1.0 - np.geomspace(1e-2, 1e-9, 3)])
    else:
        inner = np.concatenate([np.linspace(0.0, 0.9, 10), 1.0 - np.geomspace(1e-2, 1e-9, 8)])
    return np.concatenate([inner, [1.0, 1.01]])


# ---------------------------------------------------------------------------
# rods
# ---------------------------------------------------------------------------


def _smooth(rod, quick):
    import supercoil as sc
    from supercoil.core.rod import contact as sco

    u = sc.ureg
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    turns = np.concatenate([[0.0], _log(1e-3, 1e13, 8 if quick else 33)])
    slack = np.concatenate([[-0.05], np.linspace(0.0, 0.99, 4 if quick else 16),
                            [1.0 - 1e-6, 1.0, 1.1]])
    out = np.empty((slack.size, turns.size), dtype=object)
    for j, sf in enumerate(slack):
        for i, n in enumerate(turns):
            h, exc, warns = _call(lambda n=n, sf=sf: sc.smooth_helix(rod, n, sf * L * u.m))
            problems = []
            if h is not None:
                vals = {f.name: getattr(h, f.name).magnitude for f in dataclasses.fields(h)
                        if f.name != "provenance"}
                problems = _finite_problems(vals)
                if not problems:
                    with np.errstate(all="ignore"):
                        a = float(vals["alpha"])
                        om = float(h.omega.m_as(1 / u.m))
                        om_hc = float(sco.twist_density(a, r, B, C))
                        lk = float(vals["linking_number"])
                    if not 0 < a < np.pi / 4 or np.cos(2 * a) < sco.COS2A_MIN:
                        problems.append(f"alpha = {a!r} returned inside the pi/4 guard")
                    elif abs(om - om_hc) > 1e-6 * abs(om_hc):
                        problems.append(f"(HC) violated: omega = {om:.9g}, omega_HC = "
                                        f"{om_hc:.9g} 1/m")
                    if abs(lk - n) > 1e-12 * max(1.0, abs(n)):
                        problems.append(f"Lk = {lk!r} != N = {n!r}")
            out[j, i] = _verdict(exc, warns, problems)
    return ("smooth_helix",
            Axis("turns", "turns N", "", turns),
            Axis("slack_fraction", "slack S / L", "", slack), out)


def _rough_reference(kind, alpha0, k, s, r, L, B, C):
    """Reference y(s) (0 beyond the reference's end)."""
    from supercoil.core.rod import rough as rh

    if kind == "closed_form":  # reference for the ODE at k = 0
        smax = float(rh.k0_s_max(alpha0, L, B, C))
        inside = s < smax
        y = np.zeros_like(s)
        y[inside] = rh.k0_y_of_s(s[inside], alpha0, L, B, C)
        return y
    if kind == "dop853":  # reference for the closed form
        integ = rh.integrate(alpha0, None, r, L, B, C, ode_method="DOP853",
                             rtol=1e-13, atol=1e-15)
    else:  # k != 0

        def kfun(S):
            return np.full_like(np.asarray(S, float), k)

        integ = rh.integrate(alpha0, kfun, r, L, B, C, ode_method="LSODA",
                             rtol=1e-13, atol=1e-16)
    y = np.zeros_like(s)
    inside = s <= integ.s_end
    y[inside] = integ.y(s[inside])
    return y


def _rough(rod, method, k, quick):
    import supercoil as sc
    from supercoil.core.rod import contact as sco
    from supercoil.core.rod import rough as rh

    u = sc.ureg
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    # plus the paper's own twist loads (N r / L ~ 0.05-0.1: N = 30-60, r = 1 mm, L = 56.7 cm)
    loads = np.unique(np.concatenate([[0.0, 0.05, 0.1], _log(1e-9, 1e10, 7 if quick else 30)]))
    fr = _end_fractions(quick)
    out = np.empty((fr.size, loads.size), dtype=object)
    kw = {"method": method}
    if k:
        kw["twist_rate"] = k * u.rad / u.m
    ref_kind = "dop853" if method == "closed_form" else ("closed_form" if not k else "lsoda")
    for i, x in enumerate(loads):
        n = x * L / r
        res, exc, warns = _call(lambda n=n: sc.rough_helix(rod, n, **kw))
        if res is None or any(not issubclass(w.category, sc.SupercoilWarning) for w in warns):
            out[:, i] = [_verdict(exc, warns)] * fr.size
            continue
        a0 = float(res.alpha0.m_as(u.rad))
        s_max = float(res.s_max.m_as(u.m))
        problems_row = []
        rhs = (C / B) * 4.0 * np.pi * r * n / L

        def h_ini(a, rhs=rhs):
            return float(sco.y_of_alpha(a) * np.sin(2 * a) - rhs * np.cos(2 * a))

        scale = abs(float(sco.y_of_alpha(a0) * np.sin(2 * a0))) + abs(rhs * np.cos(2 * a0))
        if not _root_ok(h_ini, a0, scale):
            problems_row.append(f"[eq ini] not satisfied by alpha_0 = {a0!r}")
        if np.cos(2 * a0) < sco.COS2A_MIN:
            problems_row.append(f"alpha_0 = {a0!r} returned inside the pi/4 guard")
        inside = (fr < 1.0) | ((fr == 1.0) & (res.end == "s_stop"))
        s = fr[inside] * s_max
        prof, exc2, warns2 = _call(lambda n=n, s=s: sc.rough_helix(rod, n, s=s * u.m, **kw))
        if prof is None:
            out[inside, i] = [_verdict(exc2, warns2)] * int(inside.sum())
        else:
            p = prof.profile
            num = p.select_dtypes("number")
            if rod.friction_coefficient is None:
                num = num.drop(columns=["friction_torque_available"])
            finite = np.isfinite(num.to_numpy(float)).all(axis=1)
            alpha = p["alpha"].to_numpy()
            with np.errstate(all="ignore"):
                y = 2.0 * np.sin(alpha) ** 2
                y_ref = _rough_reference("closed_form" if ref_kind == "closed_form" else ref_kind,
                                         a0, k, s, r, L, B, C)
                dyds = np.abs(rh.dy_ds(s, y_ref, np.full_like(s, k), r, L, B, C))
                bound = ROUGH_TOL_Y + dyds * ROUGH_TOL_S * L
            slip = None if prof.slip_onset is None else float(prof.slip_onset.m_as(u.m))
            rows = np.flatnonzero(inside)
            for m, j in enumerate(rows):
                problems = list(problems_row)
                if not finite[m]:
                    bad = [c for c in num.columns if not np.isfinite(num[c].iloc[m])]
                    problems.append(f"non-finite {', '.join(bad)} at s/s_max = {fr[j]:.12g}")
                elif not 0 < alpha[m] < np.pi / 4 or np.cos(2 * alpha[m]) < sco.COS2A_MIN:
                    problems.append(f"alpha = {alpha[m]!r} outside (0, pi/4)")
                elif abs(y[m] - y_ref[m]) > bound[m]:
                    problems.append(f"y = 1 - cos 2 alpha = {y[m]:.12g} misses the reference "
                                    f"{y_ref[m]:.12g} by {abs(y[m] - y_ref[m]):.2e} "
                                    f"(tolerance {bound[m]:.2e})")
                flags = []
                if bool(p["curvature_error_flag"].iloc[m]):
                    flags.append(f"curvature_error_flag (|e - 1| = "
                                 f"{abs(p['curvature_error'].iloc[m] - 1):.3g})")
                if slip is not None and s[m] >= slip:
                    flags.append(f"slip (no-slip condition fails from s = {slip * 1e3:.6g} mm)")
                out[j, i] = _verdict(None, warns2, problems, flags)
        for j in np.flatnonzero(~inside):
            sj = fr[j] * s_max
            _, e3, w3 = _call(lambda n=n, sj=sj: sc.rough_helix(rod, n, s=[sj] * u.m, **kw))
            out[j, i] = _verdict(e3, w3, [] if e3 is not None else
                                 [f"no error at s = {fr[j]:g} s_max, beyond the helix end"])
    if method == "closed_form":
        name = "rough_helix closed_form"
    else:
        name = f"rough_helix ode (k = {k:g} rad/m)"
    return (name, Axis("twist_load", "twist load N r / L", "", loads),
            Axis("s_fraction", "arclength s / s_max", "", fr), out)


def _design_reference(P0, P1, kw, s_end, r, L, B, C):
    """Linking number N at slack 2 s_end of the analytic designed helix (quadrature)."""
    from scipy import integrate

    from supercoil.core.rod import contact as sco

    def alpha(s):
        return np.arctan2(2 * np.pi * r, P0 + P1 * np.sin(kw * s))

    def f(s):
        a = alpha(s)
        return np.sin(a) * np.cos(a) / r + sco.twist_density(a, r, B, C)

    pts = [(1.5 * np.pi + 2 * np.pi * j) / kw for j in range(int(kw * s_end / (2 * np.pi)) + 2)]
    pts = [p for p in pts if 0 < p < s_end]
    with warnings.catch_warnings():  # roundoff notices at epsrel 1e-12: still ~1e-12
        warnings.simplefilter("ignore", integrate.IntegrationWarning)
        val, _ = integrate.quad(f, 0.0, s_end, points=pts or None, limit=500, epsabs=0.0,
                                epsrel=1e-12)
    om_end = float(sco.twist_density(alpha(s_end), r, B, C))
    return val / np.pi + om_end * (L - 2 * s_end) / (2 * np.pi)


def _design(rod, quick):
    import supercoil as sc
    from supercoil.rod.design import sinusoidal_pitch

    u = sc.ureg
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    ratio = _log(0.5, 1e3, 8 if quick else 28)
    amp = np.array([0.0, 0.3, 0.6, 0.9, 1.2]) if quick else np.concatenate(
        [np.linspace(0.0, 0.95, 20), [0.99, 1.0, 1.1, 1.2]])
    out = np.empty((amp.size, ratio.size), dtype=object)
    for j, a in enumerate(amp):
        for i, q in enumerate(ratio):
            P0 = q * 2 * np.pi * r
            P1 = a * P0
            kw = 2 * np.pi / (10 * P0)
            pitch = sinusoidal_pitch(P0 * u.m, P1 * u.m, kw / u.m)
            t, exc, warns = _call(lambda pitch=pitch: sc.design_twist_schedule(rod, pitch))
            problems, flags = [], []
            if t is not None:
                num = t.select_dtypes("number")
                problems = _finite_problems({c: num[c].to_numpy() for c in num.columns})
                if not problems:
                    s_end = float(t["s"].iloc[-1]) * 1e-3
                    n_ref = _design_reference(P0, P1, kw, s_end, r, L, B, C)
                    n = float(t["turns"].iloc[-1])
                    if abs(n - n_ref) > 1e-6 * abs(n_ref):
                        problems.append(f"turns N = {n:.9g} at the last slack, the designed "
                                        f"helix has Lk = {n_ref:.9g}")
                    if "friction_torque_available" in t:
                        slip = (t["friction_torque_required"] > t["friction_torque_available"])
                        if slip.any():
                            flags.append("slip: friction_torque_required > available from "
                                         f"slack {t['slack'][slip].iloc[0]:.6g} mm")
            out[j, i] = _verdict(exc, warns, problems, flags)
    return ("design_twist_schedule",
            Axis("pitch_ratio", "mean pitch P0 / (2 pi r)", "", ratio),
            Axis("amplitude_ratio", "amplitude P1 / P0", "", amp), out)


def _spinning(rod, quick):
    import supercoil as sc

    u = sc.ureg
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    turns = np.concatenate([[0.0], _log(1e-4, 1e13, 8 if quick else 30)])
    tens = np.concatenate([[-1.0, 0.0], _log(1e-6, 1e6, 6 if quick else 22)])
    out = np.empty((tens.size, turns.size), dtype=object)
    for j, T in enumerate(tens):
        for i, n in enumerate(turns):
            sp, exc, warns = _call(lambda n=n, T=T: sc.twist_spinning(rod, n, T * u.N))
            problems = []
            if sp is not None:
                vals = {f: getattr(sp, f).magnitude for f in
                        ("alpha", "beta", "pitch", "omega", "alpha_slacking", "pitch_slacking",
                         "pitch_increase")}
                problems = _finite_problems(vals)
                if not problems:
                    problems = _spinning_checks(float(vals["alpha"]), float(vals["beta"]),
                                                float(vals["alpha_slacking"]), n, T, r, L, B, C)
            out[j, i] = _verdict(exc, warns, problems)
    return ("twist_spinning", Axis("turns", "turns N", "", turns),
            Axis("head_tension", "head tension T' [N]", "N", tens), out)


def _spinning_checks(a, beta, a0, n, T, r, L, B, C):
    problems = []
    nn = abs(n) / L
    s, c = np.sin(a), np.cos(a)

    def f4(x):
        return (B * np.sin(x) ** 2 * np.sin(2 * x) / r**2 + 0.5 * T * np.sin(x)
                - 2 * np.pi * C * nn * np.cos(2 * x) / r)

    scale = (B * s * s * np.sin(2 * a) / r**2 + abs(0.5 * T * s)
             + abs(2 * np.pi * C * nn * np.cos(2 * a) / r))
    if not _root_ok(f4, a, scale):
        problems.append(f"[f4] not satisfied by alpha = {a!r}")
    if np.cos(2 * a) < 1e-9:
        problems.append(f"alpha = {a!r} returned inside the pi/4 guard")
    if T == 0:
        if beta != 0.5 * np.pi or abs(a - a0) > 1e-12 * a0:
            problems.append(f"T' = 0: alpha = {a!r}, beta = {beta!r}; expected the slacking "
                            f"tilt {a0!r} and pi/2")
        return problems
    kappa, tau = s * s / r, s * c / r
    Ts = 2 * np.pi * C * nn * tau - 0.5 * B * kappa**2
    x = 2 * Ts / T - 2 * np.sin(0.5 * a) ** 2  # sec(beta) - 1, no cancellation
    b_ref = float(2 * np.arcsin(np.sqrt(x / (2 * (1 + x)))))
    if not abs(beta - b_ref) <= 1e-6 * b_ref:
        problems.append(f"beta = {beta!r} rad, cancellation-free value {b_ref!r} rad "
                        f"(relative error {abs(beta - b_ref) / b_ref:.2e})")
    return problems


# ---------------------------------------------------------------------------
# DNA
# ---------------------------------------------------------------------------


def _plectoneme(dna, quick):
    import supercoil as sc
    from supercoil.core.dna import plectoneme as pl

    u = sc.ureg
    forces = np.concatenate([[-1.0, 0.0], _log(1e-4, 1e6, 8 if quick else 36)])
    persist = _log(2.0, 2000.0, 4 if quick else 16)
    out = np.empty((persist.size, forces.size), dtype=object)
    for j, A in enumerate(persist):
        d = dna.replace(bending_persistence=A * u.nm)
        si = d.si
        for i, F in enumerate(forces):
            e, exc, warns = _call(lambda d=d, F=F: sc.plectoneme_equilibrium(d, F * u.pN))
            problems = []
            if e is not None:
                problems = _finite_problems({k: getattr(e, k).magnitude for k in e._fields})
                if not problems:
                    a, R = float(e.alpha.m_as(u.rad)), float(e.radius.m_as(u.m))
                    om = float(e.omega.m_as(1 / u.m))
                    with np.errstate(all="ignore"):
                        res = pl.equilibrium_residuals(F * 1e-12, a, R, om, si.bending_rigidity,
                                                       si.torsional_rigidity, si.kT, si.radius)
                    worst = max(abs(float(x)) for x in res)
                    if not 0 < a < np.pi / 4 or not R >= 0.5 * si.radius:
                        problems.append(f"alpha = {a!r}, R = {R!r} m off the physical branch")
                    elif not worst <= 1e-10:
                        problems.append(f"equilibrium residual {worst:.2e} > 1e-10")
            out[j, i] = _verdict(exc, warns, problems)
    return ("plectoneme_equilibrium", Axis("force", "force [pN]", "pN", forces),
            Axis("bending_persistence", "bending persistence A [nm]", "nm", persist), out)


def _zeta_decimal(F, M, l, B, kT):
    """Moroz-Nelson zeta in 40-digit decimal arithmetic (SI floats in)."""
    ctx = decimal.Context(prec=40)
    with decimal.localcontext(ctx):
        F, M, l, B, kT = (decimal.Decimal(float(v)) for v in (F, M, l, B, kT))
        Q = B * F / (kT * kT) - M * M / (4 * kT * kT) - decimal.Decimal(1) / 32
        if Q <= 0:
            return None
        return float(1 - decimal.Decimal("0.5") / Q.sqrt() + B * kT / (l * (B * F - M * M / 4)))


def _extension(dna, quick):
    import supercoil as sc

    u = sc.ureg
    si = dna.si
    forces = np.concatenate([[0.0], _log(1e-3, 1e6, 8 if quick else 36)])
    torques = np.concatenate([[0.0], _log(1e-2, 1e5, 6 if quick else 24)])
    tail = 750e-9
    out = np.empty((torques.size, forces.size), dtype=object)
    for j, M in enumerate(torques):
        for i, F in enumerate(forces):
            z, exc, warns = _call(lambda F=F, M=M: sc.extension_factor(
                dna, F * u.pN, M * u.pN * u.nm, tail * u.m))
            problems = []
            if z is not None:
                zz = float(z.magnitude)
                problems = _finite_problems({"zeta": zz})
                if not problems:
                    ref = _zeta_decimal(F * 1e-12, M * 1e-21, tail, si.bending_rigidity, si.kT)
                    if ref is None:
                        problems.append("zeta returned where its bracket is not positive")
                    elif abs(zz - ref) > 1e-12 * max(1.0, abs(ref)):
                        problems.append(f"zeta = {zz!r}, 40-digit value {ref!r}")
            out[j, i] = _verdict(exc, warns, problems)
    return ("extension_factor", Axis("force", "force [pN]", "pN", forces),
            Axis("torque", "torque M_3 [pN nm]", "pN nm", torques), out)


def _hat_turns(d, F, thermal):
    """17 turns from 0 to the point where the plectoneme holds half the molecule."""
    from supercoil.core.dna import hat as hc

    si = d.si
    args = (si.length, si.bending_rigidity, si.torsional_rigidity, si.kT, si.radius, thermal)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            p = hc.hat_parameters(np.array([F * 1e-12]), *args, check_zeta=False)
        n_half = p.buckling_turns[0] + 0.5 * si.length * p.linking_rate[0] / (2 * np.pi)
        if np.isfinite(n_half) and n_half > 0:
            return np.linspace(0.0, n_half, 17)
    except Exception:  # the public call reports it
        pass
    return np.linspace(0.0, 0.05 * si.length / 3.57e-9, 17)


def _hat_checks(df, d, F, thermal):
    """Model consistency and physical bounds of one hat curve (SI internally).

    Returns ``(problems, soft)``: points that do not match their phase, and
    unflagged points outside ``0 <= z <= L`` or with z growing with N.
    """
    from supercoil.core.dna import hat as hc
    from supercoil.core.dna import moroz_nelson as mn

    si = d.si
    L, B, C, kT = si.length, si.bending_rigidity, si.torsional_rigidity, si.kT
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        p = hc.hat_parameters(np.array([F * 1e-12]), L, B, C, kT, si.radius, thermal,
                              check_zeta=False)
    ratio, Mp, om, tau = p.twist_ratio[0], p.torque[0], p.omega[0], p.torsion[0]
    N = df["turns"].to_numpy()
    z = df["extension"].to_numpy() * 1e-9
    M = np.abs(df["torque"].to_numpy()) * 1e-21
    S = df["plectoneme_length"].to_numpy() * 1e-9
    phase = df["phase"].to_numpy()
    short = df["short_tail"].to_numpy(bool)
    problems = []
    with np.errstate(all="ignore"):
        for m in range(N.size):
            n = abs(N[m])
            if phase[m] == "stretched":
                M_ref, tail = (C / ratio) * 2 * np.pi * n / L, L
                lk_err = 0.0
            elif phase[m] == "plectoneme":
                M_ref, tail = Mp, L - S[m]
                lk = ratio * om * (L - S[m]) + (om + tau) * S[m]
                lk_err = abs(lk - 2 * np.pi * n) / (2 * np.pi * max(n, 1e-300))
            else:
                continue
            zeta = float(mn.extension_factor(F * 1e-12, M_ref, tail, B, kT, check=False)) \
                if thermal else 1.0
            z_ref = zeta * tail
            if abs(M[m] - M_ref) > 1e-9 * abs(M_ref) or lk_err > 1e-9 or \
                    abs(z[m] - z_ref) > 1e-9 * L:
                problems.append(f"point N = {N[m]:.6g} ({phase[m]}) does not match its phase: "
                                f"z = {z[m]:.9g} m (expected {z_ref:.9g}), torque "
                                f"{M[m]:.6g} N m (expected {M_ref:.6g}), linking error "
                                f"{lk_err:.2e}")
                break
    soft = []
    good = ~short
    if np.any(good & ((z < -1e-9 * L) | (z > L * (1 + 1e-9)))):
        m = np.flatnonzero(good & ((z < -1e-9 * L) | (z > L * (1 + 1e-9))))[0]
        soft.append(f"unflagged extension z = {z[m] * 1e9:.6g} nm outside [0, L] at "
                    f"N = {N[m]:.6g}")
    zg = z[good]
    if zg.size > 1 and np.any(np.diff(zg) > 1e-9 * L):
        soft.append("unflagged extension increases with turns")
    return problems, soft


def _hat(dna, thermal, quick):
    import supercoil as sc

    u = sc.ureg
    forces = np.concatenate([[0.0], _log(1e-3, 1e6, 8 if quick else 36)])
    lengths = _log(20.0, 5e4, 5 if quick else 20)
    out = np.empty((lengths.size, forces.size), dtype=object)
    for j, Lnm in enumerate(lengths):
        d = dna.replace(length=Lnm * u.nm)
        for i, F in enumerate(forces):
            turns = _hat_turns(d, F, thermal)
            df, exc, warns = _call(lambda d=d, F=F, turns=turns: sc.hat_curve(
                d, F * u.pN, turns, thermal=thermal))
            problems, flags, soft = [], [], []
            if df is not None:
                num = df.select_dtypes("number")
                problems = _finite_problems({c: num[c].to_numpy() for c in num.columns})
                if not problems:
                    problems, soft = _hat_checks(df, d, F, thermal)
                    short = df["short_tail"].to_numpy(bool)
                    if short.any():
                        flags.append(f"short_tail from N = {df['turns'][short].iloc[0]:.6g} "
                                     f"({int(short.sum())} of {short.size} points)")
            out[j, i] = _verdict(exc, warns, problems, flags, soft)
    name = "hat_curve " + ("thermal" if thermal else "athermal")
    return (name, Axis("force", "force [pN]", "pN", forces),
            Axis("length", "molecule length L [nm]", "nm", lengths), out)


# ---------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------

#: the maps, in plotting order: (key, builder(rod, dna, quick))
MAPS = (
    ("smooth_helix", lambda rod, dna, q: _smooth(rod, q)),
    ("rough closed_form", lambda rod, dna, q: _rough(rod, "closed_form", 0.0, q)),
    ("rough ode k=0", lambda rod, dna, q: _rough(rod, "ode", 0.0, q)),
    ("rough ode k>0", lambda rod, dna, q: _rough(rod, "ode", 100.0, q)),
    ("rough ode k<0", lambda rod, dna, q: _rough(rod, "ode", -100.0, q)),
    ("design_twist_schedule", lambda rod, dna, q: _design(rod, q)),
    ("twist_spinning", lambda rod, dna, q: _spinning(rod, q)),
    ("plectoneme_equilibrium", lambda rod, dna, q: _plectoneme(dna, q)),
    ("extension_factor", lambda rod, dna, q: _extension(dna, q)),
    ("hat_curve thermal", lambda rod, dna, q: _hat(dna, True, q)),
    ("hat_curve athermal", lambda rod, dna, q: _hat(dna, False, q)),
)


def run(quick=False, rod=None, dna=None, only=None):
    """Evaluate every solver over its grid and classify every cell.

    Parameters
    ----------
    quick : bool
        Coarse grids (same ranges), for tests and a fast look.
    rod, dna : ElasticRod, DNA, optional
        Default: the parameter sets ``silicone_rubber_rod`` and ``dna``.
    only : iterable of str, optional
        Keys of :data:`MAPS` to run (default all).

    Returns
    -------
    pandas.DataFrame
        One row per cell: ``solver``, ``x_quantity`` and ``y_quantity`` (the
        names of the two input columns of this solver), the input columns
        (``turns``, ``slack_fraction``, ``twist_load``, ``s_fraction``,
        ``pitch_ratio``, ``amplitude_ratio``, ``head_tension`` [N], ``force``
        [pN], ``bending_persistence`` [nm], ``torque`` [pN nm], ``length`` [nm];
        NaN where not an input of that solver), ``ix``, ``iy`` (grid indices),
        ``outcome`` (``ok``, ``flagged``, ``named error: <Class>``, ``WRONG``),
        ``category`` (one of :data:`CATEGORIES`) and ``detail`` (the message).
        ``attrs["provenance"]`` holds the wall time of every map.
    """
    import supercoil as sc
    from supercoil.tables import make_table, provenance

    rod = rod or sc.load_parameters("silicone_rubber_rod")
    dna = dna or sc.load_parameters("dna")
    maps, timings = [], {}
    for key, build in MAPS:
        if only is not None and key not in only:
            continue
        t0 = time.perf_counter()
        maps.append(build(rod, dna, quick))
        timings[maps[-1][0]] = round(time.perf_counter() - t0, 3)
    input_units = {}
    for _, xa, ya, _ in maps:
        input_units[xa.column] = xa.unit
        input_units[ya.column] = ya.unit
    cols = {k: [] for k in ("solver", "x_quantity", "y_quantity", *input_units, "ix", "iy",
                            "outcome", "category", "detail")}
    for name, xa, ya, out in maps:
        for iy, yv in enumerate(ya.values):
            for ix, xv in enumerate(xa.values):
                outcome, detail = out[iy, ix]
                cols["solver"].append(name)
                cols["x_quantity"].append(xa.column)
                cols["y_quantity"].append(ya.column)
                for c in input_units:
                    cols[c].append(xv if c == xa.column else yv if c == ya.column else np.nan)
                cols["ix"].append(ix)
                cols["iy"].append(iy)
                cols["outcome"].append(outcome)
                cols["category"].append(_category(outcome))
                cols["detail"].append(detail)
    units = {"solver": "", "x_quantity": "", "y_quantity": "", **input_units, "ix": "",
             "iy": "", "outcome": "", "category": "", "detail": ""}
    labels = {name: [xa.label, ya.label] for name, xa, ya, _ in maps}
    return make_table(cols, units, provenance(
        None, benchmark="stability map", quick=bool(quick), rod=rod.as_dict(),
        dna=dna.as_dict(), axis_labels=labels, map_seconds=timings,
        tolerances={"rough_y": ROUGH_TOL_Y, "rough_s_over_L": ROUGH_TOL_S}))


def summary(table):
    """Counts of cells per solver and category (columns in :data:`CATEGORIES` order)."""
    counts = table.groupby(["solver", "category"], sort=False).size().unstack(fill_value=0)
    for c in CATEGORIES:
        if c not in counts:
            counts[c] = 0
    return counts[list(CATEGORIES)]


def regions(table):
    """Input ranges of every outcome of every solver: one row per (solver, outcome).

    Columns ``solver``, ``outcome``, ``cells``, ``x_quantity``, ``x_min``,
    ``x_max``, ``y_quantity``, ``y_min``, ``y_max`` (a bounding box, not a
    boundary: read the map for the shape).
    """
    import pandas as pd

    rows = []
    for (solver, outcome), g in table.groupby(["solver", "outcome"], sort=False):
        xq, yq = g["x_quantity"].iloc[0], g["y_quantity"].iloc[0]
        rows.append({"solver": solver, "outcome": outcome, "cells": len(g), "x_quantity": xq,
                     "x_min": g[xq].min(), "x_max": g[xq].max(), "y_quantity": yq,
                     "y_min": g[yq].min(), "y_max": g[yq].max()})
    return pd.DataFrame(rows)


def _tick(v):
    if v == 0:
        return "0"
    if 0.98 < v < 1:
        return f"1-{1 - v:.0e}".replace("e-0", "e-")
    if abs(v) >= 1e4 or abs(v) < 1e-2:
        return f"{v:.0e}".replace("e+0", "e").replace("e-0", "e-").replace("e+", "e")
    return f"{v:.3g}"


def plot(table, path=None):
    """One categorical map per solver (small multiples) with a shared legend.

    Cells are drawn on their grid indices; the tick labels give the input
    values (the grids are logarithmic where the labels say so). Returns the
    figure; writes ``path`` (PNG) if given.
    """
    import matplotlib.pyplot as plt
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    solvers = list(dict.fromkeys(table["solver"]))
    labels = table.attrs.get("provenance", {}).get("axis_labels", {})
    ncol = 4
    nrow = int(np.ceil(len(solvers) / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(4.6 * ncol, 4.0 * nrow),
                             constrained_layout=True, squeeze=False)
    cmap = ListedColormap([COLORS[c] for c in CATEGORIES])
    norm = BoundaryNorm(np.arange(len(CATEGORIES) + 1) - 0.5, cmap.N)
    code = {c: k for k, c in enumerate(CATEGORIES)}
    for ax, solver in zip(axes.flat, solvers, strict=False):
        g = table[table["solver"] == solver]
        xq, yq = g["x_quantity"].iloc[0], g["y_quantity"].iloc[0]
        nx, ny = int(g["ix"].max()) + 1, int(g["iy"].max()) + 1
        grid = np.full((ny, nx), np.nan)
        grid[g["iy"].to_numpy(), g["ix"].to_numpy()] = [code[c] for c in g["category"]]
        ax.pcolormesh(np.arange(nx + 1) - 0.5, np.arange(ny + 1) - 0.5, grid, cmap=cmap,
                      norm=norm, edgecolors="white", linewidth=0.2)
        xs = g.drop_duplicates("ix").sort_values("ix")[xq].to_numpy()
        ys = g.drop_duplicates("iy").sort_values("iy")[yq].to_numpy()
        xt = np.unique(np.linspace(0, nx - 1, min(nx, 7)).round().astype(int))
        yt = np.unique(np.linspace(0, ny - 1, min(ny, 9)).round().astype(int))
        ax.set_xticks(xt, [_tick(xs[k]) for k in xt], fontsize=7, rotation=45)
        ax.set_yticks(yt, [_tick(ys[k]) for k in yt], fontsize=7)
        xl, yl = labels.get(solver, [xq, yq])
        ax.set(xlabel=xl, ylabel=yl)
        counts = g["category"].value_counts()
        ax.set_title(f"{solver}\n" + ", ".join(f"{c} {counts.get(c, 0)}" for c in CATEGORIES),
                     fontsize=9)
    for ax in axes.flat[len(solvers):]:
        ax.axis("off")
    fig.legend(handles=[Patch(color=COLORS[c], label=c) for c in CATEGORIES],
               loc="outside lower center", ncol=len(CATEGORIES), fontsize=10)
    quick = table.attrs.get("provenance", {}).get("quick")
    fig.suptitle("Stability map: outcome of every solver over its inputs"
                 + (" (quick grids)" if quick else ""))
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
