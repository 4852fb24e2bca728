"""Fitting the hat-curve model to magnetic-tweezers rotation curves (MODEL.md section 6).

Model
-----
For data point i of molecule m at force T_i and turns N_i the model extension is ::

    z_i = hat(N_i - N0_m ; T_i, L, A, C_t, r_0, t) + z0_m

``hat`` is the hat curve of MODEL.md section 6 (``supercoil.core.dna.hat``):
stretched phase with the Moroz-Nelson tail, buckling, plectoneme phase.
The physical parameters (any of the :class:`~supercoil.dna.material.DNA` fields
``length``, ``bending_persistence``, ``twist_persistence``, ``radius``) are
shared by all points and forces; the nuisance offsets are shared per molecule:
``turns_offset`` N0 (the true zero of rotation) and ``extension_offset`` z0
(the unknown bead-height reference). Each offset is fitted by default and can
be switched off (then held at 0 or at a value given in ``fixed``).

Numerics
--------
:func:`scipy.optimize.least_squares` (trust-region reflective, bounds) on
scaled variables of order one (a physical parameter divided by its start
value; N0 in turns; z0 in units of 10 nm). One residual evaluation is one call
of the vectorised kernel, which solves the plectoneme equilibrium once per
unique force. The Jacobian is built in ``n_physical + 1`` kernel calls:
forward differences for the physical parameters, one central difference in N
for all turns offsets at once (``dz/dN0 = -dz/dN``) and exact columns for the
extension offsets.

Kernel failures during the fit (:class:`~supercoil.exceptions.NoEquilibriumError`,
:class:`~supercoil.exceptions.ValidityError` for a trial step) are step-controlled:
the residual is returned as non-finite and the trust region shrinks (scipy's
TRF rejects non-finite trial points). At the start point they are an error:
:class:`~supercoil.exceptions.FitError` naming the force and the start
parameters, raised before any fitting.

Uncertainties
-------------
``cov = (J^T J)^-1`` from the weighted Jacobian at the solution. When the
Jacobian is numerically rank deficient (relative singular-value threshold from
the finite-difference accuracy, see ``_covariance``), every parameter with a
component in its null space is *not determined*: standard error ``inf``, NaN
covariance rows and columns, a :class:`~supercoil.exceptions.FitWarning` naming
it; the others get the pseudo-inverse. With per-point ``sigma`` (a ``sigma``
column or argument) the covariance is absolute; with unit weights (sigma = 1 nm)
it is scaled by the reduced chi-square, which is then the residual variance in
nm^2, and the noise estimate is its square root (the residual RMS). The report
says which.
"""

from __future__ import annotations

import math
import re
import time
import warnings
from concurrent.futures import Future, as_completed

import numpy as np
import pandas as pd
from scipy.optimize import least_squares

from supercoil.core.dna.hat import DENATURATION_FORCE, OVERSTRETCHING_FORCE
from supercoil.dna.tweezers import check_tweezers_frame
from supercoil.exceptions import (
    BoundWarning,
    FitError,
    FitWarning,
    NoEquilibriumError,
    SupercoilError,
    SupercoilWarning,
    ValidityError,
    ValidityWarning,
)
from supercoil.tables import make_table, provenance
from supercoil.units import BOLTZMANN, U, as_turns, magnitude, quantity, ureg

__all__ = [
    "PHYSICAL_PARAMETERS",
    "FitResult",
    "fit_hat_curves",
    "fit_many",
    "simulate_rotation_curves",
    "valid_turns_range",
]

#: DNA fields that can be fitted (shared by all forces and molecules).
PHYSICAL_PARAMETERS = ("length", "bending_persistence", "twist_persistence", "radius")


_NM = 1e-9
_Z0_SCALE = 1e-8  # scaled extension-offset variable: units of 10 nm
_UNIT_WEIGHT = 1e-9  # residual scale for unit weights (1 nm); cancels in the rescaled covariance
_DISPLAY = {  # name -> (display unit, unit string, factor SI -> display)
    "length": (U.nm, "nm", 1e9),
    "bending_persistence": (U.nm, "nm", 1e9),
    "twist_persistence": (U.nm, "nm", 1e9),
    "radius": (U.nm, "nm", 1e9),
    "turns_offset": (U.turn, "turn", 1.0),
    "extension_offset": (U.nm, "nm", 1e9),
}
_NAME = re.compile(r"^(?P<base>turns_offset|extension_offset)(?:\[(?P<mol>.*)\])?$")


def _hat_points(turns, force, length, B, C, kT, r0, thermal=True):
    """The hat-curve kernel (float, SI); a module attribute so tests can swap it."""
    from supercoil.core.dna.hat import hat_curve_points

    return hat_curve_points(turns, force, length, B, C, kT, r0, thermal=thermal)


def _call_kernel(turns, force, phys, thermal):
    kT = BOLTZMANN * phys["temperature"]
    return _hat_points(
        turns,
        force,
        phys["length"],
        phys["bending_persistence"] * kT,
        phys["twist_persistence"] * kT,
        kT,
        phys["radius"],
        thermal=thermal,
    )


# --------------------------------------------------------------------------------------
# input normalisation (units -> SI floats); the result is a plain picklable dict
# --------------------------------------------------------------------------------------


def _column_si(df, column, unit, converter=None):
    unit_str = df.attrs["units"][column]
    q = ureg.Quantity(df[column].to_numpy(dtype=float), unit_str or "dimensionless")
    if converter is not None:
        return np.asarray(converter(q, column), dtype=float)
    return np.asarray(magnitude(q, unit, f"data column {column!r}"), dtype=float)


def _param_kind(name, labels):
    """('phys', name) or ('turns_offset'|'extension_offset', molecule index or None)."""
    if name in PHYSICAL_PARAMETERS or name == "temperature":
        return name, None
    m = _NAME.match(name)
    if not m:
        raise FitError(
            f"unknown parameter {name!r}; fit parameters are {list(PHYSICAL_PARAMETERS)}, "
            "'turns_offset', 'extension_offset' (or 'turns_offset[<molecule>]', ...)"
        )
    mol = m.group("mol")
    if mol is None:
        return m.group("base"), None
    if mol not in labels:
        raise FitError(f"parameter {name!r}: no molecule {mol!r} in the data (have {labels})")
    return m.group("base"), labels.index(mol)


def _plain(value):
    """A value for a message: ``-1 nm`` or ``-1.0``, never ``np.float64(-1.0)`` / ``<Quantity>``."""
    mag = getattr(value, "magnitude", value)
    if isinstance(mag, np.generic):
        mag = mag.item()
    units = getattr(value, "units", None)
    if units is None:
        return str(mag)
    unit_text = f"{units:~P}"
    return f"{mag} {unit_text}" if unit_text else str(mag)


def _to_si(name, value):
    base = _NAME.match(name).group("base") if _NAME.match(name) else name
    try:
        if base == "turns_offset":
            return float(as_turns(value, name))
        if base == "temperature":
            return float(magnitude(value, U.K, name))
        return float(magnitude(value, U.m, name))
    except (TypeError, ValueError) as exc:
        raise FitError(f"parameter {name!r}: {exc}") from None


