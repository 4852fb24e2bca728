"""Before a fit: which parameters the model uses, and start values read from the data.

docs/theory/fitting.md#start-values. Three checks on the data and the model,
all at the float level (SI, turns):

* :func:`unused_parameters`: a parameter whose change leaves the model's
  extensions and torques bit-identical is not used by the model (``radius`` in
  ``marko2007``, ``end_loop_writhe`` with the end loop off); the default
  ``vary`` drops it.
* :func:`length_start` and :func:`length_excess`: the contour length from the
  extensions at the turns nearest zero (Marko-Siggia worm-like chain
  inverted), and the check that the extensions do not exceed the length.
* :func:`turns_offset_start`: the zero of the turns from every channel that
  locates it (torque zero crossing, hat symmetry), chosen robustly.
"""

from __future__ import annotations

import math

import numpy as np

from supercoil import display
from supercoil.dna.fitting.model import dna_si, guess_turns_center
from supercoil.exceptions import FitError, NoEquilibriumError, ValidityError

__all__ = ["TURNS_CHANNELS", "TURNS_WINDOW", "check_length", "drop_unused", "length_excess",
           "length_records", "length_start", "marko_siggia_relative_extension",
           "start_from_data", "turns_offset_start", "turns_runaway_messages",
           "unused_parameters"]

_KERNEL_ERRORS = (NoEquilibriumError, ValidityError, FloatingPointError, ZeroDivisionError)
_SAMPLE = 48  # points at which the use of a parameter is tested
_HELIX_PITCH = 3.57e-9  # m of B-DNA per helical turn (10.5 bp x 0.34 nm): turns per length


