"""Stability maps of the rod solvers (smooth, rough, designed, twist-spinning)."""

from __future__ import annotations

import warnings

import numpy as np

from supercoil.benchmark.stability.classify import (
    ROUGH_TOL_S,
    ROUGH_TOL_Y,
    Axis,
    call,
    end_fractions,
    finite_problems,
    log_grid,
    root_ok,
    verdict,
)


def smooth_map(rod, quick):
    import supercoil as sc
    from supercoil.core.rod import contact as sco

    u = sc.ureg
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    turns = np.concatenate([[0.0], log_grid(1e-3, 1e13, 8 if quick else 33)])
    slack = np.concatenate([[-0.05], np.linspace(0.0, 0.99, 4 if quick else 16),
                            [1.0 - 1e-6, 1.0, 1.1]])
    out = np.empty((slack.size, turns.size), dtype=object)
    for j, sf in enumerate(slack):
        for i, n in enumerate(turns):
            h, exc, warns = call(lambda n=n, sf=sf: sc.smooth_helix(rod, n, sf * L * u.m))
            problems = []
            if h is not None:
                vals = {name: q.magnitude for name, q in h._asdict().items()}
                problems = finite_problems(vals)
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
            out[j, i] = verdict(exc, warns, problems)
    return ("smooth_helix",
            Axis("turns", "turns N", "", turns),
            Axis("slack_fraction", "slack S / L", "", slack), out)


def rough_reference(kind, alpha0, k, s, r, L, B, C):
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


def _initial_problems(a0, n, r, L, B, C):
    """[eq ini] backward error and the pi/4 guard for the returned alpha_0."""
    from supercoil.core.rod import contact as sco

    rhs = (C / B) * 4.0 * np.pi * r * n / L

    def h_ini(a):
        return float(sco.y_of_alpha(a) * np.sin(2 * a) - rhs * np.cos(2 * a))

    problems = []
    scale = abs(float(sco.y_of_alpha(a0) * np.sin(2 * a0))) + abs(rhs * np.cos(2 * a0))
    if not root_ok(h_ini, a0, scale):
        problems.append(f"[eq ini] not satisfied by alpha_0 = {a0!r}")
    if np.cos(2 * a0) < sco.COS2A_MIN:
        problems.append(f"alpha_0 = {a0!r} returned inside the pi/4 guard")
    return problems


def _point_problems(m, s_frac, num, finite, alpha, y, y_ref, bound):
    """Accuracy problems of one profile point against the reference curve."""
    from supercoil.core.rod import contact as sco

    if not finite[m]:
        bad = [c for c in num.columns if not np.isfinite(num[c].iloc[m])]
        return [f"non-finite {', '.join(bad)} at s/s_max = {s_frac:.12g}"]
    if not 0 < alpha[m] < np.pi / 4 or np.cos(2 * alpha[m]) < sco.COS2A_MIN:
        return [f"alpha = {alpha[m]!r} outside (0, pi/4)"]
    if abs(y[m] - y_ref[m]) > bound[m]:
        return [f"y = 1 - cos 2 alpha = {y[m]:.12g} misses the reference {y_ref[m]:.12g} by "
                f"{abs(y[m] - y_ref[m]):.2e} (tolerance {bound[m]:.2e})"]
    return []


def _point_flags(p, m, s_m, slip):
    flags = []
    if bool(p["curvature_error_flag"].iloc[m]):
        e = abs(p["curvature_error"].iloc[m] - 1)
        flags.append(f"curvature_error_flag (|e - 1| = {e:.3g})")
    if slip is not None and s_m >= slip:
        flags.append(f"slip (no-slip condition fails from s = {slip * 1e3:.6g} mm)")
    return flags


