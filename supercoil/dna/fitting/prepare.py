"""From the keyword arguments of a fit to its :class:`FitSpec` (:func:`prepare`).

The names of ``vary``, ``fixed``, ``bounds`` and ``start`` become
:class:`FitParameters` (:func:`build_parameters`).

Names a fit accepts: the DNA fields (:data:`DNA_FIELDS`; ``temperature`` only
in ``fixed``), the parameters the DNA model and the interaction declare
(``model.parameters``, ``interaction.parameters``), and the offsets
``turns_offset`` / ``extension_offset`` (all molecules) or
``turns_offset[<molecule>]`` (one molecule), and the calibration scales
(:data:`~supercoil.dna.fitting.fit_parameters.CALIBRATION`: ``torque_scale``,
``force_scale``, ``force_spread``; held at their off values 1, 1, 0 unless varied or
fixed).
"""

from __future__ import annotations

import contextlib
import math
import re

import numpy as np

from supercoil import display
from supercoil._checks import check_flag, named
from supercoil.dna.fitting import start as _start
from supercoil.dna.fitting.data import RotationData
from supercoil.dna.fitting.fit_parameters import (
    CALIBRATION,
    CALIBRATION_OFF,
    DNA_FIELDS,
    PLAUSIBLE,
    FitParameter,
    FitParameters,
    calibration_parameter,
)
from supercoil.dna.fitting.model import dna_si
from supercoil.dna.fitting.options import DEFAULT_VARY, DEFAULTS, FitOptions, FitSpec
from supercoil.dna.fitting.spread import check_force_spread
from supercoil.dna.fitting.weights import check_sigma_scale, checked_sigma
from supercoil.dna.interactions import DEFAULT_INTERACTION, get_interaction
from supercoil.dna.models import get_model
from supercoil.dna.validity import check_dna, check_interaction
from supercoil.exceptions import FitError, ModelError
from supercoil.units import U, as_turns, magnitude

__all__ = ["Z0_SCALE", "build_parameters", "extension_offset_mode", "plain", "prepare",
           "resolve_model"]

Z0_SCALE = 1e-8  # scaled extension-offset variable: units of 10 nm
_NAME = re.compile(r"^(?P<base>turns_offset|extension_offset)(?:\[(?P<mol>.*)\])?$")
_OFFSETS = ("turns_offset", "extension_offset")


def plain(value):
    """A value for a message: ``-1 nm`` or ``-1.0``, never ``np.float64(-1.0)`` / ``<Quantity>``."""
    mag = getattr(value, "magnitude", value)
    if isinstance(mag, np.generic):
        mag = mag.item()
    units = getattr(value, "units", None)
    if units is None:
        return str(mag)
    unit_text = f"{units:~P}"
    return f"{mag} {unit_text}" if unit_text else str(mag)


class _Names:
    """Resolves a parameter name to (owner, base name, molecule index or None)."""

    def __init__(self, labels, model, interaction):
        self.labels = list(labels)
        self.model = model
        self.interaction = interaction

    def allowed(self):
        return [*DNA_FIELDS, *self.model.parameters, *self.interaction.parameters,
                *CALIBRATION]

    def kind(self, name):
        if name in DNA_FIELDS or name == "temperature":
            return "dna", name, None
        if name in self.model.parameters:
            return "model", name, None
        if name in self.interaction.parameters:
            return "interaction", name, None
        if name in CALIBRATION:
            return "calibration", name, None
        m = _NAME.match(name)
        if not m:
            raise FitError(f"unknown parameter {name!r}; fit parameters are {self.allowed()}, "
                           "'turns_offset', 'extension_offset' (or 'turns_offset[<molecule>]', "
                           "...)")
        mol = m.group("mol")
        if mol is None:
            return "offset", m.group("base"), None
        if mol not in self.labels:
            raise FitError(f"parameter {name!r}: no molecule {mol!r} in the data "
                           f"(have {self.labels})")
        return "offset", m.group("base"), self.labels.index(mol)

    def spec(self, owner, base):
        return (self.model if owner == "model" else self.interaction).parameters[base]

    def to_si(self, name, value):
        owner, base, _ = self.kind(name)
        try:
            if base == "turns_offset":
                return float(as_turns(value, name))
            if base == "temperature":
                return float(magnitude(value, U.K, name))
            if owner == "calibration":
                return float(magnitude(value, U.dimensionless, name))
            if owner in ("model", "interaction"):
                spec = self.spec(owner, base)
                if hasattr(value, "_units"):
                    return float(magnitude(value, spec.si_unit, name))
                return float(value)
            return float(magnitude(value, U.m, name))
        except (TypeError, ValueError) as exc:
            raise FitError(f"parameter {name!r}: {exc}") from None


