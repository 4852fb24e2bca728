"""Fitting hat curves to magnetic-tweezers rotation curves: :func:`fit_hat_curves` and its engine.

docs/theory/fitting.md. The model (:mod:`supercoil.dna.fitting.model`) is any
registered DNA model through the model interface; the parameters
(:mod:`supercoil.dna.fitting.fit_parameters`) are DNA fields, model and interaction
parameters and per-molecule offsets. :func:`scipy.optimize.least_squares`
(trust-region reflective, bounds) on scaled variables; covariance from the thin
SVD of the Jacobian (:mod:`supercoil.dna.fitting.covariance`); plausibility
and goodness-of-fit checks (:mod:`supercoil.dna.fitting.diagnostics`).

The engine (:func:`run_fit`) works on a :class:`FitSpec` of plain SI data and
returns a :class:`~supercoil.dna.fitting.solution.FitSolution` (typed plain data), so
:func:`~supercoil.fit_many` runs it in worker processes. The keywords the fitting
functions share have their defaults once, in :data:`~supercoil.dna.fitting.options.DEFAULTS`.
"""

from __future__ import annotations

import time
import warnings

import numpy as np
from scipy.optimize import least_squares

from supercoil import display
from supercoil._checks import check_flag
from supercoil.core.dna.interface import FULLY_COILED
from supercoil.dna.fitting import diagnostics as _diag
from supercoil.dna.fitting import offsets as _offsets
from supercoil.dna.fitting import start as _start
from supercoil.dna.fitting.covariance import covariance
from supercoil.dna.fitting.data import RotationData
from supercoil.dna.fitting.fit_parameters import CALIBRATION, FitParameters
from supercoil.dna.fitting.joint_noise import channels_info, joint_noise, tested_chi2
from supercoil.dna.fitting.model import HatCurveModel
from supercoil.dna.fitting.options import DEFAULT_VARY, DEFAULTS, FitOptions, FitSpec
from supercoil.dna.fitting.prepare import (
    build_parameters,
    extension_offset_mode,
    prepare,
    resolve_model,
)
from supercoil.dna.fitting.result import FitResult
from supercoil.dna.fitting.solution import FitSolution
from supercoil.dna.fitting.spread import spread_nodes
from supercoil.dna.validity import check_dna
from supercoil.exceptions import (
    BoundWarning,
    FitError,
    FitWarning,
    NoEquilibriumError,
    SupercoilWarning,
    ValidityError,
    ValidityWarning,
)

__all__ = ["DEFAULTS", "DEFAULT_VARY", "FitOptions", "FitSpec", "fit_hat_curves", "prepare",
           "resolve_model", "run_fit"]


def _start_offsets(spec, prob, located):
    """Start values not given, read from the data: the turns offsets and a varied length
    (:func:`~supercoil.dna.fitting.start.start_from_data`; the turns channels' values go
    into ``located``), then the extension offsets (median difference to the model).
    Returns the notes saying what was used."""
    data, params = spec.data, spec.params
    groups = data.groups()
    notes = _start.start_from_data(data, params, spec.dna, located)
    u = params.vector()
    try:
        z_start = np.asarray(prob.points(u)[0].extension, dtype=float)
    except (NoEquilibriumError, ValidityError) as exc:
        forces = ", ".join(f"{f:.4g}" for f in display.to_display(np.unique(data.force),
                                                                   "force"))
        raise FitError(
            f"cannot start the fit: the model {spec.model.name!r} fails with the start "
            f"parameters ({prob.describe()}, temperature = {spec.dna.temperature:.6g} K) at "
            f"the data's forces ({forces} pN): {type(exc).__name__}: {exc}") from exc
    for p in params.values():
        if p.vary and not p.given and p.kind == "extension_offset":
            g = groups[p.molecule] if p.shared != "per-force" else _offsets.curve_rows(data, p)
            p.value = float(np.median(data.extension[g] - z_start[g]))
    return notes


