"""Reader of MagScope recordings (``pip install magscope``, github.com/7jameslondon/MagScope).

What was verified, and where (MagScope repository, commit 9d7b06d, read
2026-12-01): ``magscope/tracking_data.py`` (the writer) and
``docs/source/user_guide.rst`` ("Tracking Data Files", "Hardware telemetry and
saving"); ``magscope/hardware.py`` (motor logs); ``examples/motors/zaber_nms.py``
and ``examples/motors/zaber_lsq.py`` (the rotary and linear magnet motors).

Tracking file ``Tracking Data <timestamp>.h5``, group ``/tracking``:

* ``frame_timestamps_ns`` (uint64, n_frames): Unix epoch time of each frame, ns;
* ``frame_offsets`` (uint64, n_frames + 1): the records of frame ``i`` are rows
  ``frame_offsets[i]:frame_offsets[i + 1]``;
* ``bead_ids`` (uint16, n_records) and ``positions_nm`` (float64, n_records x 3):
  x, y, z in nm (z NaN where no Z-LUT gave a value);
* attribute ``schema_version`` = 1 (the only version this reader knows).

Records are in writer append order, not necessarily in time order; the user
guide says to order by ``frame_timestamps_ns``, which this reader does.

Motor logs: each hardware manager appends ``<ManagerName>.txt`` to the
acquisition folder, a ``# timestamp value_1 ...`` header line then
``numpy.savetxt`` rows (whitespace-separated floats), column 0 the Unix time in
s. The columns are manager-specific: for the Zaber managers of the MagScope
examples column 1 is the position, in turns for ``ZaberNmsMotor`` (rotary
magnet motor) and in mm for ``ZaberLsqMotor`` (linear magnet motor); these are
the defaults here and can be changed. Rows are written when the state changes
(or every 50 ms), so the motor state at a frame is the last logged row at or
before it.

Not known: the sign convention of z (taken here as growing away from the
surface) and the meaning of the magnet height (distance or stage position):
the force calibration the user passes decides that.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._csvfile import check_path, read_text
from ..exceptions import DataError
from .trace import build_trace, check_increasing, hold_previous, open_hdf5

__all__ = ["read_magscope", "read_motor_log"]

_DATASETS = ("frame_timestamps_ns", "frame_offsets", "bead_ids", "positions_nm")


def read_motor_log(path, column, what="value"):
    """Read a MagScope hardware log: times (Unix s) and column ``column`` of every row.

    Raises
    ------
    DataError
        No such file, no data rows, a non-numeric field or too few columns
        (names the line), or time going backwards (names the line).
    """
    try:
        path, text = read_text(path, "motor log")
    except DataError as exc:
        raise DataError(f"{exc} (expected the MagScope hardware log holding the magnet "
                        f"{what})") from None
    times, values, lines = [], [], []
    for num, line in enumerate(text.splitlines(), start=1):
        body = line.strip()
        if not body or body.startswith("#"):
            continue
        fields = body.split()
        if len(fields) <= column:
            raise DataError(f"{path}, line {num}: {len(fields)} column(s), expected at least "
                            f"{column + 1} (timestamp and the {what} in column {column})")
        try:
            t, v = float(fields[0]), float(fields[column])
        except ValueError:
            raise DataError(f"{path}, line {num}: non-numeric field in {body[:60]!r}; "
                            "expected whitespace-separated numbers") from None
        times.append(t)
        values.append(v)
        lines.append(num)
    if not times:
        raise DataError(f"{path}: no data rows (expected '# timestamp ...' then numbers)")
    t = np.array(times)
    back = np.flatnonzero(np.diff(t) < 0)
    if back.size:
        i = int(back[0]) + 1
        raise DataError(f"{path}, line {lines[i]}: time {t[i]!r} s is before the previous "
                        f"row's {t[i - 1]!r} s; expected non-decreasing timestamps")
    # equal timestamps: keep the last row (the state after the change)
    keep = np.append(np.diff(t) > 0, True)
    return t[keep], np.array(values)[keep]


def _read_tracking(path):
    with open_hdf5(path, "MagScope tracking file") as fh:
        if "tracking" not in fh:
            raise DataError(f"{path}: no group '/tracking'; expected a MagScope tracking file "
                            f"with /tracking/{{{', '.join(_DATASETS)}}}")
        g = fh["tracking"]
        for name in _DATASETS:
            if name not in g:
                raise DataError(f"{path}, group '/tracking': no dataset {name!r}; expected "
                                f"{', '.join(_DATASETS)}")
        version = g.attrs.get("schema_version", None)
        if version is not None and int(version) != 1:
            raise DataError(f"{path}, group '/tracking': schema_version {int(version)}, "
                            "this reader knows version 1")
        ts = np.asarray(g["frame_timestamps_ns"][()], dtype=np.uint64)
        off = np.asarray(g["frame_offsets"][()], dtype=np.int64)
        ids = np.asarray(g["bead_ids"][()])
        pos = np.asarray(g["positions_nm"][()], dtype=float)
    n_frames, n_rec = ts.size, ids.size
    where = f"{path}, group '/tracking'"
    if n_frames == 0:
        raise DataError(f"{where}: 'frame_timestamps_ns' is empty; expected at least one frame")
    if off.shape != (n_frames + 1,) or off[0] != 0 or off[-1] != n_rec or np.any(np.diff(off) < 0):
        raise DataError(f"{where}: 'frame_offsets' has shape {off.shape}, first {off[:1]}, last "
                        f"{off[-1:]}; expected {n_frames + 1} non-decreasing offsets from 0 to "
                        f"{n_rec} (the number of records)")
    if pos.shape != (n_rec, 3):
        raise DataError(f"{where}: 'positions_nm' has shape {pos.shape}, expected ({n_rec}, 3)")
    return ts, off, ids, pos


def _tracking_files(path):
    """The tracking file(s): one file, a list of files, or all of a folder's."""
    if isinstance(path, list | tuple):
        paths = [check_path(p, "path") for p in path]
    elif check_path(path, "path").is_dir():
        paths = sorted(Path(path).glob("Tracking Data *.h5"))
        if not paths:
            raise DataError(f"{path}: no 'Tracking Data <timestamp>.h5' file in this folder")
    else:
        paths = [Path(path)]
    if not paths:
        raise DataError("read_magscope: no tracking file given")
    return paths