def _prepare(data, dna, vary, fixed, bounds, start, sigma, fit_turns_offset,
             fit_extension_offset, thermal, max_nfev, tol):
    """Validate and convert everything to SI floats; return the fit spec (a plain dict)."""
    lines = getattr(data, "attrs", {}).get("lines")  # file lines from read_tweezers_csv
    if lines is not None and not data.index.equals(pd.RangeIndex(len(data))):
        lines = None
    df = check_tweezers_frame(data, lines=lines, source="data")
    force = _column_si(df, "force", U.N)
    turns = _column_si(df, "turns", U.turn, as_turns)
    extension = _column_si(df, "extension", U.m)
    n = len(df)
    if "molecule" in df.columns:
        raw = df["molecule"].astype(str).to_numpy()
        labels = list(dict.fromkeys(raw))
        lookup = {lab: i for i, lab in enumerate(labels)}
        mol_index = np.array([lookup[v] for v in raw], dtype=np.intp)
        has_molecule = True
    else:
        labels, mol_index, has_molecule = ["0"], np.zeros(n, dtype=np.intp), False

    weighting = "unit"
    if sigma is not None:
        s = np.broadcast_to(np.asarray(magnitude(sigma, U.m, "sigma"), dtype=float), (n,))
        if not np.all(np.isfinite(s)) or np.any(s <= 0):
            raise FitError("sigma must be finite and positive")
        sig, weighting = np.array(s, dtype=float), "sigma argument"
    elif "sigma" in df.columns:
        sig, weighting = _column_si(df, "sigma", U.m), "sigma column"
    else:
        sig = np.full(n, _UNIT_WEIGHT)

    if isinstance(vary, str):
        vary = [vary]
    vary = list(dict.fromkeys(vary or []))
    for name in vary:
        if name not in PHYSICAL_PARAMETERS:
            raise FitError(
                f"cannot vary {name!r}: the physical fit parameters are "
                f"{list(PHYSICAL_PARAMETERS)} (offsets are switched with fit_turns_offset "
                "and fit_extension_offset)"
            )
    fixed = dict(fixed or {})
    start = dict(start or {})
    bounds = dict(bounds or {})

    phys = {
        "length": dna.si.length,
        "bending_persistence": dna.si.bending_persistence,
        "twist_persistence": dna.si.twist_persistence,
        "radius": dna.si.radius,
        "temperature": dna.si.temperature,
    }
    n_mol = len(labels)
    fit_n0 = np.full(n_mol, bool(fit_turns_offset))
    fit_z0 = np.full(n_mol, bool(fit_extension_offset))
    n0 = np.zeros(n_mol)
    z0 = np.zeros(n_mol)
    n0_given = np.zeros(n_mol, dtype=bool)
    z0_given = np.zeros(n_mol, dtype=bool)

    def offsets_of(kind, idx):
        return range(n_mol) if idx is None else [idx]

    for name, value in fixed.items():
        kind, idx = _param_kind(name, labels)
        v = _to_si(name, value)
        if kind in vary:
            raise FitError(f"parameter {name!r} is both in vary and in fixed")
        if kind in phys:
            if not (np.isfinite(v) and v > 0):
                raise FitError(f"fixed {name} must be finite and positive, got {_plain(value)}")
            phys[kind] = v
        elif kind == "turns_offset":
            for i in offsets_of(kind, idx):
                fit_n0[i], n0[i], n0_given[i] = False, v, True
        else:
            for i in offsets_of(kind, idx):
                fit_z0[i], z0[i], z0_given[i] = False, v, True
    for name, value in start.items():
        kind, idx = _param_kind(name, labels)
        v = _to_si(name, value)
        if kind in phys:
            if kind not in vary:
                raise FitError(f"start value given for {name!r}, which is not varied")
            phys[kind] = v
        elif kind == "turns_offset":
            for i in offsets_of(kind, idx):
                n0[i], n0_given[i] = v, True
        else:
            for i in offsets_of(kind, idx):
                z0[i], z0_given[i] = v, True

    # free-parameter layout
    names, kinds, scales = [], [], []
    for p in vary:
        names.append(p)
        kinds.append((p, -1))
        scales.append(phys[p])
    for i, lab in enumerate(labels):
        suffix = f"[{lab}]" if has_molecule else ""
        if fit_n0[i]:
            names.append(f"turns_offset{suffix}")
            kinds.append(("turns_offset", i))
            scales.append(1.0)
        if fit_z0[i]:
            names.append(f"extension_offset{suffix}")
            kinds.append(("extension_offset", i))
            scales.append(_Z0_SCALE)
    n_free = len(names)
    if n_free == 0:
        raise FitError("nothing to fit: vary is empty and both offsets are switched off")
    if n - n_free <= 0:
        raise FitError(f"{n} data points cannot determine {n_free} free parameters")

    lo = np.full(n_free, -np.inf)
    hi = np.full(n_free, np.inf)
    for j, (kind, _) in enumerate(kinds):
        if kind in PHYSICAL_PARAMETERS:
            lo[j] = 0.0
    for name, pair in bounds.items():
        kind, idx = _param_kind(name, labels)
        try:
            b_lo, b_hi = pair
        except (TypeError, ValueError):
            raise FitError(f"bounds[{name!r}] must be a pair (lower, upper)") from None
        b_lo = -np.inf if b_lo is None else _to_si(name, b_lo)
        b_hi = np.inf if b_hi is None else _to_si(name, b_hi)
        if not b_lo < b_hi:
            raise FitError(f"bounds[{name!r}]: lower bound {_plain(pair[0])} is not below "
                          f"{_plain(pair[1])}")
        hits = [
            j for j, (k, i) in enumerate(kinds)
            if k == kind and (idx is None or i == idx)
        ]
        if not hits:
            raise FitError(f"bounds given for {name!r}, which is not a free parameter")
        for j in hits:
            lo[j], hi[j] = b_lo, b_hi

    return {
        "force": force,
        "turns": turns,
        "extension": extension,
        "sigma": sig,
        "weighting": weighting,
        "mol_index": mol_index,
        "labels": labels,
        "has_molecule": has_molecule,
        "phys": phys,
        "vary": vary,
        "n0": n0,
        "z0": z0,
        "n0_given": n0_given,
        "z0_given": z0_given,
        "fit_n0": fit_n0,
        "fit_z0": fit_z0,
        "names": names,
        "kinds": kinds,
        "scales": np.array(scales, dtype=float),
        "lower": lo,
        "upper": hi,
        "thermal": bool(thermal),
        "max_nfev": max_nfev,
        "tol": float(tol),
        "units": dict(df.attrs["units"]),
    }


# --------------------------------------------------------------------------------------
# the float engine (runs in worker processes for fit_many; returns plain data)
# --------------------------------------------------------------------------------------


def _guess_turns_center(turns, z, force):
    """Centre of symmetry of the hat: shift c minimising the mismatch of z(N) and z(2c - N)."""
    span = np.ptp(turns)
    if span <= 0 or len(turns) < 6:
        return 0.0
    grid = np.linspace(turns.min() + 0.25 * span, turns.max() - 0.25 * span, 241)
    total = np.zeros_like(grid)
    weight = np.zeros_like(grid)
    for f in np.unique(force):
        sel = force == f
        nf, zf = turns[sel], z[sel]
        if len(nf) < 6 or np.ptp(nf) <= 0:
            continue
        order = np.argsort(nf)
        nu, inv = np.unique(nf[order], return_inverse=True)
        zu = np.bincount(inv, weights=zf[order]) / np.bincount(inv)
        scale = np.var(zf) or 1.0
        for k, c in enumerate(grid):
            mirror = 2 * c - nf
            inside = (mirror >= nu[0]) & (mirror <= nu[-1])
            if inside.sum() < max(4, 0.3 * len(nf)):
                continue
            d = zf[inside] - np.interp(mirror[inside], nu, zu)
            total[k] += np.mean(d * d) / scale
            weight[k] += 1
    ok = weight > 0
    if not ok.any():
        return 0.0
    cost = np.where(ok, total / np.maximum(weight, 1), np.inf)
    return float(grid[int(np.argmin(cost))])