def _start_vector(params):
    """Scaled start vector; moves guessed values inside their bounds, else FitError."""
    for p in params.free_params():
        if p.min < p.value < p.max:
            continue
        if not p.given:
            lo, hi = p.min, p.max
            p.value = (lo + hi) / 2 if np.isfinite(hi - lo) else (
                lo + 1e-3 * max(1.0, abs(lo)) if np.isfinite(lo) else hi - 1e-3 * max(1.0, abs(hi)))
            continue
        f = p.factor
        raise FitError(f"start value of {p.name} = {p.value * f:.6g} {p.unit} lies outside its "
                       f"bounds ({p.min * f:.6g}, {p.max * f:.6g}) {p.unit} (bounds are "
                       "exclusive; give a start value inside them)")
    return params.vector()


def _solve(spec, prob, u0):
    lb, ub = spec.params.bounds_vector()
    r0 = prob.residual(u0)
    if not np.all(np.isfinite(r0)):
        raise FitError(f"cannot start the fit: {prob.last_failure}")
    tol = spec.tol
    try:
        res = least_squares(prob.residual, u0, jac=prob.jacobian, bounds=(lb, ub), method="trf",
                            x_scale=1.0, ftol=tol, xtol=tol, gtol=tol, max_nfev=spec.max_nfev)
    except FitError:
        raise
    except (ValueError, np.linalg.LinAlgError) as exc:
        raise FitError(f"least_squares failed: {exc}") from exc
    if res.status <= 0 or not np.all(np.isfinite(res.fun)):
        raise FitError(
            f"the fit did not converge ({res.message}) after {res.nfev} evaluations; last "
            f"parameters: {prob.describe(res.x)}" + _diag.runaway_hint(spec.params, res.x)
            + (f"; last kernel failure: {prob.last_failure}" if prob.last_failure else ""))
    return res


#: the solver under a public name (the profile likelihood's refits use it)
solve = _solve