def _profile_column(rod, prof, warns, problems_row, ref, s, fr_in):
    """Verdicts of the points of one profile (one twist load) against the reference."""
    from supercoil.core.rod import rough as rh

    u = prof.s_max._REGISTRY
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    kind, a0, k = ref
    p = prof.profile
    num = p.select_dtypes("number")
    if rod.friction_coefficient is None:
        num = num.drop(columns=["friction_torque_available"])
    finite = np.isfinite(num.to_numpy(float)).all(axis=1)
    alpha = p["alpha"].to_numpy()
    with np.errstate(all="ignore"):
        y = 2.0 * np.sin(alpha) ** 2
        y_ref = rough_reference(kind, a0, k, s, r, L, B, C)
        dyds = np.abs(rh.dy_ds(s, y_ref, np.full_like(s, k), r, L, B, C))
        bound = ROUGH_TOL_Y + dyds * ROUGH_TOL_S * L
    slip = None if prof.slip_onset is None else float(prof.slip_onset.m_as(u.m))
    return [verdict(None, warns,
                    problems_row + _point_problems(m, fr_in[m], num, finite, alpha, y, y_ref,
                                                   bound),
                    _point_flags(p, m, s[m], slip))
            for m in range(s.size)]


def rough_map(rod, method, k, quick):
    import supercoil as sc

    u = sc.ureg
    si = rod.si
    r, L = si.radius, si.length
    # plus the paper's own twist loads (N r / L ~ 0.05-0.1: N = 30-60, r = 1 mm, L = 56.7 cm)
    loads = np.unique(np.concatenate([[0.0, 0.05, 0.1], log_grid(1e-9, 1e10, 7 if quick else 20)]))
    fr = end_fractions(quick)
    out = np.empty((fr.size, loads.size), dtype=object)
    kw = {"method": method}
    if k:
        kw["twist_rate"] = k * u.rad / u.m
    ref_kind = "dop853" if method == "closed_form" else ("closed_form" if not k else "lsoda")
    for i, x in enumerate(loads):
        n = x * L / r
        res, exc, warns = call(lambda n=n: sc.rough_helix(rod, n, **kw))
        if res is None or any(not issubclass(w.category, sc.SupercoilWarning) for w in warns):
            out[:, i] = [verdict(exc, warns)] * fr.size
            continue
        a0 = float(res.alpha0.m_as(u.rad))
        s_max = float(res.s_max.m_as(u.m))
        problems_row = _initial_problems(a0, n, r, L, si.bending_rigidity,
                                         si.torsional_rigidity)
        inside = (fr < 1.0) | ((fr == 1.0) & (res.end == "s_stop"))
        s = fr[inside] * s_max
        prof, exc2, warns2 = call(lambda n=n, s=s: sc.rough_helix(rod, n, s=s * u.m, **kw))
        if prof is None:
            out[inside, i] = [verdict(exc2, warns2)] * int(inside.sum())
        else:
            cells = _profile_column(rod, prof, warns2, problems_row, (ref_kind, a0, k), s,
                                    fr[inside])
            for j, cell in zip(np.flatnonzero(inside), cells, strict=True):
                out[j, i] = cell
        for j in np.flatnonzero(~inside):
            sj = fr[j] * s_max
            _, e3, w3 = call(lambda n=n, sj=sj: sc.rough_helix(rod, n, s=[sj] * u.m, **kw))
            out[j, i] = verdict(e3, w3, [] if e3 is not None else
                                 [f"no error at s = {fr[j]:g} s_max, beyond the helix end"])
    if method == "closed_form":
        name = "rough_helix closed_form"
    else:
        name = f"rough_helix ode (k = {k:g} rad/m)"
    return (name, Axis("twist_load", "twist load N r / L", "", loads),
            Axis("s_fraction", "arclength s / s_max", "", fr), out)


def design_reference(P0, P1, kw, s_end, r, L, B, C):
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