def _global_parameter(names, owner, base, value, vary):
    if owner == "calibration":
        return calibration_parameter(base, value, vary)
    if owner == "dna":
        lo, hi, src = PLAUSIBLE[base]
        return FitParameter(base, value, "nm", vary=vary, min=0.0, kind=base, owner="dna",
                            plausible=(lo, hi), plausible_source=src, scale=value)
    spec = names.spec(owner, base)
    scale = abs(value) if value != 0 else (max(abs(spec.lower), abs(spec.upper), 1.0)
                                           if math.isfinite(spec.upper - spec.lower) else 1.0)
    return FitParameter(base, value, spec.unit, vary=vary, min=spec.lower, max=spec.upper,
                        kind=base, owner=owner, plausible=(spec.lower, spec.upper),
                        plausible_source=spec.source or f"declared range of {owner} "
                        f"parameter {base}", scale=scale)


@contextlib.contextmanager
def _about(argument):
    """A FitError raised inside names ``argument`` unless it names an argument already.

    The names of ``vary``, ``fixed``, ``start`` and ``bounds`` are resolved by the same
    helpers (unknown name, wrong unit); the error says which argument held the name.
    """
    try:
        yield
    except FitError as exc:
        if exc.argument is None:
            exc.argument = argument
        raise


def _check_vary(vary, names):
    if isinstance(vary, str):
        vary = [vary]
    vary = list(dict.fromkeys(vary or []))
    allowed = names.allowed()
    for name in vary:
        if name not in allowed:
            raise FitError(f"cannot vary {name!r}: the physical fit parameters are {allowed} "
                           "(the offsets are free unless switched off with "
                           "fit_turns_offset=False and fit_extension_offset=False)",
                           argument="vary")
    return vary


def _apply_fixed(fixed, names, vary, values, n0, z0):
    """Fixed values into ``values`` (globals) and the offset tables; returns the fixed mask."""
    for name, value in fixed.items():
        owner, base, idx = names.kind(name)
        v = names.to_si(name, value)
        if base in vary:
            raise FitError(f"parameter {name!r} is both varied and fixed",
                           argument=("vary", "fixed"))
        if owner == "dna":
            if not (np.isfinite(v) and v > 0):
                raise FitError(f"the fixed value of {name} must be finite and positive, got "
                               f"{plain(value)}", argument="fixed")
            values[("dna", base)] = v
        elif owner in ("model", "interaction", "calibration"):
            if base == "force_spread":
                check_force_spread(v)
            elif owner == "calibration" and not (np.isfinite(v) and v > 0):
                raise FitError(f"the fixed value of {name} must be finite and positive, got "
                               f"{plain(value)}", argument="fixed")
            values[(owner, base)] = v
        else:
            table = n0 if base == "turns_offset" else z0
            for i in range(len(names.labels)) if idx is None else [idx]:
                table[i] = (v, True, False)


def _apply_start(start, names, vary, values, n0, z0):
    for name, value in start.items():
        owner, base, idx = names.kind(name)
        v = names.to_si(name, value)
        if owner != "offset":
            if base not in vary:
                raise FitError(f"a start value is given for {name!r}, which is not varied",
                               argument="start")
            if base == "force_spread":
                check_force_spread(v)
            values[(owner, base)] = v
            continue
        table = n0 if base == "turns_offset" else z0
        for i in range(len(names.labels)) if idx is None else [idx]:
            table[i] = (v, True, table[i][2])


def _apply_bounds(bounds, names, params):
    for name, pair in bounds.items():
        _, base, idx = names.kind(name)
        try:
            b_lo, b_hi = pair
        except (TypeError, ValueError):
            raise FitError(f"the bounds of {name!r} must be a pair (lower, upper)",
                           argument="bounds") from None
        lo = -np.inf if b_lo is None else names.to_si(name, b_lo)
        hi = np.inf if b_hi is None else names.to_si(name, b_hi)
        if not lo < hi:
            raise FitError(f"the bounds of {name!r}: lower bound {plain(pair[0])} is not "
                           f"below {plain(pair[1])}", argument="bounds")
        hits = [p for p in params.free_params()
                if p.kind == base and (idx is None or p.molecule == idx)]
        if not hits:
            raise FitError(f"bounds are given for {name!r}, which is not a free parameter",
                           argument="bounds")
        for p in hits:
            p.min, p.max = lo, hi