def _sample(force, dna):
    """A grid over supercoiling densities -0.05..0.05 at up to four of the data's forces.

    Not the data points: the question is whether the *model* uses a parameter
    (data that do not determine it are the Jacobian's business).
    """
    forces = np.unique(force)
    if len(forces) > 4:
        forces = forces[np.linspace(0, len(forces) - 1, 4).round().astype(int)]
    n_max = 0.05 * dna.length / _HELIX_PITCH
    turns = np.linspace(-n_max, n_max, _SAMPLE // len(forces))
    return np.tile(turns, len(forces)), np.repeat(forces, len(turns))


def _outputs(model, turns, force, dna, thermal, inter):
    pts = model.points(turns, force, dna, thermal, inter, None)
    return np.asarray(pts.extension, dtype=float), np.asarray(pts.torque, dtype=float)


def _perturbed(value, lower=-math.inf, upper=math.inf):
    for v in (value * 1.1, value * 0.9) if value != 0 else (0.1, -0.1):
        if lower < v < upper:
            return v
    return 0.5 * (lower + upper) if math.isfinite(upper - lower) else value + 1.0


def unused_parameters(names, force, dna, model, inter, thermal, xi_is_bending=True):
    """The ``names`` (DNA fields, model or interaction parameters) the model does not use.

    Each is changed by 10 % (within its declared range) on a grid of 48
    points (supercoiling densities -0.05 to 0.05 at up to four of the forces
    ``force``); a parameter is unused when the model's extensions and torques
    stay bit-identical. Returns ``[]`` when the model fails on the grid
    (nothing can be told).
    """
    turns, force = _sample(np.asarray(force, float), dna)
    try:
        z0, t0 = _outputs(model, turns, force, dna, thermal, inter)
    except _KERNEL_ERRORS:
        return []
    out = []
    for name in names:
        m, i, d = model, inter, dna
        if name in model.parameters:
            spec = model.parameters[name]
            m = model.replace(**{name: _perturbed(model.values[name], spec.lower, spec.upper)})
        elif inter is not None and name in inter.parameters:
            spec = inter.parameters[name]
            i = inter.replace(**{name: _perturbed(inter.values[name], spec.lower, spec.upper)})
        else:
            d = dna_si(dna, {name: _perturbed(getattr(dna, name), 0.0)}, xi_is_bending)
        try:
            z, t = _outputs(m, turns, force, d, thermal, i)
        except _KERNEL_ERRORS:
            continue
        if np.array_equal(z, z0, equal_nan=True) and np.array_equal(t, t0, equal_nan=True):
            out.append(name)
    return out


# ---- the turns offset -------------------------------------------------------------------
def _smooth(turns, y):
    """``(turns, running median of y)`` sorted by turns (window: 1/25 of the points, >= 5)."""
    order = np.argsort(turns, kind="stable")
    n, v = turns[order], y[order]
    k = max(5, len(n) // 25) | 1
    if len(n) < k:
        return n, v
    pad = k // 2
    padded = np.concatenate([np.full(pad, v[0]), v, np.full(pad, v[-1])])
    windows = np.lib.stride_tricks.sliding_window_view(padded, k)
    return n, np.median(windows, axis=1)


def _noise(y, smooth):
    """Robust noise level: 1.4826 x the median absolute deviation from the smooth curve."""
    return 1.4826 * float(np.median(np.abs(y - smooth))) if len(y) else 0.0


def _torque_zero(turns, torque):
    """Turns where the smoothed torque rises through zero (the steepest such crossing)."""
    n, s = _smooth(turns, torque)
    if len(n) < 6 or not (s.min() < 0 < s.max()):
        return None
    idx = np.flatnonzero((s[:-1] < 0) & (s[1:] >= 0))
    if not len(idx):
        return None
    width = max(1, len(n) // 20)
    rise = [s[min(i + width, len(s) - 1)] - s[max(i - width, 0)] for i in idx]
    i = int(idx[int(np.argmax(rise))])
    if s[i + 1] == s[i] or n[i + 1] == n[i]:
        return float(n[i])
    return float(n[i] - s[i] * (n[i + 1] - n[i]) / (s[i + 1] - s[i]))


def _hat_centre(turns, z):
    """Centre of the hat from the level crossings on both sides of its maximum.

    Only when the data straddle the maximum: the curve falls on both sides by
    more than 10 noise levels and 2 % of the maximum. The level is half the
    smaller fall; the centre is the midpoint of its crossings nearest the
    maximum (for a symmetric hat the centre at any level).
    """
    n, s = _smooth(turns, z)
    if len(n) < 10:
        return None
    noise = _noise(z[np.argsort(turns, kind="stable")], s)
    i = int(np.argmax(s))
    top = s[i]
    fall = min(top - s[: i + 1].min(), top - s[i:].min())
    if fall <= max(10 * noise, 0.02 * abs(top)):
        return None
    level = top - 0.5 * fall
    left = np.flatnonzero(s[: i + 1] < level)
    right = i + np.flatnonzero(s[i:] < level)
    a, b = left[-1], right[0]  # crossings between a, a + 1 and b - 1, b

    def cross(j, k):
        return float(n[j] + (level - s[j]) * (n[k] - n[j]) / (s[k] - s[j]))

    return 0.5 * (cross(a, a + 1) + cross(b - 1, b))


#: the channels that locate the zero of the turns, in the order they are trusted
TURNS_CHANNELS = ("torque zero crossing", "hat symmetry")

#: distance (turns) from every data channel beyond which a fitted turns offset is named in a
#: FitWarning: the channels locate the zero to a fraction of a turn (the torque zero
#: crossing to the point spacing, the hat centre to the symmetric pair of slope points), so
#: an offset that moves further fits a model's misfit, not the zero (a model without
#: melting fitted to both sides of measured curves ran 15 turns away). Not a bound: bounds
#: change the optimiser's path even where they are not reached.
TURNS_WINDOW = 3.0


def turns_runaway_messages(params, located):
    """FitWarning texts for fitted turns offsets more than :data:`TURNS_WINDOW` turns from
    every channel that located them (``located``: name -> {channel: value} of
    :func:`start_from_data`)."""
    out = []
    for name, found in located.items():
        p = params.get(name)
        if p is None or not p.vary or not found:
            continue
        near = min(abs(p.value - v) for v in found.values())
        if near > TURNS_WINDOW:
            where = ", ".join(f"{k}: {v:.3g}" for k, v in found.items())
            out.append(f"{name} = {p.value:.4g} turn is {near:.3g} turns from every channel "
                       f"of the data that locates the zero ({where}): the fit moves the "
                       "offset to absorb a misfit of the model, not to find the zero; try a "
                       "model that describes both sides, or hold it with fixed="
                       f"{{'{name}': ...}} or bounds={{'{name}': (lo, hi)}}")
    return out


def turns_offset_start(turns, z, force, torque=None):
    """Start value of the turns offset from every channel that locates zero.

    Channels (per force, then the median over the forces that give one):

    * ``"torque zero crossing"`` (with a torque channel): the turns where the
      smoothed torque rises through zero. Needs no symmetry, so it works on
      one-sided data (the negative side cut where DNA melts).
    * ``"hat symmetry"`` (when the data straddle the hat maximum: the curve
      falls on both sides): the midpoint of the two crossings of a level
      below the maximum, i.e. the hat maximum or, deeper, the symmetric pair
      of points on the two post-buckling slopes; refined to the centre of
      symmetry of the whole curves (:func:`guess_turns_center`) when that
      lies within 2 turns of it.

    The first channel in :data:`TURNS_CHANNELS` that gives a value is used;
    without any, ``"applied turns' zero (no channel locates it)"`` and 0.

    Returns
    -------
    (value, method, candidates) : float (turns), str, dict of channel -> value
    """
    turns, z, force = (np.asarray(a, dtype=float) for a in (turns, z, force))
    found = {}
    for name in TURNS_CHANNELS:
        if name.startswith("torque") and torque is None:
            continue
        vals = []
        for f in np.unique(force):
            sel = force == f
            v = (_torque_zero(turns[sel], np.asarray(torque, float)[sel])
                 if name.startswith("torque") else _hat_centre(turns[sel], z[sel]))
            if v is not None and np.isfinite(v):
                vals.append(v)
        if vals:
            found[name] = float(np.median(vals))
    if "hat symmetry" in found:
        # straddled: the centre of symmetry of the whole curves (the package's earlier guess,
        # more precise), unless it strays from the level crossings (2 turns)
        centre = guess_turns_center(turns, z, force)
        if abs(centre - found["hat symmetry"]) <= 2.0:
            found["hat symmetry"] = centre
    for name in TURNS_CHANNELS:
        if name in found:
            return found[name], name, found
    return 0.0, "applied turns' zero (no channel locates it)", found


# ---- the contour length -----------------------------------------------------------------
def marko_siggia_relative_extension(force, persistence, kT):
    """z/L of the Marko-Siggia worm-like chain at ``force`` (N; persistence m, kT J).

    Inverts ``F P / kT = z/L + 1 / (4 (1 - z/L)^2) - 1/4`` (Marko & Siggia,
    Macromolecules 28, 8759 (1995), eq. 7) by bisection (monotonic in z/L).
    """
    target = np.atleast_1d(np.asarray(force, dtype=float)) * persistence / kT
    lo, hi = np.zeros_like(target), np.full_like(target, 1 - 1e-12)
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        g = mid + 0.25 / (1 - mid) ** 2 - 0.25
        lo, hi = np.where(g < target, mid, lo), np.where(g < target, hi, mid)
    return 0.5 * (lo + hi)


def length_start(turns, z, force, n0, dna):
    """Contour length (m) from the extensions at the turns nearest zero, per force.

    At each force the median extension of the points within 1 turn of the
    zero (``turns - n0``; at least the 5 nearest points) is divided by the
    Marko-Siggia ``z/L`` at that force (persistence ``dna.wlc_persistence``);
    the median over the forces. The extension offset is taken as 0 here (the
    fit then starts it from the residuals). None without data.
    """
    turns, z, force = (np.asarray(a, dtype=float) for a in (turns, z, force))
    est = []
    for f in np.unique(force):
        sel = np.flatnonzero(force == f)
        dist = np.abs(turns[sel] - n0)
        near = sel[dist <= 1.0]
        if len(near) < 5:
            near = sel[np.argsort(dist)[:5]]
        top = float(np.median(z[near]))
        rel = float(marko_siggia_relative_extension(f, dna.wlc_persistence, dna.kT)[0])
        if top > 0 and rel > 0:
            est.append(top / rel)
    return float(np.median(est)) if est else None


#: extensions may exceed the contour length by this fraction: noise (extension offsets
#: held at 0), or noise and a bead-height offset (extension offsets fitted)
LENGTH_TOLERANCE = {False: 0.02, True: 0.2}


def length_excess(z, length, offset_fitted=False):
    """A message if the extensions exceed the contour length (both m), else None.

    Robust to noise and an offset: the 95th percentile of the extensions must
    exceed ``L (1 + LENGTH_TOLERANCE[offset_fitted])`` (2 %, or 20 % when the
    extension offsets are fitted, which may place the data above L); the
    message names the largest.
    """
    if not len(z):
        return None
    zmax, z95 = float(np.max(z)), float(np.percentile(z, 95))
    if not z95 > length * (1 + LENGTH_TOLERANCE[bool(offset_fitted)]):
        return None
    return (f"the extensions of the data reach {display.text(zmax, 'extension', '.5g')} "
            f"(95th percentile {display.text(z95, 'extension', '.5g')}), beyond the contour "
            f"length L = {display.text(length, 'length', '.5g')} of "
            "the DNA given: no worm-like chain reaches "
            "beyond its contour length. Set your molecule's length: dna.replace(length=...) "
            "(the number of base pairs x 0.34 nm), or on the command line --start "
            "length=<L>nm with --vary length (or --fix length=<L>nm); "
            "docs/theory/fitting.md#start-values")


# ---- used by the fit (supercoil.dna.fitting.fit) ----------------------------------------
def _offset_fitted(params):
    return any(p.kind == "extension_offset" and p.vary for p in params.values())


def check_length(params, si, rot):
    """FitError when the extensions exceed a fixed contour length (a varied one warns)."""
    p = params.get("length")
    if rot is None or (p is not None and p.vary):
        return
    msg = length_excess(rot.extension, p.value if p is not None else si.length,
                        _offset_fitted(params))
    if msg is not None:
        raise FitError(msg + "; or vary the length")


def length_records(spec):
    """A FitWarning record when the extensions exceed the length given (varied length)."""
    p = spec.params.get("length")
    if p is None or not p.vary:
        return []
    msg = length_excess(spec.data.extension, spec.dna.length, _offset_fitted(spec.params))
    return [] if msg is None else [("FitWarning", msg + "; the fit starts the length from the "
                                    "data")]


def drop_unused(params, optional, rot, si, model, inter, thermal, xi_is_bending):
    """Hold the ``optional`` free parameters the model does not use; the notes saying so."""
    names = [n for n in dict.fromkeys(optional) if n in params and params[n].vary]
    if not names:
        return []
    unused = unused_parameters(names, rot.force, si, model, inter, thermal, xi_is_bending)
    if len(unused) == len(params.free):
        return []  # nothing left to fit: let the Jacobian say it
    for name in unused:
        params[name].vary = False
    return [f"{name} not varied: the model {model.name!r} does not use it (its extensions "
            "and torques do not change with it), so the data cannot determine it; give it "
            "in vary explicitly to fit it anyway" for name in unused]


def _turns_starts(data, params, groups, located):
    """Start the turns offsets not given; ``(turns offset per molecule, notes)``; the
    channels' values go into ``located`` (name -> {channel: value})."""
    notes, n0 = [], np.zeros(data.n_molecules)
    for p in params.values():
        if p.kind != "turns_offset" or p.molecule is None:
            continue
        if p.vary and not p.given:
            g = groups[p.molecule]
            tq = None if data.torque is None else data.torque[g]
            p.value, how, found = turns_offset_start(data.turns[g], data.extension[g],
                                                     data.force[g], tq)
            located[p.name] = found
            others = ", ".join(f"{k}: {v:.3g}" for k, v in found.items() if k != how)
            notes.append(f"{p.name} starts at {p.value:.4g} turn from the {how}"
                         + (f" (other channels: {others})" if others else ""))
        n0[p.molecule] = p.value
    return n0, notes


def start_from_data(data, params, dna, located=None):
    """Start values not given, from the data: the turns offsets (:func:`turns_offset_start`),
    then a varied length (:func:`length_start`). Returns the notes saying what was used;
    the turns channels' values go into the dict ``located`` if given (for
    :func:`turns_runaway_messages` after the fit)."""
    groups = data.groups()
    n0, notes = _turns_starts(data, params, groups, {} if located is None else located)
    length = params.get("length")
    if length is None or not length.vary or length.given:
        return notes
    est = [length_start(data.turns[g], data.extension[g], data.force[g], n0[i], dna)
           for i, g in enumerate(groups)]
    est = [e for e in est if e is not None and np.isfinite(e) and e > 0]
    if est:
        length.value = float(np.median(est))
        notes.append(f"length starts at {display.text(length.value, 'length', '.5g')}, read "
                     "from the data "
                     "(Marko-Siggia worm-like chain inverted at the turns nearest zero, "
                     "median over the forces); give start={'length': ...} to override")
    return notes