def run_fit(spec: FitSpec, time_curve=False) -> FitSolution:
    """Run one fit on a prepared spec: a :class:`FitSolution` (plain picklable data).

    Warnings are records in :attr:`FitSolution.warnings` (the caller issues
    them). ``time_curve``: also measure the CPU time of one evaluation of the
    model at the data points (:attr:`FitSolution.curve_cpu_seconds`).
    """
    t0, c0 = time.perf_counter(), time.process_time()
    cls = (_offsets.PerForceOffsetModel if _offsets.has_per_force_offsets(spec.params)
           else HatCurveModel)
    prob = cls(spec.data, spec.params, spec.dna, spec.model, spec.interaction, spec.thermal,
               spec.xi_is_bending)
    pre = _start.length_records(spec)
    located = {}
    start_notes = _start_offsets(spec, prob, located)
    u0 = _start_vector(spec.params)
    start = u0 * spec.params.scales
    res = _solve(spec, prob, u0)
    res, noise = joint_noise(spec, prob, res, _solve)
    u = res.x
    J = prob.jacobian(u)
    flat = ~np.any(J, axis=0)  # the model does not change with them: back to their start
    if flat.any() and not np.array_equal(u[flat], u0[flat]):
        u = np.where(flat, u0, u)
        J = prob.jacobian(u)
    r = prob.residual(u)
    n = len(r)
    chi2 = float(r @ r)
    nfree = n - len(u)
    # dimensionless chi-square: extension-only unit weights are 1 nm; the noise estimate
    # (residual variance) is their sigma (then chisqr == nfree by construction)
    s2 = chi2 / nfree if spec.data.weighting == "unit" and not spec.data.has_torque else 1.0
    s2 = s2 if s2 > 0 else 1.0
    channels = channels_info(spec, prob, u, noise)
    cov_u, undetermined, note = covariance(J, prob.names)
    records = pre + ([("FitWarning", note)] if note else [])
    if spec.data.weighting == "unit" and not spec.data.has_torque:
        cov_u = cov_u * (chi2 / nfree)
    scales = spec.params.scales
    cov = cov_u * np.outer(scales, scales)
    stderr = np.sqrt(np.clip(np.diag(cov), 0, None))
    stderr[undetermined] = np.inf
    spec.params.set_vector(u, stderr)
    records += _diag.bound_records(spec.params, u)
    records += [("FitWarning", m) for m in _start.turns_runaway_messages(spec.params, located)]
    pts, z0_pts = prob.points(u)
    dna, model, inter = prob.fitted(u)
    n0, z0 = prob.unpack(u)[3:]
    best = np.asarray(pts.extension, dtype=float) + z0_pts
    records += _validity_records(spec, pts, n0, model, dna)
    records += [("FitWarning", m) for m in _diag.plausibility_messages(spec.params)
                + _diag.length_offset_messages(spec.params, prob.names, cov, undetermined,
                                               spec.data, n0, dna)]
    gof, gof_info = _diag.goodness_messages(spec.data.weighting, *tested_chi2(channels, nfree),
                                            spec.data.extension - best, spec.data)
    records += [("FitWarning", m) for m in gof]
    cpu = time.process_time() - c0
    return FitSolution(
        names=list(prob.names), params=spec.params, values=u * scales, stderr=stderr,
        start=start, covariance=cov, undetermined=np.asarray(undetermined, dtype=bool),
        chi_square=chi2, reduced_chi_square=chi2 / nfree, chisqr=chi2 / s2,
        redchi=chi2 / s2 / nfree, ndata=n, nfree=nfree, jac=J / np.sqrt(s2),
        residual_weighted=r, residual_scale=float(np.sqrt(s2)),
        nfev=int(res.nfev), njev=int(prob.njev), kernel_calls=int(prob.n_kernel_calls),
        kernel_failures=int(prob.n_kernel_failures), status=int(res.status),
        message=str(res.message), dna=dna, model=model,
        interaction=inter,
        turns_offset=n0, extension_offset=z0,
        extension_offset_points=np.asarray(z0_pts, dtype=float),
        states=prob.states(u) if prob.per_force else None, best_fit=best,
        torque=prob.torque_prediction(u),  # the predicted measured torque
        phase=np.asarray(pts.phase), short_tail=np.asarray(pts.short_tail, dtype=bool),
        plectoneme_length=np.asarray(pts.plectoneme_length, dtype=float),
        calibration={k: prob.scale(k, u) for k in CALIBRATION}, goodness=gof_info,
        warnings=records, channels=channels, notes=list(spec.notes) + start_notes,
        seconds=time.perf_counter() - t0, cpu_seconds=cpu,
        curve_cpu_seconds=_curve_cost(prob, u) if time_curve else None)


def _curve_cost(prob, u):
    """CPU seconds of one model evaluation at the data points (``time.process_time``; the
    mean of repeats until 20 ms of CPU, at most 50)."""
    dna, model, inter = prob.fitted(u)
    turns = prob.data.turns - prob.unpack(u)[3][prob.data.mol_index]
    force = prob.data.force * prob.scale("force_scale", u)
    spread = prob.scale("force_spread", u)
    if spread:  # the node points of the average (docs/theory/fitting.md)
        turns, force, factor = spread_nodes(turns, force, spread)
        force = force * factor
    n, c0 = 0, time.process_time()
    while n < 50 and (n == 0 or time.process_time() - c0 < 0.02):
        model.points(turns, force, dna, prob.thermal, inter, None)
        n += 1
    return (time.process_time() - c0) / n


def _validity_records(spec, pts, n0, model, dna):
    """The fit's validity warnings: points outside the model's range, then the model's
    messages at the data (the shared limits and its own, :meth:`DNAModel.validity`)."""
    data = spec.data
    n_eff = data.turns - n0[data.mol_index]
    phase = np.asarray(pts.phase)
    short = np.asarray(pts.short_tail, dtype=bool)
    out = []
    bad = short | (phase == FULLY_COILED)
    if bad.any():
        out.append(("ValidityWarning",
                    f"{int(bad.sum())} of {data.n} data points lie where the hat-curve model "
                    f"is not valid ({int((phase == FULLY_COILED).sum())} fully coiled, "
                    f"{int(short.sum())} with a tail shorter than a few persistence lengths); "
                    "exclude the large-|turns| ends of the curves"))
    return out + [("ValidityWarning", m)
                  for m in model.validity(n_eff, data.force, pts, dna, spec.thermal)]


