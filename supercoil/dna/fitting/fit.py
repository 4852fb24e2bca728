"""Fitting hat curves to magnetic-tweezers rotation curves: :func:`fit_hat_curves` and its engine.

docs/theory/fitting.md. The model (:mod:`supercoil.dna.fitting.model`) is any
registered DNA model through the model interface; the parameters
(:mod:`supercoil.dna.fitting.fit_parameters`) are DNA fields, model and interaction
parameters and per-molecule offsets. :func:`scipy.optimize.least_squares`
(trust-region reflective, bounds) on scaled variables; covariance from the thin
SVD of the Jacobian (:mod:`supercoil.dna.fitting.covariance`); plausibility
and goodness-of-fit checks (:mod:`supercoil.dna.fitting.diagnostics`).

The engine (:func:`run_fit`) works on a :class:`FitSpec` of plain SI data and
returns plain data, so :func:`~supercoil.fit_many` runs it in worker processes.
"""

from __future__ import annotations

import dataclasses
import time
import warnings

import numpy as np
from scipy.optimize import least_squares

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
from supercoil.dna.fitting.prepare import build_parameters
from supercoil.dna.fitting.result import FitResult
from supercoil.dna.fitting.weights import check_sigma_scale, checked_sigma
from supercoil.dna.interactions import DEFAULT_INTERACTION, get_interaction
from supercoil.dna.models import DEFAULT_MODEL, get_model
from supercoil.dna.validity import check_dna, check_interaction
from supercoil.exceptions import (
    BoundWarning,
    FitError,
    FitWarning,
    ModelError,
    NoEquilibriumError,
    SupercoilWarning,
    ValidityError,
    ValidityWarning,
)

__all__ = ["DEFAULT_VARY", "FitSpec", "fit_hat_curves", "prepare", "run_fit"]

#: the DNA fields fitted by default
DEFAULT_VARY = ("twist_persistence", "radius")


@dataclasses.dataclass
class FitSpec:
    """Everything one fit needs, as plain picklable data (SI floats, numpy arrays)."""

    data: RotationData
    params: FitParameters
    dna: object  # DNASI
    xi_is_bending: bool
    model: object
    interaction: object
    thermal: bool
    max_nfev: int | None
    tol: float
    vary: list
    #: what the preparation decided for the user (a dropped parameter, ...): the report's notes
    notes: list = dataclasses.field(default_factory=list)


def resolve_model(model, interaction):
    """``(model, interaction)`` instances; ModelError for an interaction the model cannot take."""
    m = get_model(model)
    if interaction is None or interaction == DEFAULT_INTERACTION:
        return m, get_interaction(DEFAULT_INTERACTION)
    if not m.uses_interaction:
        raise ModelError(f"model {m.name!r} has no plectoneme helix state, so it takes no "
                         f"interaction (got interaction={interaction!r})")
    return m, get_interaction(interaction)


def prepare(data, dna, vary=DEFAULT_VARY, fixed=None, bounds=None, start=None, sigma=None,
            fit_turns_offset=True, fit_extension_offset=True, thermal=True, max_nfev=None,
            tol=1e-10, model=DEFAULT_MODEL, interaction=DEFAULT_INTERACTION, params=None,
            rotation=None, optional=None):
    """Validate every argument and convert to SI: the :class:`FitSpec` of one fit.

    ``optional``: varied names that are dropped (held at their value, with a
    note) when the model does not use them; default: the names of
    :data:`DEFAULT_VARY` when ``vary`` is the default.
    """
    thermal = check_flag(thermal, "thermal")
    fit_turns_offset = check_flag(fit_turns_offset, "fit_turns_offset")
    fit_extension_offset, z0_per_force = _extension_offset_mode(fit_extension_offset)
    check_dna(dna)
    m, inter = resolve_model(model, interaction)
    if m.uses_interaction:
        check_interaction(inter, dna.si)  # with the hard-core scale A/r0
    else:
        inter.check(dna.si)
    own_params = params is not None
    if rotation is None:
        rotation = RotationData.from_frame(data)
    rot = rotation if sigma is None else rotation.with_sigma(checked_sigma(sigma, rotation))
    check_sigma_scale(rot, dna.si.length)
    if params is None:
        params, si, m, inter = build_parameters(rot, dna, m, inter, vary, fixed, bounds, start,
                                                fit_turns_offset, fit_extension_offset,
                                                z0_per_force)
    else:
        if not isinstance(params, FitParameters):
            raise TypeError(f"params must be a FitParameters, got {type(params).__name__}")
        if fixed or bounds or start or vary is not DEFAULT_VARY:
            raise FitError("give either params= or vary/fixed/bounds/start, not both")
        params, si = params.copy(), dna.si
        _check_params(params, rot, m, inter)
    _start.check_length(params, si, rot)
    if optional is None:  # a params= set is the user's full control: nothing dropped
        default = (not own_params and not isinstance(vary, str)
                   and tuple(vary or ()) == DEFAULT_VARY)
        optional = DEFAULT_VARY if default else ()
    notes = _start.drop_unused(params, optional, rot, si, m, inter, thermal,
                         dna.wlc_persistence is None)
    vary = list(dict.fromkeys(p.kind for p in params.free_params() if p.owner != "offset"))
    return FitSpec(rot, params, si, dna.wlc_persistence is None, m, inter, thermal, max_nfev,
                   float(tol), vary, notes)


