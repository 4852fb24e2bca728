"""Stability maps of the DNA solvers (plectoneme, zeta, hat curve)."""

from __future__ import annotations

import decimal
import warnings

import numpy as np

from supercoil import display
from supercoil.benchmark.stability.classify import (
    Axis,
    call,
    finite_problems,
    log_grid,
    verdict,
)


def _pn(force_pn):
    """A force in pN (the maps' grid unit) in newtons."""
    return display.from_display(force_pn, "force")


def plectoneme_map(dna, quick):
    import supercoil as sc
    from supercoil.core.dna import plectoneme as pl

    u = sc.ureg
    forces = np.concatenate([[-1.0, 0.0], log_grid(1e-4, 1e6, 8 if quick else 36)])
    persist = log_grid(2.0, 2000.0, 4 if quick else 16)
    out = np.empty((persist.size, forces.size), dtype=object)
    for j, A in enumerate(persist):
        d = dna.replace(bending_persistence=A * u.nm)
        si = d.si
        for i, F in enumerate(forces):
            e, exc, warns = call(lambda d=d, F=F: sc.plectoneme_equilibrium(d, F * u.pN))
            problems = []
            if e is not None:
                problems = finite_problems({k: getattr(e, k).magnitude for k in e._fields})
                if not problems:
                    a, R = float(e.alpha.m_as(u.rad)), float(e.radius.m_as(u.m))
                    om = float(e.omega.m_as(1 / u.m))
                    with np.errstate(all="ignore"):
                        res = pl.hard_core_residuals(_pn(F), a, R, om, si.bending_rigidity,
                                                       si.torsional_rigidity, si.kT, si.radius)
                    worst = max(abs(float(x)) for x in res)
                    if not 0 < a < np.pi / 4 or not R >= 0.5 * si.radius:
                        problems.append(f"alpha = {a!r}, R = {R!r} m off the physical branch")
                    elif not worst <= 1e-10:
                        problems.append(f"equilibrium residual {worst:.2e} > 1e-10")
            out[j, i] = verdict(exc, warns, problems)
    return ("plectoneme_equilibrium", Axis("force", "force [pN]", "pN", forces),
            Axis("bending_persistence", "bending persistence A [nm]", "nm", persist), out)


def zeta_decimal(F, M, l, B, kT):
    """Moroz-Nelson zeta in 40-digit decimal arithmetic (SI floats in)."""
    ctx = decimal.Context(prec=40)
    with decimal.localcontext(ctx):
        F, M, l, B, kT = (decimal.Decimal(float(v)) for v in (F, M, l, B, kT))
        Q = B * F / (kT * kT) - M * M / (4 * kT * kT) - decimal.Decimal(1) / 32
        if Q <= 0:
            return None
        return float(1 - decimal.Decimal("0.5") / Q.sqrt() + B * kT / (l * (B * F - M * M / 4)))


def extension_map(dna, quick):
    import supercoil as sc

    u = sc.ureg
    si = dna.si
    forces = np.concatenate([[0.0], log_grid(1e-3, 1e6, 8 if quick else 36)])
    torques = np.concatenate([[0.0], log_grid(1e-2, 1e5, 6 if quick else 24)])
    tail = 750e-9
    out = np.empty((torques.size, forces.size), dtype=object)
    for j, M in enumerate(torques):
        for i, F in enumerate(forces):
            z, exc, warns = call(lambda F=F, M=M: sc.extension_factor(
                dna, F * u.pN, M * u.pN * u.nm, tail * u.m))
            problems = []
            if z is not None:
                zz = float(z.magnitude)
                problems = finite_problems({"zeta": zz})
                if not problems:
                    ref = zeta_decimal(_pn(F), display.from_display(M, "torque"), tail,
                                       si.bending_rigidity, si.kT)
                    if ref is None:
                        problems.append("zeta returned where its bracket is not positive")
                    elif abs(zz - ref) > 1e-12 * max(1.0, abs(ref)):
                        problems.append(f"zeta = {zz!r}, 40-digit value {ref!r}")
            out[j, i] = verdict(exc, warns, problems)
    return ("extension_factor", Axis("force", "force [pN]", "pN", forces),
            Axis("torque", "torque M_3 [pN nm]", "pN nm", torques), out)