def read_magscope(path, *, rotation_log="ZaberNmsMotor.txt", rotation_column=1,
                  height_log="ZaberLsqMotor.txt", height_column=1, reference_beads=()):
    """Read a MagScope recording into the trace table of :mod:`supercoil.traces.trace`.

    Parameters
    ----------
    path : str, Path or list of them
        A ``Tracking Data <timestamp>.h5`` file, several (MagScope starts a new
        file every hour by default, user guide "Tracking Data Saving"), or the
        acquisition folder (all its tracking files). The frames of all files
        are merged in time order; a frame time present twice is an error.
    rotation_log, height_log : str or Path
        Motor logs of the magnet rotation (in turns) and height (in mm);
        relative paths are taken in the tracking file's folder. Defaults: the
        Zaber rotary and linear managers of the MagScope examples.
    rotation_column, height_column : int
        Column of the rotation / height in those logs (0 is the timestamp).
    reference_beads : sequence of int or str
        Bead ids that are reference (surface-stuck) beads; MagScope does not
        mark them in the file. Stored in ``attrs["reference_beads"]``.

    Returns
    -------
    pandas.DataFrame
        The trace table (time [s], bead, x, y, z [nm], turns, height [mm]).

    Raises
    ------
    DataError
        Missing file, group or dataset; inconsistent shapes; duplicated frame
        times; a requested reference bead that is not in the file; malformed
        or time-reversed motor log (names the line).
    ImportError
        h5py is not installed (``pip install 'supercoil[hdf5]'``).
    """
    paths = _tracking_files(path)
    path = paths[0]
    parts = [_read_tracking(p) for p in paths]
    ts = np.concatenate([q[0] for q in parts])
    shift = np.cumsum([0] + [q[2].size for q in parts[:-1]])
    off = np.concatenate([[0]] + [q[1][1:] + k for q, k in zip(parts, shift, strict=True)])
    ids = np.concatenate([q[2] for q in parts])
    pos = np.concatenate([q[3] for q in parts])
    order = np.argsort(ts, kind="stable")
    ts_sorted = ts[order]
    t_rel = (ts_sorted - ts_sorted[0]).astype(np.int64) / 1e9
    where = path if len(paths) == 1 else f"{len(paths)} tracking files ({path.name}, ...)"
    check_increasing(t_rel, f"{where}, dataset '/tracking/frame_timestamps_ns' (sorted)",
                      "frame time")
    rank = np.empty_like(order)
    rank[order] = np.arange(order.size)
    frame_of_record = rank[np.repeat(np.arange(ts.size), np.diff(off))]
    labels = np.unique(ids)
    beads = [str(int(b)) for b in labels]
    col = np.searchsorted(labels, ids)
    xyz = np.full((ts.size, labels.size, 3), np.nan)
    xyz[frame_of_record, col] = pos
    refs = [str(r) for r in reference_beads]
    missing = [r for r in refs if r not in beads]
    if missing:
        raise DataError(f"{path}: reference bead(s) {missing} not in '/tracking/bead_ids' "
                        f"(beads found: {beads})")
    origin = int(ts_sorted[0]) / 1e9
    folder = path.parent
    t_rot, rot = read_motor_log(folder / rotation_log, rotation_column, "rotation (turns)")
    t_h, h = read_motor_log(folder / height_log, height_column, "height (mm)")
    turns = hold_previous(t_rot - origin, rot, t_rel)
    height = hold_previous(t_h - origin, h, t_rel)
    source = path if len(paths) == 1 else path.parent
    return build_trace(t_rel, beads, xyz, turns, height, source=source, fmt="magscope",
                       reference_beads=refs, time_origin=origin,
                       extra={"files": [str(p) for p in paths],
                              "rotation_log": str(folder / rotation_log),
                              "height_log": str(folder / height_log)})