def design_map(rod, quick):
    import supercoil as sc
    from supercoil.rod.design import sinusoidal_pitch

    u = sc.ureg
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    ratio = log_grid(0.5, 1e3, 8 if quick else 28)
    amp = np.array([0.0, 0.3, 0.6, 0.9, 1.2]) if quick else np.concatenate(
        [np.linspace(0.0, 0.95, 20), [0.99, 1.0, 1.1, 1.2]])
    out = np.empty((amp.size, ratio.size), dtype=object)
    for j, a in enumerate(amp):
        for i, q in enumerate(ratio):
            P0 = q * 2 * np.pi * r
            P1 = a * P0
            kw = 2 * np.pi / (10 * P0)
            pitch = sinusoidal_pitch(P0 * u.m, P1 * u.m, kw / u.m)
            t, exc, warns = call(lambda pitch=pitch: sc.design_twist_schedule(rod, pitch))
            problems, flags = [], []
            if t is not None:
                num = t.select_dtypes("number")
                problems = finite_problems({c: num[c].to_numpy() for c in num.columns})
                if not problems:
                    s_end = float(t["s"].iloc[-1]) * 1e-3
                    n_ref = design_reference(P0, P1, kw, s_end, r, L, B, C)
                    n = float(t["turns"].iloc[-1])
                    if abs(n - n_ref) > 1e-6 * abs(n_ref):
                        problems.append(f"turns N = {n:.9g} at the last slack, the designed "
                                        f"helix has Lk = {n_ref:.9g}")
                    if "friction_torque_available" in t:
                        slip = (t["friction_torque_required"] > t["friction_torque_available"])
                        if slip.any():
                            flags.append("slip: friction_torque_required > available from "
                                         f"slack {t['slack'][slip].iloc[0]:.6g} mm")
            out[j, i] = verdict(exc, warns, problems, flags)
    return ("design_twist_schedule",
            Axis("pitch_ratio", "mean pitch P0 / (2 pi r)", "", ratio),
            Axis("amplitude_ratio", "amplitude P1 / P0", "", amp), out)


def spinning_map(rod, quick):
    import supercoil as sc

    u = sc.ureg
    si = rod.si
    r, L, B, C = si.radius, si.length, si.bending_rigidity, si.torsional_rigidity
    turns = np.concatenate([[0.0], log_grid(1e-4, 1e13, 8 if quick else 30)])
    tens = np.concatenate([[-1.0, 0.0], log_grid(1e-6, 1e6, 6 if quick else 22)])
    out = np.empty((tens.size, turns.size), dtype=object)
    for j, T in enumerate(tens):
        for i, n in enumerate(turns):
            sp, exc, warns = call(lambda n=n, T=T: sc.twist_spinning(rod, n, T * u.N))
            problems = []
            if sp is not None:
                vals = {f: getattr(sp, f).magnitude for f in
                        ("alpha", "beta", "pitch", "omega", "alpha_slacking", "pitch_slacking",
                         "pitch_increase")}
                problems = finite_problems(vals)
                if not problems:
                    problems = spinning_checks(float(vals["alpha"]), float(vals["beta"]),
                                                float(vals["alpha_slacking"]), n, T, r, L, B, C)
            out[j, i] = verdict(exc, warns, problems)
    return ("twist_spinning", Axis("turns", "turns N", "", turns),
            Axis("head_tension", "head tension T' [N]", "N", tens), out)


def spinning_checks(a, beta, a0, n, T, r, L, B, C):
    problems = []
    nn = abs(n) / L
    s, c = np.sin(a), np.cos(a)

    def f4(x):
        return (B * np.sin(x) ** 2 * np.sin(2 * x) / r**2 + 0.5 * T * np.sin(x)
                - 2 * np.pi * C * nn * np.cos(2 * x) / r)

    scale = (B * s * s * np.sin(2 * a) / r**2 + abs(0.5 * T * s)
             + abs(2 * np.pi * C * nn * np.cos(2 * a) / r))
    if not root_ok(f4, a, scale):
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