class _Problem:
    """Residuals and Jacobian in scaled variables u (physical = scale * u)."""

    def __init__(self, spec):
        self.s = spec
        self.n_mol = len(spec["labels"])
        self.mol = spec["mol_index"]
        self.w = 1.0 / spec["sigma"]
        self.kinds = spec["kinds"]
        self.scales = spec["scales"]
        self.n_kernel_failures = 0
        self.last_failure = None
        self._cache_u = None
        self._cache_r = None
        self.njev = 0

    def unpack(self, u):
        s = self.s
        phys = dict(s["phys"])
        n0 = np.array(s["n0"], dtype=float)
        z0 = np.array(s["z0"], dtype=float)
        for (kind, i), scale, x in zip(self.kinds, self.scales, u, strict=True):
            v = scale * x
            if kind == "turns_offset":
                n0[i] = v
            elif kind == "extension_offset":
                z0[i] = v
            else:
                phys[kind] = v
        return phys, n0, z0

    def points(self, u):
        """Kernel output at the data points (raises the kernel's errors)."""
        phys, n0, _ = self.unpack(u)
        return _call_kernel(self.s["turns"] - n0[self.mol], self.s["force"], phys,
                            self.s["thermal"])

    def model(self, u):
        _, _, z0 = self.unpack(u)
        return np.asarray(self.points(u).extension, dtype=float) + z0[self.mol]

    def residual(self, u):
        u = np.asarray(u, dtype=float)
        if self._cache_u is not None and np.array_equal(u, self._cache_u):
            return self._cache_r
        try:
            r = (self.model(u) - self.s["extension"]) * self.w
        except (NoEquilibriumError, ValidityError) as exc:
            # step control: scipy's TRF shrinks the trust region on a non-finite trial point
            self.n_kernel_failures += 1
            self.last_failure = f"{type(exc).__name__}: {exc}"
            r = np.full(len(self.w), np.inf)
        if not np.all(np.isfinite(r)):
            r = np.full(len(self.w), np.inf)
        self._cache_u, self._cache_r = u.copy(), r
        return r

    def jacobian(self, u):
        u = np.asarray(u, dtype=float)
        self.njev += 1
        f0 = self.residual(u)
        if not np.all(np.isfinite(f0)):
            raise FitError(f"the model fails at {self.describe(u)}: {self.last_failure}")
        n, m = len(f0), len(u)
        J = np.zeros((n, m))
        lo, hi = self.s["lower"] / self.scales, self.s["upper"] / self.scales
        mol = self.mol
        phys, n0, _ = self.unpack(u)
        for j, (kind, i) in enumerate(self.kinds):
            if kind in PHYSICAL_PARAMETERS:
                h = 1e-6 * max(1.0, abs(u[j]))
                col = None
                for step in (h, -h):
                    if not lo[j] <= u[j] + step <= hi[j]:
                        continue
                    up = u.copy()
                    up[j] += step
                    try:
                        zp = self.model(up)
                    except (NoEquilibriumError, ValidityError):
                        continue
                    col = ((zp - self.s["extension"]) * self.w - f0) / step
                    break
                if col is None:
                    raise FitError(
                        f"cannot differentiate the model in {kind} at {self.describe(u)}: "
                        "the kernel fails on both sides"
                    )
                J[:, j] = col
            elif kind == "extension_offset":
                J[mol == i, j] = self.s["scales"][j] * self.w[mol == i]
        if any(k == "turns_offset" for k, _ in self.kinds):
            dzdn = self._dz_dturns(self.s["turns"] - n0[mol], phys, f0)
            for j, (kind, i) in enumerate(self.kinds):
                if kind == "turns_offset":
                    sel = mol == i
                    J[sel, j] = -dzdn[sel] * self.w[sel] * self.s["scales"][j]
        return J

    def _dz_dturns(self, n_eff, phys, f0):
        """dz/dN at every point: one kernel call at N -/+ h (central difference)."""
        h = 1e-4
        force = self.s["force"]
        try:
            pts = _call_kernel(np.concatenate([n_eff - h, n_eff + h]),
                               np.concatenate([force, force]), phys, self.s["thermal"])
            z = np.asarray(pts.extension, dtype=float)
            return (z[len(n_eff):] - z[: len(n_eff)]) / (2 * h)
        except (NoEquilibriumError, ValidityError):
            pass
        base = np.asarray(_call_kernel(n_eff, force, phys, self.s["thermal"]).extension)
        for sgn in (1.0, -1.0):
            try:
                z = np.asarray(
                    _call_kernel(n_eff + sgn * h, force, phys, self.s["thermal"]).extension
                )
                return (z - base) / (sgn * h)
            except (NoEquilibriumError, ValidityError):
                continue
        raise FitError(f"cannot differentiate the model in turns at {self.describe_phys(phys)}")

    def describe(self, u):
        return self.describe_phys(self.unpack(u)[0])

    @staticmethod
    def describe_phys(phys):
        return ", ".join(f"{k} = {phys[k] * 1e9:.6g} nm" for k in PHYSICAL_PARAMETERS)


#: Relative accuracy of the Jacobian's columns: the forward-difference step (the
#: truncation error of a forward difference is O(h) relative; h = 1e-6 in the
#: scaled variables, which are of order one).
_JAC_RTOL = 1e-6


def _covariance(J, names=None):
    """``(J^T J)^-1`` by SVD, with the parameters the data do not determine.

    Rank threshold: a singular value ``s_k < s_max * _JAC_RTOL * sqrt(n_par)``
    counts as zero. Justification: each column of the finite-difference
    Jacobian has a relative error of about ``_JAC_RTOL``, so the error matrix
    ``E`` has ``||E||_2 <= ||E||_F <= _JAC_RTOL * ||J||_F <= _JAC_RTOL *
    sqrt(n_par) * s_max``, and by Weyl's inequality a singular value below that
    cannot be told from zero. (numpy's ``matrix_rank`` default, ``eps * max(shape)
    * s_max``, assumes entries exact to rounding; ours are differences.)

    A parameter is *undetermined* when its unit vector has a component larger
    than the same tolerance in the numerical null space: moving along that
    null direction leaves the residuals unchanged, so its variance is infinite.
    Its standard error is ``inf`` and its covariance row and column are NaN.
    The covariance of the other parameters is the pseudo-inverse restricted to
    them, which equals their covariance with the undetermined ones profiled out
    (the null directions have no component along them).

    Returns ``(cov, undetermined, note)``: the covariance in the scaled
    variables, a boolean mask, and a warning text naming the undetermined
    parameters (None when the Jacobian has full rank).
    """
    n_par = J.shape[1]
    names = list(names) if names is not None else [f"p{j}" for j in range(n_par)]
    _, s, vt = np.linalg.svd(J, full_matrices=True)
    s_full = np.zeros(n_par)
    s_full[: s.size] = s
    s_max = s_full[0] if s_full.size else 0.0
    rtol = _JAC_RTOL * math.sqrt(n_par)
    keep = s_full > s_max * rtol if s_max > 0 else np.zeros(n_par, dtype=bool)
    null = vt[~keep]
    undetermined = np.sqrt(np.sum(null**2, axis=0)) > rtol if null.size else np.zeros(
        n_par, dtype=bool)
    vt_k = vt[keep]
    cov = (vt_k.T / s_full[keep] ** 2) @ vt_k
    note = None
    if undetermined.any():
        cov[undetermined, :] = np.nan
        cov[:, undetermined] = np.nan
        bad = [n for n, u in zip(names, undetermined, strict=True) if u]
        note = (
            f"the Jacobian is singular (rank {int(keep.sum())} of {n_par}, relative "
            f"singular-value threshold {rtol:.2g}): the data do not determine "
            f"{', '.join(bad)}; {'its' if len(bad) == 1 else 'their'} standard error"
            f"{'' if len(bad) == 1 else 's'} {'is' if len(bad) == 1 else 'are'} inf"
        )
    return cov, undetermined, note