_WARNING_CLASSES = {"BoundWarning": BoundWarning, "FitWarning": FitWarning,
                    "ValidityWarning": ValidityWarning}


def emit(records, prefix="", stacklevel=3):
    """Issue warning records ``(category name, message)``."""
    for cat, msg in records:
        warnings.warn(prefix + msg, _WARNING_CLASSES.get(cat, SupercoilWarning),
                      stacklevel=stacklevel)


def fit_hat_curves(data, dna, vary=DEFAULTS.vary, fixed=DEFAULTS.fixed, bounds=DEFAULTS.bounds,
                   *, start=DEFAULTS.start, sigma=DEFAULTS.sigma,
                   fit_turns_offset=DEFAULTS.fit_turns_offset,
                   fit_extension_offset=DEFAULTS.fit_extension_offset,
                   thermal=DEFAULTS.thermal, max_nfev=DEFAULTS.max_nfev, tol=DEFAULTS.tol,
                   model=DEFAULTS.model, interaction=DEFAULTS.interaction, params=None):
    """Fit a hat-curve model to rotation curves at several forces at once.

    Parameters
    ----------
    data : pandas.DataFrame
        Long table as :func:`read_tweezers_csv` returns: ``force``, ``turns``,
        ``extension``, optional ``molecule`` and ``sigma`` (``attrs["units"]``).
        With a ``torque`` column (optional ``torque_sigma``) extension and
        torque are fitted jointly, each channel with its stated sigmas or its
        own noise estimate (docs/theory/fitting.md#joint-torque-fit);
        :attr:`FitResult.channels` has each channel's statistics.
    dna : DNA
        Start values of the varied parameters, values of all others.
    vary : sequence of str
        Parameters fitted, shared by all forces and molecules: DNA fields
        (``length``, ``bending_persistence``, ``twist_persistence``,
        ``radius``) and the parameters the model and the interaction declare.
        The default (:data:`DEFAULT_VARY`) drops a field the model does not
        use (``radius`` for ``marko2007``), with a note; named explicitly it is
        fitted and reported undetermined.
    fixed : dict of str -> Quantity, optional
        Values held fixed: DNA fields (override ``dna``), model or interaction
        parameters, or offsets (``"turns_offset"`` for all molecules,
        ``"turns_offset[m1]"`` for one, likewise ``extension_offset``).
    bounds : dict of str -> (Quantity or None, Quantity or None), optional
        Bounds of free parameters, same names as ``fixed`` (None: unbounded).
        DNA fields are bounded below by 0, model and interaction parameters by
        their declared range. Start values must lie strictly inside, else
        :class:`FitError` names the parameter before any fitting.
    start : dict of str -> Quantity, optional
        Start values overriding ``dna`` and the starts read from the data
        (docs/theory/fitting.md#start-values): the turns offset from the
        torque zero crossing, else the hat symmetry when the data straddle the
        maximum, else 0 (the report's notes say which); a varied ``length``
        from the worm-like chain at the turns nearest zero; the extension
        offset from the median difference to the model.
    sigma : Quantity [length], optional
        Standard error of the extensions: a scalar, or one value per data row
        (overrides a ``sigma`` column); in ``[1e-150 L, L]``. Any other shape
        (e.g. one per force) is a ValueError naming the accepted shapes.
        Without either: unit weights, errors scaled by the noise.
    fit_turns_offset : bool
        Fit the per-molecule turns offset (default); off: held at 0 or at ``fixed``.
    fit_extension_offset : bool or {"per-molecule", "per-force"}
        Fit the extension offset (the bead-height reference). Default (True,
        ``"per-molecule"``): a molecule is one bead, one offset for all its
        forces. ``"per-force"``: one per (molecule, force) curve, named
        ``extension_offset[0.3 pN]`` (``extension_offset[m1, 0.3 pN]`` with a
        molecule column), for curves referenced separately. False: held at 0
        or at ``fixed``.
    thermal : bool
        Thermal hat curve (Moroz-Nelson tail); False for the athermal variant.
    max_nfev : int, optional
        Limit of model evaluations (default: scipy's, 100 x number of parameters).
    tol : float
        ``ftol = xtol = gtol`` of :func:`scipy.optimize.least_squares`.
    model : str or DNAModel
        The hat-curve construction (default ``"li-zhao"``); any registered model.
    interaction : str or Interaction
        The plectoneme interaction (default ``"hard-core"``).
    params : FitParameters, optional
        Full control (:func:`fit_parameters` builds the default set to edit);
        excludes ``vary``, ``fixed``, ``bounds`` and ``start``.

    Returns
    -------
    FitResult

    Raises
    ------
    DataError
        The table is malformed (names the row and column).
    FitError
        Unknown or conflicting names, bad bounds, a start value outside its
        bounds, extensions beyond a fixed contour length (names both and the
        fix), the model failing at the start, or no convergence; a stated
        sigma outside ``[1e-150 L, L]``.
    ValueError
        ``sigma`` neither a scalar nor one value per data row.
    ModelError
        Unknown model or interaction; an interaction for a model without one.

    Warns
    -----
    BoundWarning
        An estimate sits on a bound.
    FitWarning
        Extensions beyond the contour length given (varied length: the fit
        starts it from the data); singular Jacobian (names the parameters the
        data do not determine: they are not counted in AIC and BIC);
        an estimate at or beyond its plausible limit; residuals inconsistent
        with the stated sigmas (chi-square test) or with the model (runs test
        with unit weights); see :mod:`supercoil.dna.fitting.diagnostics`.
    ValidityWarning
        Data points in the short-tail or fully coiled region; negative turns
        above 0.8 pN (denaturation); the model's own validity messages.
    """
    options = FitOptions(vary, fixed, bounds, start, sigma, fit_turns_offset,
                         fit_extension_offset, thermal, max_nfev, tol, model, interaction)
    spec = prepare(data, dna, options, params=params)
    solution = run_fit(spec)
    emit(solution.warnings)
    return FitResult(solution, spec, data, dna)