def _extension_offset_mode(value):
    """``(fitted, per force)`` from ``fit_extension_offset`` (bool, "per-molecule", "per-force")."""
    if isinstance(value, str):
        if value not in ("per-molecule", "per-force"):
            raise TypeError(f"fit_extension_offset must be True or False, got {value!r} (or "
                            "'per-molecule', the default, or 'per-force')")
        return True, value == "per-force"
    return check_flag(value, "fit_extension_offset"), False


def _check_params(params, rot, model, inter):
    allowed = {"dna": ("length", "bending_persistence", "twist_persistence", "radius"),
               "model": tuple(model.parameters), "interaction": tuple(inter.parameters),
               "offset": ("turns_offset", "extension_offset"),
               "calibration": tuple(CALIBRATION)}
    forces = np.unique(rot.force)
    for p in params.values():
        want = (("per-molecule", "per-force") if p.kind == "extension_offset" else
                ("per-molecule",)) if p.owner == "offset" else ("global", "per-force")
        if p.shared not in want:
            raise FitError(f"parameter {p.name!r}: shared={p.shared!r} is not supported for "
                           f"{p.owner} parameters (only {' or '.join(map(repr, want))})")
        if p.shared == "per-force" and not (p.force is not None and np.isclose(
                forces, p.force, rtol=1e-9, atol=0).any()):
            raise FitError(f"per-force parameter {p.name!r}: its force is not one of the "
                           "data's forces")
        if p.kind not in allowed.get(p.owner, ()):
            raise FitError(f"parameter {p.name!r}: {p.owner} parameter {p.kind!r} is not one "
                           f"of {list(allowed.get(p.owner, ()))}")
        in_data = p.molecule is not None and 0 <= p.molecule < rot.n_molecules
        if p.owner == "offset" and not in_data:
            raise FitError(f"parameter {p.name!r}: molecule index {p.molecule} not in the data")
    if not params.free:
        raise FitError("nothing to fit: no parameter has vary=True")
    if rot.n - len(params.free) <= 0:
        raise FitError(f"{rot.n} data points cannot determine {len(params.free)} free parameters")


def _start_offsets(spec, prob):
    """Start values not given, read from the data: the turns offsets and a varied length
    (:func:`~supercoil.dna.fitting.start.start_from_data`), then the extension offsets
    (median difference to the model). Returns the notes saying what was used."""
    data, params = spec.data, spec.params
    groups = data.groups()
    notes = _start.start_from_data(data, params, spec.dna)
    u = params.vector()
    try:
        z_start = np.asarray(prob.points(u)[0].extension, dtype=float)
    except (NoEquilibriumError, ValidityError) as exc:
        forces = ", ".join(f"{f * 1e12:.4g}" for f in np.unique(data.force))
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
            f"parameters: {prob.describe(res.x)}"
            + (f"; last kernel failure: {prob.last_failure}" if prob.last_failure else ""))
    return res