def hat_turns(d, F, thermal):
    """17 turns from 0 to the point where the plectoneme holds half the molecule."""
    from supercoil.core.dna import li_zhao as hc

    si = d.si
    args = (si.length, si.bending_rigidity, si.torsional_rigidity, si.kT, si.radius, thermal)
    try:
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore")
            p = hc.hat_parameters(np.array([_pn(F)]), *args, check_zeta=False)
        n_half = p.buckling_turns[0] + 0.5 * si.length * p.linking_rate[0] / (2 * np.pi)
        if np.isfinite(n_half) and n_half > 0:
            return np.linspace(0.0, n_half, 17)
    except Exception:  # the public call reports it
        pass
    return np.linspace(0.0, 0.05 * si.length / 3.57e-9, 17)


def hat_checks(df, d, F, thermal):
    """Model consistency and physical bounds of one hat curve (SI internally).

    Returns ``(problems, soft)``: points that do not match their phase, and
    unflagged points outside ``0 <= z <= L`` or with z growing with N.
    """
    from supercoil.core.dna import li_zhao as hc
    from supercoil.core.dna import moroz_nelson as mn

    si = d.si
    L, B, C, kT = si.length, si.bending_rigidity, si.torsional_rigidity, si.kT
    with warnings.catch_warnings(), np.errstate(all="ignore"):
        warnings.simplefilter("ignore")
        p = hc.hat_parameters(np.array([_pn(F)]), L, B, C, kT, si.radius, thermal,
                              check_zeta=False)
    ratio, Mp, om, tau = p.twist_ratio[0], p.torque[0], p.omega[0], p.torsion[0]
    N = df["turns"].to_numpy()
    z = display.from_display(df["extension"].to_numpy(), "extension")
    M = display.from_display(np.abs(df["torque"].to_numpy()), "torque")
    S = display.from_display(df["plectoneme_length"].to_numpy(), "plectoneme_length")
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
            zeta = float(mn.extension_factor(_pn(F), M_ref, tail, B, kT, check=False)) \
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
        soft.append(f"unflagged extension z = {display.text(z[m], 'extension')} outside [0, L] at "
                    f"N = {N[m]:.6g}")
    zg = z[good]
    if zg.size > 1 and np.any(np.diff(zg) > 1e-9 * L):
        soft.append("unflagged extension increases with turns")
    return problems, soft


def hat_map(dna, thermal, quick):
    import supercoil as sc

    u = sc.ureg
    forces = np.concatenate([[0.0], log_grid(1e-3, 1e6, 8 if quick else 36)])
    lengths = log_grid(20.0, 5e4, 5 if quick else 20)
    out = np.empty((lengths.size, forces.size), dtype=object)
    for j, Lnm in enumerate(lengths):
        d = dna.replace(length=Lnm * u.nm)
        for i, F in enumerate(forces):
            turns = hat_turns(d, F, thermal)
            df, exc, warns = call(lambda d=d, F=F, turns=turns: sc.hat_curve(
                d, F * u.pN, turns, thermal=thermal))
            problems, flags, soft = [], [], []
            if df is not None:
                num = df.select_dtypes("number")
                problems = finite_problems({c: num[c].to_numpy() for c in num.columns})
                if not problems:
                    problems, soft = hat_checks(df, d, F, thermal)
                    short = df["short_tail"].to_numpy(bool)
                    if short.any():
                        flags.append(f"short_tail from N = {df['turns'][short].iloc[0]:.6g} "
                                     f"({int(short.sum())} of {short.size} points)")
            out[j, i] = verdict(exc, warns, problems, flags, soft)
    name = "hat_curve " + ("thermal" if thermal else "athermal")
    return (name, Axis("force", "force [pN]", "pN", forces),
            Axis("length", "molecule length L [nm]", "nm", lengths), out)


# ---------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------