def _add_offsets(params, data, n0, z0, per_force):
    """The per-molecule offsets (or per-force extension offsets) from the tables."""
    for i, lab in enumerate(data.labels):
        suffix = f"[{lab}]" if data.has_molecule else ""
        for base, table, unit, scale in (("turns_offset", n0, "turn", 1.0),
                                         ("extension_offset", z0, "nm", Z0_SCALE)):
            v, given, free = table[i]
            lo, hi, src = PLAUSIBLE[base]
            if base == "extension_offset" and per_force:
                _add_per_force_offsets(params, data, i, lab, (v, given, free), src)
                continue
            params.add(FitParameter(f"{base}{suffix}", v, unit, vary=free,
                                    shared="per-molecule", molecule=i, kind=base,
                                    owner="offset", plausible=(lo, hi), plausible_source=src,
                                    given=given, scale=scale))


def _add_per_force_offsets(params, data, i, label, entry, source):
    """One extension offset per force of molecule ``i`` (``extension_offset[0.3 pN]``)."""
    v, given, free = entry
    for f in np.unique(data.force[data.mol_index == i]):
        force = display.text(f, "force")
        inner = force if not data.has_molecule else f"{label}, {force}"
        params.add(FitParameter(f"extension_offset[{inner}]", v, "nm", vary=free,
                                shared="per-force", molecule=i, force=float(f),
                                kind="extension_offset", owner="offset",
                                plausible=(-np.inf, np.inf), plausible_source=source,
                                given=given, scale=Z0_SCALE))


def _fixed_calibration(params, vary, values, data):
    """A fixed calibration parameter other than its off value as a fixed parameter;
    FitError for a torque scale without torque data."""
    for base in CALIBRATION:
        if base not in vary and values[("calibration", base)] != CALIBRATION_OFF[base]:
            params.add(calibration_parameter(base, values[("calibration", base)], vary=False))
    if "torque_scale" in params and not data.has_torque:
        raise FitError("torque_scale scales the torque channel, but the data have no "
                       "'torque' column")


def build_parameters(data, dna, model, interaction, vary, fixed=None, bounds=None, start=None,
                     fit_turns_offset=True, fit_extension_offset=True,
                     extension_offset_per_force=False):
    """The :class:`FitParameters` of a fit and the model/interaction with fixed values applied.

    ``extension_offset_per_force``: one extension offset per (molecule, force)
    curve instead of one per molecule (:mod:`supercoil.dna.fitting.offsets`).

    Returns ``(params, dna SI, model, interaction)``.
    """
    names = _Names(data.labels, model, interaction)
    with _about("vary"):
        vary = _check_vary(vary, names)
    si = dna.si
    values = {("dna", k): getattr(si, k) for k in (*DNA_FIELDS, "temperature")}
    values.update({("model", k): v for k, v in model.values.items()})
    values.update({("interaction", k): v for k, v in interaction.values.items()})
    values.update({("calibration", k): CALIBRATION_OFF[k] for k in CALIBRATION})
    n_mol = len(data.labels)
    # per molecule: (value, given, free)
    n0 = [(0.0, False, bool(fit_turns_offset))] * n_mol
    z0 = [(0.0, False, bool(fit_extension_offset))] * n_mol
    with _about("fixed"):
        _apply_fixed(dict(fixed or {}), names, vary, values, n0, z0)
    with _about("start"):
        _apply_start(dict(start or {}), names, vary, values, n0, z0)
    si = dna_si(si, {k: values[("dna", k)] for k in (*DNA_FIELDS, "temperature")},
                dna.wlc_persistence is None)
    model = model.replace(**{k: values[("model", k)] for k in model.parameters}) \
        if model.parameters else model
    interaction = interaction.replace(**{k: values[("interaction", k)]
                                         for k in interaction.parameters}) \
        if interaction.parameters else interaction
    params = FitParameters()
    owners = {b: o for o, b in values}
    for base in vary:
        params.add(_global_parameter(names, owners[base], base, values[(owners[base], base)],
                                     True))
    _fixed_calibration(params, vary, values, data)
    _add_offsets(params, data, n0, z0, extension_offset_per_force)
    if "length" in params and "length" not in dict(start or {}):
        params["length"].given = False  # a varied length starts from the data
    with _about("bounds"):
        _apply_bounds(dict(bounds or {}), names, params)
    n_free = len(params.free)
    if n_free == 0:
        raise FitError("nothing to fit: no parameter is varied and both offsets are switched "
                       "off", argument="vary")
    if data.n - n_free <= 0:
        raise FitError(f"{data.n} data points cannot determine {n_free} free parameters")
    return params, si, model, interaction