#: the solver under a public name (the profile likelihood's refits use it)
solve = _solve


def run_fit(spec: FitSpec) -> dict:
    """Run one fit on a prepared spec; a dict of plain data (picklable), warnings as records."""
    t0 = time.perf_counter()
    cls = (_offsets.PerForceOffsetModel if _offsets.has_per_force_offsets(spec.params)
           else HatCurveModel)
    prob = cls(spec.data, spec.params, spec.dna, spec.model, spec.interaction, spec.thermal,
               spec.xi_is_bending)
    pre = _start.length_records(spec)
    start_notes = _start_offsets(spec, prob)
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
    pts, z0_pts = prob.points(u)
    dna, model, inter, n0, z0 = prob.unpack(u)
    best = np.asarray(pts.extension, dtype=float) + z0_pts
    records += _validity_records(spec, pts, n0, model, dna)
    records += [("FitWarning", m) for m in _diag.plausibility_messages(spec.params)]
    gof, gof_info = _diag.goodness_messages(spec.data.weighting, *tested_chi2(channels, nfree),
                                            spec.data.extension - best, spec.data)
    records += [("FitWarning", m) for m in gof]
    return {
        "names": list(prob.names), "params": spec.params, "values": u * scales,
        "stderr": stderr, "covariance": cov, "start": start, "undetermined": undetermined,
        "chi_square": chi2, "reduced_chi_square": chi2 / nfree, "ndata": n, "nfree": nfree,
        "chisqr": chi2 / s2, "redchi": chi2 / s2 / nfree, "jac": J / np.sqrt(s2),
        "residual_scale": float(np.sqrt(s2)),
        "nfev": int(res.nfev), "njev": int(prob.njev), "kernel_calls": prob.n_kernel_calls,
        "status": int(res.status), "message": str(res.message),
        "kernel_failures": prob.n_kernel_failures, "dna": dna, "model_obj": model,
        "interaction_obj": inter.interaction, "n0": n0, "z0": z0, "model": best,
        "z0_points": np.asarray(z0_pts, dtype=float),
        "states": prob.states(u) if prob._per_force else None,
        "phase": np.asarray(pts.phase), "short_tail": np.asarray(pts.short_tail, dtype=bool),
        "torque": prob.torque_prediction(u),  # the predicted measured torque
        "calibration": {k: prob.scale(k, u) for k in CALIBRATION},
        "plectoneme_length": np.asarray(pts.plectoneme_length, dtype=float),
        "residual_weighted": r, "goodness": gof_info, "warnings": records,
        "channels": channels, "notes": list(spec.notes) + start_notes,
        "seconds": time.perf_counter() - t0,
    }


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


def fit_hat_curves(data, dna, vary=DEFAULT_VARY, fixed=None, bounds=None, *, start=None,
                   sigma=None, fit_turns_offset=True, fit_extension_offset=True, thermal=True,
                   max_nfev=None, tol=1e-10, model=DEFAULT_MODEL,
                   interaction=DEFAULT_INTERACTION, params=None):
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
    spec = prepare(data, dna, vary, fixed, bounds, start, sigma, fit_turns_offset,
                   fit_extension_offset, thermal, max_nfev, tol, model, interaction, params)
    core = run_fit(spec)
    emit(core["warnings"])
    return FitResult(core, spec, data, dna)


def fit_parameters(data, dna, vary=DEFAULT_VARY, fixed=None, bounds=None, *, start=None,
                   fit_turns_offset=True, fit_extension_offset=True, model=DEFAULT_MODEL,
                   interaction=DEFAULT_INTERACTION) -> FitParameters:
    """The :class:`FitParameters` that :func:`fit_hat_curves` would build (to edit, then pass
    as ``params=``): start values, bounds, ``vary`` flags, plausible limits.

    Guessed offsets have ``given=False`` (their start values are set by the fit).
    Model and interaction parameters held fixed must be set on the model or
    interaction instance passed to the fit.
    """
    check_dna(dna)
    m, inter = resolve_model(model, interaction)
    rot = RotationData.from_frame(data)
    z0_fit, z0_per_force = _extension_offset_mode(fit_extension_offset)
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
