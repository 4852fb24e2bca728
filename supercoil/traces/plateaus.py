"""From a trace table to rotation curves: plateaus, settling, drift, averages, errors.

See docs/theory/recordings.md for the method:

1. **Plateaus** (:func:`find_plateaus`, recordings.md#plateaus): maximal runs of
   frames over which the magnet rotation and height stay within a tolerance of
   their first value; runs shorter than ``settle`` plus ``min_frames`` frames
   are moves and are skipped.
2. **Settling** (recordings.md#settling): the first ``settle`` seconds of every
   plateau are dropped (the bead relaxes to its new height); the rest is checked
   for a remaining trend (first half against second half).
3. **Drift** (recordings.md#drift): the mean z of the reference beads, minus its
   mean over the recording, is subtracted frame by frame; a surface offset
   (per bead or common) is subtracted if given.
4. **Averages and errors** (recordings.md#error): the mean of every plateau and
   its standard error by blocking (:func:`supercoil.traces.errors.blocking_error`).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd

from ..dna.tweezers import check_tweezers_frame
from ..exceptions import DataError, DataWarning
from ..tables import make_table, provenance
from ..units import U, as_turns, magnitude, ureg
from .errors import blocking_error, error_from_inefficiency, pooled_inefficiency
from .trace import check_trace

__all__ = ["find_plateaus", "force_from_height", "rotation_curves"]

#: a plateau whose halves differ by more than this many standard errors has not settled
#: (false alarms on stationary AR(1) plateaus: below 5e-5, see _plateau_mean)
SETTLED_SIGMAS = 8.0


def _frames(trace):
    """Per-frame motor state (time-sorted) and the (frames x beads) z matrix."""
    first = trace.drop_duplicates("time").sort_values("time")
    cols = ["time", "turns", "height"] + (["force"] if "force" in trace.columns else [])
    frames = first[cols].reset_index(drop=True)
    z = trace.pivot_table(index="time", columns="bead", values="z", aggfunc="first",
                          sort=True)
    labels = list(pd.unique(trace["bead"]))  # the recording's order, not string order
    return frames, z.reindex(index=frames["time"].to_numpy(), columns=labels)


def _runs(turns, height, tol_n, tol_h):
    """Start and stop indices of maximal runs within the tolerances of their first frame."""
    starts, stops = [], []
    s = 0
    n0, h0 = turns[0], height[0]
    for i in range(1, turns.size):
        if abs(turns[i] - n0) > tol_n or abs(height[i] - h0) > tol_h:
            starts.append(s)
            stops.append(i)
            s, n0, h0 = i, turns[i], height[i]
    starts.append(s)
    stops.append(turns.size)
    return np.array(starts), np.array(stops)


def find_plateaus(trace, settle=1.0 * ureg.s, *, turns_tolerance=1e-3,
                  height_tolerance=1e-4 * ureg.mm, min_frames=16, guard=0.05 * ureg.s,
                  source=None):
    """Plateaus of constant magnet rotation and height in a trace.

    Parameters
    ----------
    trace : pandas.DataFrame
        A trace table (:mod:`supercoil.traces.trace`).
    settle : Quantity [time]
        Settling time dropped at the start of every plateau.
    turns_tolerance : float or Quantity (turns, or an angle)
        Largest change of the rotation within a plateau.
    height_tolerance : Quantity [length]
        Largest change of the magnet height within a plateau.
    min_frames : int
        Frames a plateau must keep after ``settle`` (at least 4).
    guard : Quantity [time]
        Frames this close to the end of a run are dropped too: a motor log
        that is sampled (MagScope's Zaber managers poll every 50 ms) reports a
        move up to one sampling interval late (default 0.05 s).

    Returns
    -------
    pandas.DataFrame
        One row per plateau in time order: ``plateau`` (index), ``start``,
        ``used_from``, ``used_to``, ``end`` [s] (first frame, first and last
        frame kept, last frame), ``turns``, ``height`` [mm], ``frames``,
        ``frames_used``, and ``force`` [pN] (mean) if the trace has a force
        column. ``attrs["moves"]``: the number of shorter runs skipped.

    Raises
    ------
    DataError
        No plateau is long enough: the rotation or the height never settles
        (names the longest constant stretch and what was needed).
    """
    source = source or trace.attrs.get("provenance", {}).get("source", "trace")
    check_trace(trace, source)
    t_settle = float(magnitude(settle, U.s, "settle"))
    t_guard = float(magnitude(guard, U.s, "guard"))
    tol_n = float(as_turns(turns_tolerance, "turns_tolerance"))
    tol_h = float(magnitude(height_tolerance, U.mm, "height_tolerance"))
    min_frames = check_min_frames(min_frames)
    if not (t_settle >= 0 and t_guard >= 0 and tol_n >= 0 and tol_h >= 0):
        raise ValueError("settle and the tolerances must be >= 0, got "
                         f"settle={settle}, turns_tolerance={turns_tolerance}, "
                         f"height_tolerance={height_tolerance}, min_frames={min_frames}")
    frames, _ = _frames(trace)
    rows, moves, longest = _scan(frames, t_settle, t_guard, tol_n, tol_h, int(min_frames))
    t = frames["time"].to_numpy()
    if not rows:
        dur, a = longest
        raise DataError(
            f"{source}: the magnet never settles: no stretch of constant rotation (within "
            f"{tol_n:g} turn) and height (within {tol_h:g} mm) keeps {min_frames} frames after "
            f"settle={t_settle:g} s; the longest lasts {dur:.3g} s (from t = {t[a]:.4g} s, "
            f"{frames['turns'].iloc[a]:g} turns)")
    table = pd.DataFrame(rows)
    table.insert(0, "plateau", np.arange(len(table)))
    out = make_table({c: table[c].to_numpy() for c in table.columns},
                     {c: _PLATEAU_UNITS[c] for c in table.columns},
                     provenance(source=str(source), settle=f"{t_settle:g} s",
                                guard=f"{t_guard:g} s", turns_tolerance=tol_n,
                                height_tolerance=f"{tol_h:g} mm",
                                min_frames=int(min_frames)))
    out.attrs["moves"] = moves
    return out


def check_min_frames(min_frames):
    """``min_frames`` as an int >= 4; TypeError/ValueError naming it otherwise."""
    if isinstance(min_frames, bool) or not isinstance(min_frames, int | np.integer | float
                                                      | np.floating):
        raise TypeError(f"min_frames must be a whole number of frames (>= 4), got "
                        f"{type(min_frames).__name__} {min_frames!r}")
    if not (np.isfinite(min_frames) and float(min_frames).is_integer() and min_frames >= 4):
        raise ValueError(f"min_frames must be a whole number of frames >= 4, got {min_frames!r}")
    return int(min_frames)


_PLATEAU_UNITS = {"plateau": "", "start": "s", "used_from": "s", "used_to": "s", "end": "s",
                  "turns": "", "height": "mm", "frames": "", "frames_used": "", "first": "",
                  "stop": "", "force": "pN"}


def _scan(frames, t_settle, t_guard, tol_n, tol_h, min_frames):
    """Plateau rows, number of skipped runs (moves) and the longest run (duration, start)."""
    t = frames["time"].to_numpy()
    starts, stops = _runs(frames["turns"].to_numpy(), frames["height"].to_numpy(), tol_n, tol_h)
    rows, moves, longest = [], 0, (0.0, 0)
    for a, b in zip(starts, stops, strict=True):
        used = np.flatnonzero((t[a:b] >= t[a] + t_settle) & (t[a:b] <= t[b - 1] - t_guard)) + a
        if t[b - 1] - t[a] > longest[0]:
            longest = (t[b - 1] - t[a], a)
        if used.size < min_frames:
            moves += 1
            continue
        row = {"start": t[a], "used_from": t[used[0]], "used_to": t[used[-1]], "end": t[b - 1],
               "turns": float(frames["turns"].iloc[used].mean()),
               "height": float(frames["height"].iloc[used].mean()),
               "frames": int(b - a), "frames_used": int(used.size),
               "first": int(used[0]), "stop": int(b)}
        if "force" in frames.columns:
            row["force"] = float(frames["force"].iloc[used].mean())
        rows.append(row)
    return rows, moves, longest


def force_from_height(calibration, height_mm, source="calibration"):
    """Force [pN] at magnet heights [mm] from a user calibration.

    ``calibration`` is a callable (Quantity [length] -> Quantity [force]), a
    table with ``height`` and ``force`` columns and ``attrs["units"]``, or a
    pair ``(heights, forces)`` of quantities; tables are interpolated with a
    monotone cubic (:class:`scipy.interpolate.PchipInterpolator`) and never
    extrapolated (DataError outside the calibrated heights).
    """
    from scipy.interpolate import PchipInterpolator

    h = np.asarray(height_mm, dtype=float)
    if callable(calibration):
        f = calibration(ureg.Quantity(h, "mm"))
        return np.asarray(magnitude(f, U.pN, "calibration(height)"), dtype=float)
    if isinstance(calibration, pd.DataFrame):
        units = calibration.attrs.get("units", {})
        for col in ("height", "force"):
            if col not in calibration.columns or col not in units:
                raise DataError(f"{source}: a force calibration table needs columns 'height' "
                                f"and 'force' with units; got {list(calibration.columns)}")
        hh = ureg.Quantity(calibration["height"].to_numpy(float), units["height"] or "mm")
        ff = ureg.Quantity(calibration["force"].to_numpy(float), units["force"] or "pN")
    else:
        hh, ff = calibration
    hh = np.asarray(magnitude(hh, U.mm, "calibration heights"), dtype=float)
    ff = np.asarray(magnitude(ff, U.pN, "calibration forces"), dtype=float)
    order = np.argsort(hh)
    hh, ff = hh[order], ff[order]
    if hh.size < 2 or np.any(np.diff(hh) <= 0) or np.any(ff <= 0):
        raise DataError(f"{source}: the calibration needs at least 2 distinct heights and "
                        "positive forces")
    out = h < hh[0] - 1e-12
    out |= h > hh[-1] + 1e-12
    if out.any():
        bad = float(h[np.flatnonzero(out)[0]])
        raise DataError(f"{source}: magnet height {bad:g} mm is outside the calibrated "
                        f"range {hh[0]:g} to {hh[-1]:g} mm (no extrapolation)")
    return PchipInterpolator(hh, ff)(np.clip(h, hh[0], hh[-1]))


def _reference_signal(z, refs, source):
    """Mean z of the reference beads minus its recording mean (nm, per frame)."""
    if not refs:
        return np.zeros(len(z))
    missing = [r for r in refs if r not in z.columns]
    if missing:
        raise DataError(f"{source}: reference bead(s) {missing} not in the trace "
                        f"(beads: {list(z.columns)})")
    r = z[refs].mean(axis=1, skipna=True).to_numpy()
    return r - np.nanmean(r)


def _surface(surface, bead):
    if surface is None:
        return 0.0
    if isinstance(surface, dict):
        if bead not in surface:
            raise DataError(f"surface offsets given for {sorted(surface)}, not for bead {bead!r}")
        return float(magnitude(surface[bead], U.nm, f"surface[{bead!r}]"))
    return float(magnitude(surface, U.nm, "surface"))


def _plateau_mean(values, bead, p, source):
    """Blocking mean/error of one plateau, with the settled check (halves)."""
    res = blocking_error(values)
    if res.error <= 0:
        raise DataError(f"{source}: bead {bead!r}, plateau {int(p.plateau)} "
                        f"(t = {p.used_from:.4g} to {p.used_to:.4g} s): z is constant; expected "
                        "a fluctuating tracked bead")
    # the halves' mean difference against its error from the quadratically detrended frames:
    # naive errors of the halves times the blocking inefficiency of the residual (a trend must
    # not inflate its own yardstick). On stationary AR(1) plateaus of 240 frames none of 20000
    # exceed 8; a 100 nm step relaxing with tau = 3 s (1 s dropped) is flagged in 99 %.
    half = values.size // 2
    i = np.arange(values.size)
    resid = values - np.polyval(np.polyfit(i, values, 2), i)
    g = blocking_error(resid).inefficiency
    diff = abs(np.mean(values[:half]) - np.mean(values[half:]))
    err = np.sqrt(g) * np.hypot(np.std(resid[:half], ddof=1) / np.sqrt(half),
                                np.std(resid[half:], ddof=1) / np.sqrt(values.size - half))
    if diff > SETTLED_SIGMAS * err:
        raise DataError(
            f"{source}: bead {bead!r}, plateau {int(p.plateau)} ({p.turns:g} turns, "
            f"{p.height:g} mm, kept t = {p.used_from:.4g} to {p.used_to:.4g} s) has not "
            f"settled: the first and second half of the kept frames differ by {diff:.3g} nm "
            f"= {diff / err:.1f} standard errors (limit {SETTLED_SIGMAS:g}); increase settle, "
            "or check_settled=False")
    return res


def rotation_curves(trace, settle=1.0 * ureg.s, reference=None, *, surface=None,
                    calibration=None, molecules=None, turns_tolerance=1e-3,
                    height_tolerance=1e-4 * ureg.mm, min_frames=16, guard=0.05 * ureg.s,
                    check_settled=True, errors="pooled"):
    """Rotation curves (one point per bead and plateau) from a recording's trace.

    Parameters
    ----------
    trace : pandas.DataFrame
        From :func:`~supercoil.traces.read_magscope` or
        :func:`~supercoil.traces.read_calisto`.
    settle : Quantity [time]
        Settling time dropped after every magnet move (default 1 s).
    reference : str or sequence of str, optional
        Reference beads whose mean z (minus its recording mean) is subtracted
        frame by frame (drift). Default: ``trace.attrs["reference_beads"]``;
        ``[]`` for no drift correction.
    surface : Quantity [length] or dict of bead -> Quantity, optional
        Tracker z of the surface, subtracted from the extension (one value or
        one per bead). Default: none (the fits' extension offset absorbs it).
    calibration : callable, table or (heights, forces), optional
        Magnet height -> force (see :func:`force_from_height`). Without it the
        trace must have a ``force`` column. There is no default calibration.
    molecules : sequence of str, optional
        Beads to turn into curves (default: all but the reference beads).
    turns_tolerance, height_tolerance, min_frames, guard
        As for :func:`find_plateaus`.
    check_settled : bool
        Raise DataError when a plateau's kept frames still drift (first half
        against second half beyond 8 standard errors).
    errors : {"pooled", "plateau"}
        ``"pooled"`` (default): each plateau's own standard deviation with
        the statistical inefficiency of all plateaus of that bead at that
        magnet height, from their summed autocovariances (Sokal's windowing,
        bias of the plateau means removed:
        :func:`~supercoil.traces.errors.pooled_inefficiency`); assumes the
        bead's correlation time is about the same at all of them.
        ``"plateau"``: every plateau's own blocking error (no assumption, but
        on plateaus of a few hundred frames it scatters by about 20 % and is
        low by about 4 %; weighted by ``1 / sigma**2`` such errors make the
        fitted parameters' error bars about 20 % too small).
        See docs/theory/recordings.md#error.

    Returns
    -------
    pandas.DataFrame
        Exactly the table of :func:`supercoil.read_tweezers_csv`: ``molecule``,
        ``force`` [pN], ``turns``, ``extension`` [nm], ``sigma`` [nm] (the
        blocking standard error of each plateau mean), ready for
        :func:`~supercoil.fit_hat_curves` and :func:`~supercoil.fit_many`
        (rows molecule-major, plateaus in time order; :func:`find_plateaus`
        with the same arguments gives the plateau table).

    Raises
    ------
    DataError
        No plateau (the magnet never settles); no force; heights outside the
        calibration; unknown bead; a plateau not settled; a constant bead.

    Warns
    -----
    DataWarning
        Plateaus skipped (too few tracked frames) or too short for blocking.
    """
    source = trace.attrs.get("provenance", {}).get("source", "trace") \
        if isinstance(trace, pd.DataFrame) else "trace"
    if errors not in ("plateau", "pooled"):
        raise ValueError(f"errors must be 'plateau' or 'pooled', got {errors!r}")
    min_frames = check_min_frames(min_frames)
    plateaus = find_plateaus(trace, settle, turns_tolerance=turns_tolerance,
                             height_tolerance=height_tolerance, min_frames=min_frames,
                             guard=guard, source=source)
    z, force, refs, beads = _inputs(trace, plateaus, calibration, reference, molecules, source)
    zc = z.to_numpy() - _reference_signal(z, refs, source)[:, None]
    cols = _points(zc, list(z.columns), beads, plateaus, force, surface, min_frames,
                   check_settled, source, errors == "pooled")
    prov = provenance(
        source=str(source), settle=f"{float(magnitude(settle, U.s, 'settle')):g} s",
        reference_beads=refs, surface=_jsonable_surface(surface),
        force="calibration" if calibration is not None else "force column",
        error=_POOLED_METHOD if errors == "pooled" else _ERROR_METHOD + "per plateau",
        plateaus=len(plateaus))
    table = make_table({k: np.asarray(v, dtype=object if k == "molecule" else float)
                        for k, v in cols.items()}, _CURVE_UNITS, prov)
    return check_tweezers_frame(table, source=str(source))


_CURVE_UNITS = {"molecule": "", "force": "pN", "turns": "", "extension": "nm", "sigma": "nm"}
_POOLED_METHOD = ("standard deviation of each plateau with the statistical inefficiency pooled "
                  "over all plateaus of the bead at that magnet height: summed autocovariances, "
                  "Sokal's automatic window (c = 5), plateau-mean bias removed")
_ERROR_METHOD = ("blocking (Flyvbjerg & Petersen, J. Chem. Phys. 91, 461 (1989)); block size by "
                 "Lee et al., Phys. Rev. E 83, 066706 (2011), Eq. 14; ")


def _inputs(trace, plateaus, calibration, reference, molecules, source):
    """z matrix (frames x beads), force per plateau, reference beads, molecules."""
    _, z = _frames(trace)
    if calibration is not None:
        force = force_from_height(calibration, plateaus["height"].to_numpy())
    elif "force" in plateaus.columns:
        force = plateaus["force"].to_numpy()
    else:
        raise DataError(f"{source}: no force: pass calibration= (magnet height -> force) or a "
                        "trace with a force column; supercoil has no default calibration")
    refs = trace.attrs.get("reference_beads", []) if reference is None else (
        [reference] if isinstance(reference, str) else [str(r) for r in reference])
    beads = [b for b in z.columns if b not in refs] if molecules is None else \
        [str(m) for m in molecules]
    unknown = [b for b in beads if b not in z.columns]
    if unknown or not beads:
        raise DataError(f"{source}: molecule(s) {unknown or beads} not in the trace "
                        f"(beads: {list(z.columns)}, reference: {refs})")
    return z, force, refs, beads


def _points(zc, labels, beads, plateaus, force, surface, min_frames, check_settled, source,
            pool):
    """Mean and error of every (bead, plateau): the rotation-curve columns.

    ``pool=True``: one statistical inefficiency for all plateaus of a bead at
    one magnet height, from their summed autocovariances
    (:func:`~supercoil.traces.errors.pooled_inefficiency`); every plateau's
    error is its own standard deviation with it. ``pool=False``: each
    plateau's own blocking error (recordings.md#error).
    """
    cols = {"molecule": [], "force": [], "turns": [], "extension": [], "sigma": []}
    skipped, unconverged, groups = [], 0, {}
    for j, bead in enumerate(labels):
        if bead not in beads:
            continue
        offset = _surface(surface, bead)
        for p, f in zip(plateaus.itertuples(), force, strict=True):
            v = zc[p.first:p.stop, j]
            v = v[np.isfinite(v)]
            if v.size < min_frames:
                skipped.append((bead, int(p.plateau)))
                continue
            res = _plateau_mean(v, bead, p, source) if check_settled else blocking_error(v)
            unconverged += not (res.converged or pool)
            groups.setdefault((bead, round(p.height, 9)), []).append((len(cols["sigma"]), v))
            for key, val in (("molecule", bead), ("force", f), ("turns", p.turns),
                             ("extension", res.mean - offset), ("sigma", res.error)):
                cols[key].append(val)
    if pool:
        for members in groups.values():
            g, _, ok = pooled_inefficiency([v for _, v in members])
            unconverged += not ok
            for i, v in members:
                cols["sigma"][i] = error_from_inefficiency(v, g)[0]
    _warn(source, skipped, unconverged, len(cols["sigma"]))
    if not cols["sigma"]:
        raise DataError(f"{source}: no plateau has {min_frames} tracked frames for any bead")
    return cols

def _jsonable_surface(surface):
    if isinstance(surface, dict):
        return {str(k): str(v) for k, v in surface.items()}
    return None if surface is None else str(surface)


def _warn(source, skipped, unconverged, n):
    if skipped:
        shown = ", ".join(f"{b}/{p}" for b, p in skipped[:10]) + (" ..." if len(skipped) > 10
                                                                     else "")
        warnings.warn(f"{source}: skipped {len(skipped)} (bead/plateau) with too few tracked "
                      f"frames: {shown}", DataWarning, stacklevel=3)
    if unconverged:
        warnings.warn(f"{source}: blocking did not converge for {unconverged} of {n} plateau "
                      "means (plateau too short for the bead's correlation time); their sigma "
                      "is the largest blocking level (conservative)", DataWarning, stacklevel=3)