def strip_molecule_keys(d, argument):
    """``d`` unchanged, or FitError naming ``argument`` for a per-molecule key.

    fit_many fits each molecule alone, so a key such as ``'turns_offset[m1]'`` has no
    meaning there.
    """
    if d is None:
        return None
    for k in d:
        m = _NAME.match(k)
        if m and m.group("mol") is not None:
            raise FitError(f"each molecule is fitted alone here, so per-molecule names do "
                           f"not apply: give {m.group('base')!r}, not {k!r}",
                           argument=argument)
    return dict(d)


def resolve_model(model, interaction):
    """``(model, interaction)`` instances; ModelError for an interaction the model cannot take."""
    m = get_model(model)
    if interaction is None or interaction == DEFAULT_INTERACTION:
        return m, get_interaction(DEFAULT_INTERACTION)
    if not m.uses_interaction:
        raise ModelError(f"model {m.name!r} has no plectoneme helix state, so it takes no "
                         f"interaction (got interaction={interaction!r})")
    return m, get_interaction(interaction)


def prepare(data, dna, options=None, *, params=None, rotation=None, optional=None,
            **keywords):
    """Validate every argument and convert to SI: the :class:`FitSpec` of one fit.

    ``options`` (a :class:`FitOptions`, default :data:`DEFAULTS`) holds the
    keywords of :func:`~supercoil.fit_hat_curves`; ``keywords`` (the same
    names) override its fields. ``params``: a full :class:`FitParameters`
    set (excludes ``vary``, ``fixed``, ``bounds`` and ``start``).
    ``rotation``: the data already converted (:class:`RotationData`; then
    ``data`` is not read). ``optional``: varied names that are dropped (held
    at their value, with a note) when the model does not use them; default:
    the names of :data:`DEFAULT_VARY` when ``vary`` is the default.
    """
    if options is None:
        options = DEFAULTS
    elif not isinstance(options, FitOptions):
        raise TypeError(f"options must be a FitOptions, got {type(options).__name__} (give "
                        "the fit's keywords by name)")
    o = options.replace(**keywords) if keywords else options
    thermal = check_flag(o.thermal, "thermal")
    fit_turns_offset = check_flag(o.fit_turns_offset, "fit_turns_offset")
    fit_extension_offset, z0_per_force = extension_offset_mode(o.fit_extension_offset)
    check_dna(dna)
    m, inter = resolve_model(o.model, o.interaction)
    if m.uses_interaction:
        check_interaction(inter, dna.si)  # with the hard-core scale A/r0
    else:
        inter.check(dna.si)
    own_params = params is not None
    if rotation is None:
        rotation = RotationData.from_frame(data)
    rot = (rotation if o.sigma is None
           else rotation.with_sigma(checked_sigma(o.sigma, rotation)))
    check_sigma_scale(rot, dna.si.length)
    vary = o.vary
    if params is None:
        params, si, m, inter = build_parameters(rot, dna, m, inter, vary, o.fixed, o.bounds,
                                                o.start, fit_turns_offset,
                                                fit_extension_offset, z0_per_force)
    else:
        if not isinstance(params, FitParameters):
            raise TypeError(f"params must be a FitParameters, got {type(params).__name__}")
        if o.fixed or o.bounds or o.start or vary is not DEFAULT_VARY:
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
    return FitSpec(rot, params, si, dna.wlc_persistence is None, m, inter, thermal,
                   o.max_nfev, float(o.tol), vary, notes)


def extension_offset_mode(value):
    """``(fitted, per force)`` from ``fit_extension_offset`` (bool, "per-molecule", "per-force")."""
    if isinstance(value, str):
        if value not in ("per-molecule", "per-force"):
            raise named(TypeError(f"fit_extension_offset must be True or False, got "
                                  f"{value!r} (or 'per-molecule', the default, or "
                                  "'per-force')"), "fit_extension_offset")
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