def _fit_core(spec):
    """Run one fit on a prepared spec. Returns a dict of plain floats/arrays (picklable)."""
    t0 = time.perf_counter()
    prob = _Problem(spec)
    out_warnings = []
    n = len(spec["extension"])
    labels = spec["labels"]

    # ---- start values of the offsets (guesses unless given) ---------------------------
    phys0 = spec["phys"]
    for i in range(len(labels)):
        sel = spec["mol_index"] == i
        if spec["fit_n0"][i] and not spec["n0_given"][i]:
            spec["n0"][i] = _guess_turns_center(spec["turns"][sel], spec["extension"][sel],
                                                spec["force"][sel])
    try:
        pts = _call_kernel(spec["turns"] - spec["n0"][spec["mol_index"]], spec["force"], phys0,
                           spec["thermal"])
    except (NoEquilibriumError, ValidityError) as exc:
        forces = ", ".join(f"{f * 1e12:.4g}" for f in np.unique(spec["force"]))
        raise FitError(
            f"cannot start the fit: the model fails with the start parameters "
            f"({_Problem.describe_phys(phys0)}, temperature = {phys0['temperature']:.6g} K) "
            f"at the data's forces ({forces} pN): {type(exc).__name__}: {exc}"
        ) from exc
    z_start = np.asarray(pts.extension, dtype=float)
    for i in range(len(labels)):
        sel = spec["mol_index"] == i
        if spec["fit_z0"][i] and not spec["z0_given"][i]:
            spec["z0"][i] = float(np.median(spec["extension"][sel] - z_start[sel]))

    # ---- start vector, bounds check -----------------------------------------------------
    u0 = np.empty(len(spec["names"]))
    for j, (kind, i) in enumerate(spec["kinds"]):
        if kind == "turns_offset":
            v = spec["n0"][i]
        elif kind == "extension_offset":
            v = spec["z0"][i]
        else:
            v = phys0[kind]
        lo_j, hi_j = spec["lower"][j], spec["upper"][j]
        guessed = (kind == "turns_offset" and not spec["n0_given"][i]) or (
            kind == "extension_offset" and not spec["z0_given"][i]
        )
        if not lo_j < v < hi_j:
            if guessed:
                width = hi_j - lo_j
                v = (lo_j + hi_j) / 2 if np.isfinite(width) else (
                    lo_j + 1e-3 * max(1.0, abs(lo_j)) if np.isfinite(lo_j)
                    else hi_j - 1e-3 * max(1.0, abs(hi_j))
                )
            else:
                disp = _DISPLAY[kind]
                raise FitError(
                    f"start value of {spec['names'][j]} = {v * disp[2]:.6g} {disp[1]} lies "
                    f"outside its bounds ({lo_j * disp[2]:.6g}, {hi_j * disp[2]:.6g}) {disp[1]}"
                    " (bounds are exclusive; give a start value inside them)"
                )
        u0[j] = v / spec["scales"][j]
    lb = spec["lower"] / spec["scales"]
    ub = spec["upper"] / spec["scales"]

    r0 = prob.residual(u0)
    if not np.all(np.isfinite(r0)):
        raise FitError(f"cannot start the fit: {prob.last_failure}")

    tol = spec["tol"]
    try:
        res = least_squares(
            prob.residual,
            u0,
            jac=prob.jacobian,
            bounds=(lb, ub),
            method="trf",
            x_scale=1.0,
            ftol=tol,
            xtol=tol,
            gtol=tol,
            max_nfev=spec["max_nfev"],
        )
    except FitError:
        raise
    except (ValueError, np.linalg.LinAlgError) as exc:
        raise FitError(f"least_squares failed: {exc}") from exc
    if res.status <= 0 or not np.all(np.isfinite(res.fun)):
        raise FitError(
            f"the fit did not converge ({res.message}) after {res.nfev} evaluations; last "
            f"parameters: {_values_text(spec, res.x)}"
            + (f"; last kernel failure: {prob.last_failure}" if prob.last_failure else "")
        )

    u = res.x
    J = prob.jacobian(u)
    r = prob.residual(u)
    chi2 = float(r @ r)
    nfree = n - len(u)
    redchi = chi2 / nfree
    cov_u, undetermined, note = _covariance(J, spec["names"])
    if note:
        out_warnings.append(("FitWarning", note))
    if spec["weighting"] == "unit":
        cov_u = cov_u * redchi
    cov = cov_u * np.outer(spec["scales"], spec["scales"])
    values = u * spec["scales"]
    stderr = np.sqrt(np.clip(np.diag(cov), 0, None))
    stderr[undetermined] = np.inf

    # ---- estimates on bounds -------------------------------------------------------------
    for j, name in enumerate(spec["names"]):
        for bound, side in ((lb[j], "lower"), (ub[j], "upper")):
            if np.isfinite(bound) and abs(u[j] - bound) <= 1e-6 * max(1.0, abs(bound)):
                kind = spec["kinds"][j][0]
                disp = _DISPLAY[kind]
                out_warnings.append((
                    "BoundWarning",
                    f"{name} = {values[j] * disp[2]:.6g} {disp[1]} sits on its {side} bound "
                    f"({bound * spec['scales'][j] * disp[2]:.6g} {disp[1]}); its standard "
                    "error is not meaningful",
                ))

    # ---- model at the solution, validity flags -------------------------------------------
    pts = prob.points(u)
    phys, n0, z0 = prob.unpack(u)
    n_eff = spec["turns"] - n0[spec["mol_index"]]
    phase = np.asarray(pts.phase)
    short = np.asarray(pts.short_tail, dtype=bool)
    bad = short | (phase == 2)
    if bad.any():
        out_warnings.append((
            "ValidityWarning",
            f"{int(bad.sum())} of {n} data points lie where the hat-curve model is not valid "
            f"({int((phase == 2).sum())} fully coiled, {int(short.sum())} with a tail shorter "
            "than a few persistence lengths); exclude the large-|turns| ends of the curves",
        ))
    zeta = getattr(pts, "zeta", None)
    if spec["thermal"] and zeta is not None:
        zeta_bad = ~short & (phase != 2) & ~((np.asarray(zeta) > 0) & (np.asarray(zeta) <= 1))
        if zeta_bad.any():
            out_warnings.append((
                "ValidityWarning",
                f"{int(zeta_bad.sum())} data points have a Moroz-Nelson zeta outside (0, 1] "
                "at the best fit: the extension model is not valid there",
            ))
    over = spec["force"] > OVERSTRETCHING_FORCE
    if over.any():
        out_warnings.append((
            "ValidityWarning",
            f"{int(over.sum())} data points are above {OVERSTRETCHING_FORCE * 1e12:g} pN, "
            "where B-DNA overstretches; the model (inextensible DNA) ignores it",
        ))
    denat = (spec["force"] > DENATURATION_FORCE) & (n_eff < 0)
    if denat.any():
        out_warnings.append((
            "ValidityWarning",
            f"{int(denat.sum())} data points have negative turns at forces above "
            f"{DENATURATION_FORCE * 1e12:g} pN, where real DNA denatures; the model "
            "(symmetric in N) does not describe them",
        ))
    return {
        "names": list(spec["names"]),
        "kinds": list(spec["kinds"]),
        "values": values,
        "stderr": stderr,
        "covariance": cov,
        "start": u0 * spec["scales"],
        "lower": spec["lower"],
        "upper": spec["upper"],
        "chi_square": chi2,
        "weighted_chi_square": chi2,
        "undetermined": undetermined,
        "reduced_chi_square": redchi,
        "ndata": n,
        "nfree": nfree,
        "nfev": int(res.nfev),
        "njev": int(prob.njev),
        "status": int(res.status),
        "message": str(res.message),
        "kernel_failures": prob.n_kernel_failures,
        "phys": phys,
        "n0": n0,
        "z0": z0,
        "model": prob.model(u),
        "phase": phase,
        "short_tail": short,
        "torque": np.asarray(pts.torque, dtype=float),
        "plectoneme_length": np.asarray(pts.plectoneme_length, dtype=float),
        "residual_weighted": r,
        "warnings": out_warnings,
        "seconds": time.perf_counter() - t0,
    }


def _values_text(spec, u):
    parts = []
    for j, name in enumerate(spec["names"]):
        kind = spec["kinds"][j][0]
        disp = _DISPLAY[kind]
        parts.append(f"{name} = {u[j] * spec['scales'][j] * disp[2]:.6g} {disp[1]}")
    return ", ".join(parts)


_WARNING_CLASSES = {
    "BoundWarning": BoundWarning,
    "FitWarning": FitWarning,
    "ValidityWarning": ValidityWarning,
}


def _emit(records, prefix="", stacklevel=3):
    for cat, msg in records:
        warnings.warn(prefix + msg, _WARNING_CLASSES.get(cat, SupercoilWarning),
                      stacklevel=stacklevel)


# --------------------------------------------------------------------------------------
# the result
# --------------------------------------------------------------------------------------


