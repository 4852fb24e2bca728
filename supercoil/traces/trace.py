"""The tidy time-series table every recording reader returns.

One row per (frame, bead), in the package's table convention
(:mod:`supercoil.tables`): plain magnitudes with ``attrs["units"]`` and
``attrs["provenance"]``. Columns:

===========  =======  ==========================================================
``time``     s        since the first frame of the recording
``bead``     (text)   the bead label as the recording names it (``"3"``, ``"M0"``)
``x, y, z``  nm       tracker position; ``z`` grows away from the surface
``turns``    (turns)  magnet rotation at that frame
``height``   mm       magnet height (stage position) at that frame
``force``    pN       optional: a force column written by the instrument
===========  =======  ==========================================================

``attrs["reference_beads"]`` lists the beads the recording marks as reference
(surface-stuck) beads, e.g. CALISTO's ``R<i>`` groups; ``[]`` if it marks none.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from ..exceptions import DataError
from ..tables import make_table, provenance

__all__ = ["TRACE_COLUMNS", "TRACE_UNITS", "build_trace", "check_trace", "require_h5py"]

#: Units of the trace table's columns.
TRACE_UNITS = {"time": "s", "bead": "", "x": "nm", "y": "nm", "z": "nm", "turns": "",
               "height": "mm", "force": "pN"}
#: Required columns (``force`` is optional).
TRACE_COLUMNS = ("time", "bead", "x", "y", "z", "turns", "height")


def require_h5py(path):
    """Import h5py or raise ImportError naming the ``supercoil[hdf5]`` extra."""
    try:
        import h5py
    except ImportError:  # pragma: no cover - h5py is in the test extra
        raise ImportError(
            f"reading or writing the HDF5 recording {path} needs h5py: "
            "pip install 'supercoil[hdf5]'"
        ) from None
    return h5py


def open_hdf5(path, kind):
    """The open h5py File of a recording; DataError naming ``path`` if it is missing or not HDF5."""
    from .._csvfile import check_path

    path = check_path(path, "path")
    if path.is_dir():
        raise DataError(f"cannot read {path}: it is a directory, not a {kind}; give the "
                        "file's path")
    h5py = require_h5py(path)
    try:
        return h5py.File(path, "r")
    except FileNotFoundError:
        raise DataError(f"no such {kind}: {path}") from None
    except OSError as exc:
        raise DataError(f"{path}: not an HDF5 file ({exc})") from None


def check_increasing(t, where, what="time"):
    """DataError naming ``where`` and the first index where ``t`` does not increase."""
    t = np.asarray(t, dtype=float)
    bad = np.flatnonzero(~np.isfinite(t))
    if bad.size:
        raise DataError(f"{where}: {what} is not finite at index {int(bad[0])} "
                        f"(expected finite, strictly increasing times)")
    step = np.diff(t)
    bad = np.flatnonzero(step <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise DataError(
            f"{where}: {what} is not strictly increasing at index {i} "
            f"({t[i - 1]!r} then {t[i]!r}); expected strictly increasing times")


def hold_previous(t_log, values, t_frames):
    """Value of an event log at each frame: the last logged value at or before it.

    Frames before the first log entry get NaN.
    """
    idx = np.searchsorted(t_log, t_frames, side="right") - 1
    out = np.full(t_frames.shape, np.nan)
    ok = idx >= 0
    out[ok] = np.asarray(values, dtype=float)[idx[ok]]
    return out


def build_trace(time, beads, xyz, turns, height, *, source, fmt, reference_beads=(),
                force=None, time_origin=None, extra=None):
    """Build the trace table from per-frame arrays (SI-free display units, see above).

    Parameters
    ----------
    time : (n_frames,) float, seconds, strictly increasing
    beads : sequence of str, one label per bead
    xyz : (n_frames, n_beads, 3) float, nm (NaN where the tracker lost the bead)
    turns, height : (n_frames,) float (turns, mm); NaN where the motor state is unknown
    force : (n_frames,) float pN, optional

    Frames without a motor state and bead records with a non-finite ``z`` are
    dropped; their numbers are recorded in the provenance (``dropped_frames``,
    ``dropped_records``) and the reader warns.
    """
    import warnings

    from ..exceptions import DataWarning

    time = np.asarray(time, dtype=float)
    n_frames, n_beads = xyz.shape[:2]
    known = np.isfinite(turns) & np.isfinite(height)
    if force is not None:
        known &= np.isfinite(force)
    if not known.any():
        raise DataError(f"{source}: no frame has a known magnet rotation and height "
                        "(the motor log does not overlap the frames)")
    for j, lab in enumerate(beads):
        if not np.isfinite(xyz[:, j, 2]).any():
            raise DataError(f"{source}: bead {lab!r} has no frames (no finite z value); "
                            "expected at least one tracked frame per bead")
    zok = np.isfinite(xyz[:, :, 2]) & known[:, None]
    dropped_records = int(known.sum() * n_beads - zok.sum())
    dropped_frames = int((~known).sum())
    fi, bj = np.nonzero(zok)  # frame-major order
    t0 = time[0]
    cols = {
        "time": time[fi] - t0,
        "bead": np.asarray(list(beads), dtype=object)[bj],
        "x": xyz[fi, bj, 0], "y": xyz[fi, bj, 1], "z": xyz[fi, bj, 2],
        "turns": np.asarray(turns, dtype=float)[fi],
        "height": np.asarray(height, dtype=float)[fi],
    }
    if force is not None:
        cols["force"] = np.asarray(force, dtype=float)[fi]
    prov = provenance(source=str(source), format=fmt, frames=int(n_frames),
                      dropped_frames=dropped_frames, dropped_records=dropped_records,
                      time_origin=time_origin if time_origin is not None else float(t0),
                      reference_beads=list(reference_beads), **(extra or {}))
    table = make_table(cols, {c: TRACE_UNITS[c] for c in cols}, prov)
    table.attrs["reference_beads"] = list(reference_beads)
    if dropped_frames or dropped_records:
        warnings.warn(
            f"{source}: dropped {dropped_frames} frame(s) without a known magnet state "
            f"(outside the motor log) and {dropped_records} bead record(s) with a non-finite z",
            DataWarning, stacklevel=3)
    return table


def check_trace(trace, source="trace"):
    """Check a trace table (columns, units, finite values); return it.

    Raises
    ------
    DataError
        Not a DataFrame, missing column or unit, unit other than the
        reader's, a non-finite value (names the row and column).
    """
    if not isinstance(trace, pd.DataFrame):
        raise DataError(f"{source}: expected a trace DataFrame, got {type(trace).__name__}")
    units = trace.attrs.get("units")
    if units is None:
        raise DataError(f"{source}: the trace has no attrs['units']")
    for col in (*TRACE_COLUMNS, "force"):
        if col not in trace.columns:
            if col == "force":
                continue
            raise DataError(f"{source}: missing column {col!r}; columns found: "
                            f"{list(map(str, trace.columns))}")
        if units.get(col) != TRACE_UNITS[col]:
            raise DataError(f"{source}, column {col!r}: unit {units.get(col)!r}, expected "
                            f"{TRACE_UNITS[col]!r} (the readers' unit)")
        if col != "bead":
            v = trace[col].to_numpy(dtype=float)
            bad = np.flatnonzero(~np.isfinite(v))
            if bad.size:
                raise DataError(f"{source}, row {int(bad[0])}, column {col!r}: non-finite "
                                f"value {v[bad[0]]!r}")
    if len(trace) == 0:
        raise DataError(f"{source}: the trace has no rows")
    return trace