def fit_parameters(data, dna, vary=DEFAULTS.vary, fixed=DEFAULTS.fixed, bounds=DEFAULTS.bounds,
                   *, start=DEFAULTS.start, fit_turns_offset=DEFAULTS.fit_turns_offset,
                   fit_extension_offset=DEFAULTS.fit_extension_offset, model=DEFAULTS.model,
                   interaction=DEFAULTS.interaction) -> FitParameters:
    """The :class:`FitParameters` that :func:`fit_hat_curves` would build (to edit, then pass
    as ``params=``): start values, bounds, ``vary`` flags, plausible limits.

    Guessed offsets have ``given=False`` (their start values are set by the fit).
    Model and interaction parameters held fixed must be set on the model or
    interaction instance passed to the fit.
    """
    check_dna(dna)
    m, inter = resolve_model(model, interaction)
    rot = RotationData.from_frame(data)
    z0_fit, z0_per_force = extension_offset_mode(fit_extension_offset)
    return build_parameters(rot, dna, m, inter, vary, fixed, bounds, start,
                            check_flag(fit_turns_offset, "fit_turns_offset"), z0_fit,
                            z0_per_force)[0]


#: names that lived in this module before the fit package was split (old import paths)
_MOVED = {"simulate_rotation_curves": "simulate", "valid_turns_range": "simulate",
          "fit_many": "batch", "compare_models": "compare"}


def __getattr__(name):
    """Old import paths (``from supercoil.dna.fitting.fit import simulate_rotation_curves``)."""
    if name in _MOVED:
        import importlib

        return getattr(importlib.import_module(f"supercoil.dna.fitting.{_MOVED[name]}"), name)
    if name == "PHYSICAL_PARAMETERS":
        from supercoil.dna.fitting.fit_parameters import DNA_FIELDS

        return DNA_FIELDS
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