class FitResult:
    """The result of :func:`fit_hat_curves`.

    Attributes
    ----------
    parameters : dict of str -> pint.Quantity
        Best-fit values of the free parameters: the varied DNA fields (nm) and
        the offsets ``turns_offset`` (turn) and ``extension_offset`` (nm);
        with a ``molecule`` column the offsets are named
        ``turns_offset[<molecule>]``, ``extension_offset[<molecule>]``.
    stderr : dict of str -> pint.Quantity
        One-sigma standard errors, same keys and units; ``inf`` for a
        parameter the data do not determine (see ``undetermined``).
    undetermined : list of str
        Free parameters with a component in the numerical null space of the
        Jacobian (the residuals do not change along it): their standard error
        is ``inf``, their covariance rows and columns and their correlations
        NaN, and a :class:`~supercoil.exceptions.FitWarning` names them.
        Empty for a well-posed fit.
    fixed : dict of str -> pint.Quantity
        The parameters held fixed (DNA fields not varied, offsets switched off).
    covariance : pandas.DataFrame
        Covariance of the free parameters in the units of ``parameters``
        (``attrs["units"]`` gives the unit of each row and column).
    correlation : pandas.DataFrame
        Correlation matrix.
    chi_square, reduced_chi_square : float
        ``sum(((data - model) / sigma)^2)`` and the same divided by the
        degrees of freedom ``nfree``, both dimensionless in the units of the
        weighting: with per-point sigma they are the usual chi-square; with
        unit weights sigma = 1 nm, so ``chi_square`` is the sum of squared
        residuals in nm^2 and ``reduced_chi_square`` the residual variance in
        nm^2 (not a goodness of fit). Always ``chi_square / nfree ==
        reduced_chi_square``.
    residual_rms : pint.Quantity
        ``sqrt(sum((data - model)^2) / nfree)`` (nm): with unit weights the
        estimate of the extension noise (``sqrt(reduced_chi_square)`` nm).
    ndata, nfree, nfev : int
        Data points, degrees of freedom, model evaluations.
    weighting : str
        ``"sigma column"``, ``"sigma argument"`` (absolute uncertainties) or
        ``"unit"`` (covariance scaled by the reduced chi-square).
    residuals : pint.Quantity
        ``data - model`` extensions (nm), in the row order of the data.
    best_fit : pint.Quantity
        Model extensions at the data points (nm).
    dna : DNA
        The input DNA with the fitted fields replaced by their estimates.
    data : pandas.DataFrame
        The data as given.
    """

    def __init__(self, core, spec, data, dna):
        self._core = core
        self._spec = spec
        self.data = data
        self.names = list(core["names"])
        self.parameters = {}
        self.stderr = {}
        self.units = {}
        for name, (kind, _), v, e in zip(self.names, core["kinds"], core["values"],
                                         core["stderr"], strict=True):
            unit, ustr, factor = _DISPLAY[kind]
            self.parameters[name] = quantity(v * factor, unit)
            self.stderr[name] = quantity(e * factor, unit)
            self.units[name] = ustr
        factors = np.array([_DISPLAY[k][2] for k, _ in core["kinds"]])
        cov = core["covariance"] * np.outer(factors, factors)
        self.covariance = pd.DataFrame(cov, index=self.names, columns=self.names)
        self.covariance.attrs["units"] = dict(self.units)
        undetermined = np.asarray(core["undetermined"], dtype=bool)
        d = np.sqrt(np.diag(cov))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = cov / np.outer(d, d)
        corr[~np.isfinite(corr)] = 0.0
        np.fill_diagonal(corr, 1.0)
        corr[undetermined, :] = np.nan
        corr[:, undetermined] = np.nan
        corr[undetermined, undetermined] = 1.0
        self.correlation = pd.DataFrame(corr, index=self.names, columns=self.names)
        self.correlation.attrs["units"] = {k: "" for k in self.names}
        self.undetermined = [n for n, u in zip(self.names, undetermined, strict=True) if u]
        self.chi_square = float(core["chi_square"])
        self.reduced_chi_square = float(core["reduced_chi_square"])
        resid = spec["extension"] - core["model"]
        self.residual_rms = quantity(
            math.sqrt(float(resid @ resid) / int(core["nfree"])) * 1e9, U.nm)
        self.ndata = int(core["ndata"])
        self.nfree = int(core["nfree"])
        self.nfev = int(core["nfev"])
        self.message = core["message"]
        self.success = core["status"] > 0
        self.weighting = spec["weighting"]
        self.thermal = spec["thermal"]
        self.seconds = float(core["seconds"])
        self.best_fit = quantity(core["model"] * 1e9, U.nm)
        self.residuals = quantity((spec["extension"] - core["model"]) * 1e9, U.nm)
        self.warnings = [m for _, m in core["warnings"]]
        phys = core["phys"]
        self.fixed = {}
        for p in PHYSICAL_PARAMETERS:
            if p not in spec["vary"]:
                self.fixed[p] = quantity(phys[p] * 1e9, U.nm)
        self.fixed["temperature"] = quantity(phys["temperature"], U.K)
        for i, lab in enumerate(spec["labels"]):
            suffix = f"[{lab}]" if spec["has_molecule"] else ""
            if not spec["fit_n0"][i]:
                self.fixed[f"turns_offset{suffix}"] = quantity(core["n0"][i], U.turn)
            if not spec["fit_z0"][i]:
                self.fixed[f"extension_offset{suffix}"] = quantity(core["z0"][i] * 1e9, U.nm)
        self.dna = dna.replace(**{p: quantity(phys[p] * 1e9, U.nm) for p in spec["vary"]})

    # ---- text -------------------------------------------------------------------------
    def __repr__(self):
        vals = ", ".join(
            f"{k}={_fmt_pm(self.parameters[k].magnitude, self.stderr[k].magnitude)} "
            f"{self.units[k]}"
            for k in self.names
        )
        if self.weighting == "unit":
            stat = f"noise estimate {self.residual_rms.magnitude:.4g} nm"
        else:
            stat = f"reduced chi-square {self.reduced_chi_square:.4g}"
        return f"<FitResult {vals}; {stat}>"

    def report(self, min_correlation=0.1) -> str:
        """A fit report: statistics, parameter table with units, fixed values, correlations."""
        s, c = self._spec, self._core
        forces = np.unique(s["force"])
        force_text = ", ".join(f"{f * 1e12:.4g}" for f in forces)
        noise = self.residual_rms.magnitude
        if self.weighting == "unit":
            wtext = ("unit weights; covariance scaled by the reduced chi-square (the noise "
                     "level is estimated from the scatter: the noise estimate above)")
            stats = [
                f"    noise estimate     = {noise:.4g} nm (residual RMS, "
                "sqrt(sum of squared residuals / degrees of freedom))",
                f"    chi-square         = {self.chi_square:.6g} nm^2 (sum of squared "
                "residuals; unit weights, sigma = 1 nm)",
                f"    reduced chi-square = {self.reduced_chi_square:.6g} nm^2 (the residual "
                "variance with unit weights, not a goodness of fit)",
            ]
        else:
            wtext = (f"per-point sigma ({self.weighting}); covariance not rescaled "
                     "(absolute uncertainties)")
            stats = [
                f"    chi-square         = {self.chi_square:.6g}",
                f"    reduced chi-square = {self.reduced_chi_square:.6g} (1 when the model and "
                "the sigmas describe the data)",
                f"    residual RMS       = {noise:.4g} nm",
            ]
        lines = [
            "[[Model]]",
            "    hat curve z = hat(N - turns_offset) + extension_offset (MODEL.md s.6), "
            + ("thermal (Moroz-Nelson tail)" if self.thermal else "athermal (C_eff = C, zeta = 1)"),
            "[[Fit statistics]]",
            f"    fitting method     = least_squares (trf), {self.nfev} model evaluations, "
            f"{self.seconds:.3g} s",
            f"    data points        = {self.ndata} ({len(forces)} forces: {force_text} pN; "
            f"{len(s['labels'])} molecule{'s' if len(s['labels']) > 1 else ''})",
            f"    free parameters    = {len(self.names)}",
            f"    degrees of freedom = {self.nfree}",
            *stats,
            f"    weighting          = {wtext}",
            f"    converged          = {self.success} ({self.message})",
            "[[Parameters]]",
        ]
        width = max(len(n) for n in [*self.names, *self.fixed, "name"]) + 2
        lines.append(
            f"    {'name':<{width}}{'value':>12}{'stderr':>16}  {'unit':<6}{'rel.err':>9}"
            f"{'start':>12}  bounds"
        )
        for j, name in enumerate(self.names):
            v = self.parameters[name].magnitude
            e = self.stderr[name].magnitude
            kind = c["kinds"][j][0]
            f = _DISPLAY[kind][2]
            if name in self.undetermined:
                etext, rel = "not determined", "-"
            else:
                etext = f"{e:.4g}"
                rel = f"{100 * e / abs(v):.2f}%" if v != 0 else "-"
            lo, hi = c["lower"][j] * f, c["upper"][j] * f
            lines.append(
                f"    {name:<{width}}{v:>12.6g}{etext:>16}  {self.units[name]:<6}{rel:>9}"
                f"{c['start'][j] * f:>12.6g}  ({lo:.4g}, {hi:.4g})"
            )
        if self.fixed:
            lines.append("[[Fixed]]")
            for name, q in self.fixed.items():
                lines.append(f"    {name:<{width}}{q.magnitude:>12.6g}  {q.units:~P}")
        pairs = []
        names = self.names
        corr = self.correlation.to_numpy()
        for a in range(len(names)):
            for b in range(a + 1, len(names)):
                if np.isfinite(corr[a, b]) and abs(corr[a, b]) >= min_correlation:
                    pairs.append((abs(corr[a, b]), names[a], names[b], corr[a, b]))
        if pairs:
            lines.append(f"[[Correlations]] (|C| >= {min_correlation:g})")
            for _, a, b, v in sorted(pairs, reverse=True):
                lines.append(f"    C({a}, {b}) = {v:+.4f}")
        if self.warnings:
            lines.append("[[Warnings]]")
            lines.extend(f"    {w}" for w in self.warnings)
        return "\n".join(lines)

    # ---- tables -------------------------------------------------------------------------
    def to_frame(self) -> pd.DataFrame:
        """One-row table (package convention): every free parameter and its stderr, fit stats.

        Columns ``<name>`` and ``<name>_stderr`` in the units of ``parameters``
        (``attrs["units"]``; the stderr is ``inf`` for an undetermined
        parameter), then ``reduced_chi_square``, ``chi_square`` (see the class
        docstring), ``residual_rms`` (nm), ``ndata``, ``nfree``, ``nfev``,
        ``weighting``, ``determined`` (False if any parameter is undetermined).
        """
        cols, units = {}, {}
        for name in self.names:
            cols[name] = [self.parameters[name].magnitude]
            cols[f"{name}_stderr"] = [self.stderr[name].magnitude]
            units[name] = units[f"{name}_stderr"] = self.units[name]
        for k, v, unit in (("reduced_chi_square", self.reduced_chi_square, ""),
                           ("chi_square", self.chi_square, ""),
                           ("residual_rms", self.residual_rms.magnitude, "nm"),
                           ("ndata", self.ndata, ""), ("nfree", self.nfree, ""),
                           ("nfev", self.nfev, ""), ("weighting", self.weighting, ""),
                           ("determined", not self.undetermined, "")):
            cols[k] = [v]
            units[k] = unit
        prov = provenance(self.dna, vary=list(self._spec["vary"]),
                          fixed={k: v for k, v in self.fixed.items()},
                          thermal=self.thermal, model="hat curve, MODEL.md s.6")
        return make_table(cols, units, prov)

    def points_frame(self) -> pd.DataFrame:
        """Per-point table: data, offset-corrected turns, best fit, residual, phase flags."""
        s, c = self._spec, self._core
        cols = {}
        units = {}
        if s["has_molecule"]:
            cols["molecule"] = [s["labels"][i] for i in s["mol_index"]]
            units["molecule"] = ""
        n_eff = s["turns"] - c["n0"][s["mol_index"]]
        for k, v, u in (
            ("force", s["force"] * 1e12, "pN"),
            ("turns", s["turns"], "turn"),
            ("turns_corrected", n_eff, "turn"),
            ("extension", s["extension"] * 1e9, "nm"),
            ("best_fit", c["model"] * 1e9, "nm"),
            ("residual", (s["extension"] - c["model"]) * 1e9, "nm"),
            ("torque", c["torque"] * 1e21, "pN*nm"),
            ("plectoneme_length", c["plectoneme_length"] * 1e9, "nm"),
            ("phase", c["phase"].astype(int), ""),
            ("short_tail", c["short_tail"], ""),
        ):
            cols[k] = v
            units[k] = u
        return make_table(cols, units, provenance(self.dna, vary=list(s["vary"])))

    # ---- figure -------------------------------------------------------------------------
    def plot(self, fig=None, n_curve=300):
        """Data, fit and residuals per force (offset-corrected); returns the Figure.

        Top row: extension minus the molecule's extension offset against
        turns minus its turns offset, with the fitted hat curve. Bottom row:
        residuals ``data - model``.
        """
        import matplotlib.pyplot as plt

        s, c = self._spec, self._core
        forces = np.unique(s["force"])
        nf = len(forces)
        if fig is None:
            fig = plt.figure(figsize=(min(4.2 * nf, 16), 5.2), layout="constrained")
        axes = fig.subplots(2, nf, sharex="col", squeeze=False,
                            gridspec_kw={"height_ratios": [3, 1]})
        mol = s["mol_index"]
        n_eff = s["turns"] - c["n0"][mol]
        z_corr = (s["extension"] - c["z0"][mol]) * 1e9
        resid = (s["extension"] - c["model"]) * 1e9
        markers = "osd^v<>p*hX"
        for k, f in enumerate(forces):
            ax, axr = axes[0, k], axes[1, k]
            sel = s["force"] == f
            for i, lab in enumerate(s["labels"]):
                m = sel & (mol == i)
                if not m.any():
                    continue
                label = f"molecule {lab}" if s["has_molecule"] and len(s["labels"]) > 1 else "data"
                kw = {"marker": markers[i % len(markers)], "ms": 3, "ls": "none", "alpha": 0.6}
                ax.plot(n_eff[m], z_corr[m], label=label if k == 0 else None, **kw)
                axr.plot(n_eff[m], resid[m], **kw)
            grid = np.linspace(n_eff[sel].min(), n_eff[sel].max(), n_curve)
            try:
                curve = _call_kernel(grid, np.full_like(grid, f), c["phys"], s["thermal"])
                ax.plot(grid, np.asarray(curve.extension) * 1e9, "k-", lw=1.5,
                        label="fit" if k == 0 else None)
            except SupercoilError:
                order = np.argsort(n_eff[sel])
                ax.plot(n_eff[sel][order], (c["model"][sel] - c["z0"][mol][sel])[order] * 1e9,
                        "k-", lw=1.5, label="fit" if k == 0 else None)
            ax.set_title(f"F = {f * 1e12:.3g} pN")
            axr.axhline(0, color="k", lw=0.8)
            axr.set_xlabel("turns - turns offset")
            if k == 0:
                ax.set_ylabel("extension - offset (nm)")
                axr.set_ylabel("residual (nm)")
        axes[0, 0].legend(fontsize="small")
        text = ", ".join(
            f"{k} = {_fmt_pm(self.parameters[k].magnitude, self.stderr[k].magnitude)} "
            f"{self.units[k]}"
            for k in self.names if k in PHYSICAL_PARAMETERS
        )
        if self.weighting == "unit":  # the reduced chi-square is a variance in nm^2 here
            stat = f"noise estimate (residual RMS) {self.residual_rms.magnitude:.3g} nm"
        else:
            stat = f"reduced chi-square {self.reduced_chi_square:.3g}"
        fig.suptitle(f"hat-curve fit: {text}; {stat}", fontsize="medium")
        return fig


def _fmt_pm(v, e):
    if np.isinf(e):
        return f"{v:.6g} (not determined)"
    if not np.isfinite(e) or e <= 0:
        return f"{v:.6g}"
    digits = max(0, 1 - math.floor(math.log10(e)))
    return f"{v:.{digits}f} ± {e:.{digits}f}" if digits < 12 else f"{v:.6g} ± {e:.2g}"


# --------------------------------------------------------------------------------------
# public API
# --------------------------------------------------------------------------------------


def fit_hat_curves(
    data,
    dna,
    vary=("twist_persistence", "radius"),
    fixed=None,
    bounds=None,
    *,
    start=None,
    sigma=None,
    fit_turns_offset=True,
    fit_extension_offset=True,
    thermal=True,
    max_nfev=None,
    tol=1e-10,
) -> FitResult:
    """Fit the hat-curve model to rotation curves at several forces at once.

    Parameters
    ----------
    data : pandas.DataFrame
        Long table in the package convention (as :func:`read_tweezers_csv`
        returns): ``force``, ``turns``, ``extension``, optional ``molecule``
        and ``sigma``, magnitudes in the units of ``data.attrs["units"]``.
    dna : DNA
        Start values of the varied parameters and values of all others
        (temperature included).
    vary : sequence of str
        DNA fields fitted, shared by all forces and molecules: any of
        ``length``, ``bending_persistence``, ``twist_persistence``, ``radius``.
    fixed : dict of str -> Quantity, optional
        Values held fixed: DNA fields (override ``dna``) or offsets
        (``"turns_offset"`` for all molecules, ``"turns_offset[m1]"`` for one,
        likewise ``extension_offset``); a fixed offset is not fitted.
    bounds : dict of str -> (Quantity or None, Quantity or None), optional
        Bounds of free parameters, same names as ``fixed`` (None: unbounded).
        Physical parameters are bounded below by 0 by default. The start
        values (from ``dna`` / ``start``) must lie strictly inside, else
        :class:`FitError` names the parameter before any fitting.
    start : dict of str -> Quantity, optional
        Start values overriding ``dna`` and the automatic offset guesses
        (turns offset: centre of symmetry of the curves; extension offset:
        median difference to the start model).
    sigma : Quantity [length], optional
        Standard error of the extensions (scalar or one per point); overrides
        a ``sigma`` column. Without either, unit weights are used and the
        covariance is scaled by the reduced chi-square.
    fit_turns_offset, fit_extension_offset : bool
        Fit the per-molecule offsets (default True). Off: held at 0 (or at
        the value in ``fixed``).
    thermal : bool
        Thermal hat curve (Moroz-Nelson tail); False for the athermal variant.
    max_nfev : int, optional
        Limit of model evaluations (default: scipy's, 100 x number of parameters).
    tol : float
        ``ftol = xtol = gtol`` of :func:`scipy.optimize.least_squares`.

    Returns
    -------
    FitResult

    Raises
    ------
    DataError
        The table is malformed (names the row and column).
    FitError
        Unknown or conflicting parameter names, bad bounds, a start value
        outside its bounds, the model failing at the start (a force without
        plectoneme equilibrium), or no convergence.

    Warns
    -----
    BoundWarning
        An estimate sits on a bound.
    FitWarning
        Singular Jacobian: names the parameters the data do not determine
        (their standard error is ``inf``, see :attr:`FitResult.undetermined`).
    ValidityWarning
        Data points in the short-tail or fully coiled region; negative turns
        above 0.8 pN (denaturation).
    """
    spec = _prepare(data, dna, vary, fixed, bounds, start, sigma, fit_turns_offset,
                    fit_extension_offset, thermal, max_nfev, tol)
    core = _fit_core(spec)
    _emit(core["warnings"])
    return FitResult(core, spec, data, dna)


def _fit_worker(spec):
    """Module-level (picklable) worker of :func:`fit_many`: never raises."""
    try:
        core = _fit_core(spec)
    except Exception as exc:  # reported per molecule, not raised for the batch
        return {"ok": False, "error": f"{type(exc).__name__}: {exc}"}
    keep = ("names", "kinds", "values", "stderr", "reduced_chi_square", "weighted_chi_square",
            "ndata", "nfree", "nfev", "warnings", "seconds", "n0", "z0", "undetermined")
    return {"ok": True, **{k: core[k] for k in keep}}


def fit_many(
    data,
    dna,
    vary=("twist_persistence", "radius"),
    fixed=None,
    bounds=None,
    *,
    executor=None,
    progress=None,
    **kwargs,
) -> pd.DataFrame:
    """Fit every molecule of ``data`` separately; one result row per molecule.

    Parameters
    ----------
    data : pandas.DataFrame
        As for :func:`fit_hat_curves`, with a ``molecule`` column (without it
        the whole table is one molecule).
    dna, vary, fixed, bounds, **kwargs
        As for :func:`fit_hat_curves` (offsets are named without the
        molecule suffix: ``"turns_offset"``).
    executor : concurrent.futures.Executor, optional
        Runs the fits in parallel (``ProcessPoolExecutor``, ``ThreadPoolExecutor``,
        ``dask.distributed.Client(...).get_executor()`` or the client itself, ...):
        each molecule is one
        ``executor.submit`` of a module-level function with picklable
        arguments (SI floats, no pint objects). None: serial.
    progress : callable, optional
        ``progress(done, total, molecule)`` after each molecule finishes.

    Returns
    -------
    pandas.DataFrame
        Package table convention, one row per molecule in order of first
        appearance: ``molecule``, ``success`` (the fit ran and converged),
        ``determined`` (False when the data of that molecule do not determine
        some free parameter, e.g. a nicked molecule with a flat curve: those
        parameters have ``<name>_stderr = inf`` and the ``warnings`` cell names
        them; also False for a failed fit), ``error`` (the exception for a
        failed fit, else ""), ``ndata`` (the molecule's data points, also for
        a failed fit), ``reduced_chi_square``, ``nfev``, then ``<name>`` and
        ``<name>_stderr`` for every varied parameter and offset (NaN where the
        fit failed; ``success`` says so), ``warnings``.
        Warnings of single fits are also re-issued, prefixed by the molecule.

    Raises
    ------
    DataError, FitError
        Only for problems common to all molecules (malformed table, unknown
        parameter names); failures of single fits are reported in the table.
    """
    df = check_tweezers_frame(data, source="data")
    start = kwargs.pop("start", None)
    if "molecule" in df.columns:
        raw = df["molecule"].astype(str).to_numpy()
        labels = list(dict.fromkeys(raw))
    else:
        raw, labels = None, ["0"]
    # validate the arguments once on the whole table (names, units, vary)
    names_check = _prepare(df.drop(columns=["molecule"], errors="ignore"), dna, vary,
                           _strip_molecule_keys(fixed), _strip_molecule_keys(bounds),
                           _strip_molecule_keys(start), kwargs.get("sigma"),
                           kwargs.get("fit_turns_offset", True),
                           kwargs.get("fit_extension_offset", True), kwargs.get("thermal", True),
                           kwargs.get("max_nfev"), kwargs.get("tol", 1e-10))
    allowed = {"sigma", "fit_turns_offset", "fit_extension_offset", "thermal", "max_nfev", "tol"}
    unknown = set(kwargs) - allowed
    if unknown:
        raise TypeError(f"fit_many got unexpected keyword arguments {sorted(unknown)}")
    sigma = kwargs.pop("sigma", None)
    specs = {}
    for lab in labels:
        if raw is None:
            sub = df.copy()
        else:
            sub = df.loc[raw == lab].drop(columns=["molecule"]).reset_index(drop=True)
        sub.attrs = dict(df.attrs)
        sig = sigma
        if sigma is not None and raw is not None and np.ndim(getattr(sigma, "magnitude", sigma)):
            sig = sigma[raw == lab]
        try:
            specs[lab] = _prepare(sub, dna, vary, _strip_molecule_keys(fixed),
                                  _strip_molecule_keys(bounds), _strip_molecule_keys(start), sig,
                                  kwargs.get("fit_turns_offset", True),
                                  kwargs.get("fit_extension_offset", True),
                                  kwargs.get("thermal", True), kwargs.get("max_nfev"),
                                  kwargs.get("tol", 1e-10))
        except SupercoilError as exc:
            specs[lab] = exc
    results = {}
    total = len(labels)
    done = 0

    def finished(lab, res):
        nonlocal done
        results[lab] = res
        done += 1
        if progress is not None:
            progress(done, total, lab)

    pending = {}
    for lab in labels:
        spec = specs[lab]
        if isinstance(spec, Exception):
            finished(lab, {"ok": False, "error": f"{type(spec).__name__}: {spec}"})
        elif executor is None:
            finished(lab, _fit_worker(spec))
        else:
            pending[executor.submit(_fit_worker, spec)] = lab
    if all(isinstance(f, Future) for f in pending):
        order = as_completed(pending)
    else:  # e.g. a dask.distributed Client used directly: its futures are not cf.Futures
        order = list(pending)
    for fut in order:
        lab = pending[fut]
        try:
            res = fut.result()
        except Exception as exc:  # the executor itself failed (e.g. a worker died)
            res = {"ok": False, "error": f"{type(exc).__name__}: {exc}"}
        finished(lab, res)

    # table
    param_names = list(names_check["names"])
    param_kinds = [k for k, _ in names_check["kinds"]]
    cols = {"molecule": [], "success": [], "determined": [], "error": [], "ndata": [],
            "reduced_chi_square": [], "nfev": []}
    units = {"molecule": "", "success": "", "determined": "", "error": "", "ndata": "",
             "reduced_chi_square": "", "nfev": ""}
    for name, kind in zip(param_names, param_kinds, strict=True):
        cols[name], cols[f"{name}_stderr"] = [], []
        units[name] = units[f"{name}_stderr"] = _DISPLAY[kind][1]
    cols["warnings"] = []
    units["warnings"] = ""
    for lab in labels:
        res = results[lab]
        cols["molecule"].append(lab)
        cols["success"].append(bool(res["ok"]))
        cols["error"].append("" if res["ok"] else res["error"])
        cols["determined"].append(bool(res["ok"]) and not np.any(res.get("undetermined", [])))
        if res["ok"]:
            cols["ndata"].append(int(res["ndata"]))
            cols["reduced_chi_square"].append(float(res["reduced_chi_square"]))
            cols["nfev"].append(int(res["nfev"]))
            by_name = dict(zip(res["names"], range(len(res["names"])), strict=True))
            for name, kind in zip(param_names, param_kinds, strict=True):
                j = by_name.get(name)
                f = _DISPLAY[kind][2]
                cols[name].append(np.nan if j is None else res["values"][j] * f)
                cols[f"{name}_stderr"].append(np.nan if j is None else res["stderr"][j] * f)
            cols["warnings"].append("; ".join(m for _, m in res["warnings"]))
            _emit(res["warnings"], prefix=f"molecule {lab}: ")
        else:
            cols["ndata"].append(len(df) if raw is None else int(np.sum(raw == lab)))
            cols["reduced_chi_square"].append(np.nan)
            cols["nfev"].append(0)
            for name in param_names:
                cols[name].append(np.nan)
                cols[f"{name}_stderr"].append(np.nan)
            cols["warnings"].append("")
    prov = provenance(dna, vary=list(names_check["vary"]), fixed=dict(fixed or {}),
                      bounds={k: list(v) for k, v in (bounds or {}).items()},
                      thermal=names_check["thermal"], weighting=names_check["weighting"],
                      model="hat curve, MODEL.md s.6")
    return make_table(cols, units, prov)


def _strip_molecule_keys(d):
    if d is None:
        return None
    out = {}
    for k, v in d.items():
        m = _NAME.match(k)
        if m and m.group("mol") is not None:
            raise FitError(f"fit_many fits each molecule alone: give {m.group('base')!r}, "
                           f"not {k!r}")
        out[k] = v
    return out


# --------------------------------------------------------------------------------------
# synthetic data (examples, validation, tests)
# --------------------------------------------------------------------------------------


def valid_turns_range(dna, force, min_tail=None, thermal=True):
    """Largest |N| (turns) at each force whose tail is still longer than ``min_tail``.

    Beyond it the hat curve enters the short-tail region where the Moroz-Nelson
    extension factor is not valid (MODEL.md s.6). ``min_tail`` defaults to 4
    bending persistence lengths (one more than the kernel's short-tail flag, so
    that a turns offset of a turn or two keeps the data valid).

    Returns a float array (turns), one per force.
    """
    from supercoil.core.dna.hat import hat_parameters

    si = dna.si
    F = np.atleast_1d(np.asarray(magnitude(force, U.N, "force"), dtype=float))
    lmin = 4 * si.bending_persistence if min_tail is None else float(
        magnitude(min_tail, U.m, "min_tail"))
    par = hat_parameters(F, si.length, si.bending_rigidity, si.torsional_rigidity, si.kT,
                         si.radius, thermal=thermal)
    return par.buckling_turns + (si.length - lmin) * par.linking_rate / (2 * np.pi)


def simulate_rotation_curves(
    dna,
    force,
    turns=None,
    *,
    points_per_force=110,
    noise=None,
    turns_offset=0.0,
    extension_offset=None,
    molecules=None,
    seed=None,
    thermal=True,
    extension_unit="um",
    sigma_column=False,
):
    """Synthetic rotation curves: the hat-curve model plus offsets and Gaussian noise.

    Parameters
    ----------
    dna : DNA
        The true parameters.
    force : Quantity [force], array
        One rotation curve per force (and per molecule).
    turns : array, optional
        Applied turns of every curve; default ``points_per_force`` points evenly
        over +-:func:`valid_turns_range` at each force.
    noise : Quantity [length], optional
        Standard deviation of the Gaussian extension noise (default 5 nm).
    turns_offset, extension_offset : float / Quantity or sequence, optional
        True offsets: the data are ``hat(N - turns_offset) + extension_offset``
        (one value, or one per molecule). Default 0 turns and 0 nm.
    molecules : int or sequence of str, optional
        Number (labels ``m1``, ``m2``, ...) or labels of molecules; with it the
        table has a ``molecule`` column.
    seed : int or numpy.random.Generator, optional
        Random seed (reproducible data).
    extension_unit : str
        Unit of the extension column (``"um"`` or ``"nm"``).
    sigma_column : bool
        Add a ``sigma`` column (nm) holding the noise level.

    Returns
    -------
    pandas.DataFrame
        The table convention of :func:`~supercoil.read_tweezers_csv`:
        ``[molecule,] force [pN], turns, extension [extension_unit][, sigma [nm]]``.
    """
    rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
    F = np.atleast_1d(np.asarray(magnitude(force, U.N, "force"), dtype=float))
    sd = 5e-9 if noise is None else float(magnitude(noise, U.m, "noise"))
    if molecules is None:
        labels, has_mol = ["m1"], False
    elif isinstance(molecules, int):
        labels, has_mol = [f"m{i + 1}" for i in range(molecules)], True
    else:
        labels, has_mol = [str(m) for m in molecules], True
    n0 = np.broadcast_to(np.asarray(as_turns(turns_offset, "turns_offset"), dtype=float),
                         (len(labels),))
    z0 = np.broadcast_to(
        np.asarray(magnitude(extension_offset if extension_offset is not None else 0 * U.nm,
                             U.m, "extension_offset"), dtype=float), (len(labels),))
    if turns is None:
        nmax = valid_turns_range(dna, quantity(F, U.N), thermal=thermal)
        grids = [np.linspace(-m, m, points_per_force) for m in nmax]
    else:
        grids = [np.asarray(as_turns(turns, "turns"), dtype=float)] * len(F)
    factor = {"um": 1e6, "nm": 1e9}[extension_unit]
    cols = {"molecule": [], "force": [], "turns": [], "extension": []}
    phys = {"length": dna.si.length, "bending_persistence": dna.si.bending_persistence,
            "twist_persistence": dna.si.twist_persistence, "radius": dna.si.radius,
            "temperature": dna.si.temperature}
    for i, lab in enumerate(labels):
        N = np.concatenate(grids)
        FF = np.concatenate([np.full(len(g), f) for g, f in zip(grids, F, strict=True)])
        z = np.asarray(_call_kernel(N - n0[i], FF, phys, thermal).extension, dtype=float)
        z = z + z0[i] + rng.normal(0.0, sd, z.shape)
        cols["molecule"].extend([lab] * len(N))
        cols["force"].append(FF * 1e12)
        cols["turns"].append(N)
        cols["extension"].append(z * factor)
    table = {"molecule": cols["molecule"]} if has_mol else {}
    table.update(force=np.concatenate(cols["force"]), turns=np.concatenate(cols["turns"]),
                 extension=np.concatenate(cols["extension"]))
    units = {"molecule": "", "force": "pN", "turns": "", "extension": extension_unit}
    if sigma_column:
        table["sigma"] = np.full(len(table["force"]), sd * 1e9)
        units["sigma"] = "nm"
    prov = provenance(
        dna, simulated=True, noise=f"{sd * 1e9:.6g} nm", seed=seed if isinstance(seed, int)
        else None, turns_offset=[float(v) for v in n0],
        extension_offset=[f"{v * 1e9:.6g} nm" for v in z0], thermal=thermal,
    )
    return make_table(table, {k: units[k] for k in table}, prov)
