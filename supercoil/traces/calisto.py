"""Reader of CALISTO recordings (Lipfert lab, github.com/lipfertlab/calisto).

What was verified, and where (CALISTO repository, read 2026-12-01 at commits
2efb2d0 and 0b79d75): README.md ("Input File Formats"),
``src/CALISTO/engines/landing_engine.py`` and ``src/CALISTO/engines/offset_engine.py``
(the loaders, including the rotation loaders ``load_rot_hdfdatafile``,
``load_rot_datafile``, ``load_rot_motor_datafile`` and
``verify_rot_data_consistency``), ``src/CALISTO/config.yaml`` (unit factors).

HDF5 (``.h5``): root dataset ``timestamp`` (frame times, float64); group
``stage`` with ``t_s`` (motor times), ``mag_pos_mm`` (magnet position) and, for
rotation measurements, ``mag_rot_turn`` (magnet rotation, turns); one group per
bead, ``M<id>`` (magnetic), ``R<id>`` (reference) or a bare integer ``<id>``
(magnetic), each with ``x_nm``, ``y_nm``, ``z_nm`` of the frames' length.

Text (``.txt``): whitespace-separated, no header. Bead file: column 0 frame
index (ignored), 1 time, then x, y, z of bead 0, of bead 1, ...; motor file:
0 frame index, 1 time, 2 magnet position, 3 magnet rotation (turns). The token
``-1.#IND000`` is NaN (CALISTO interpolates it; here such a record is dropped
and counted, with a warning).

Units: CALISTO multiplies every quantity by per-setup factors
(``bead_time_to_seconds``, ``bead_xy_position_to_nanometers``,
``bead_z_position_to_nanometers``, ``magnet_position_to_millimeters``,
``magnet_time_to_seconds``; all 1 in its default setup), so the dataset names
do not fix the units; the ``*_unit`` arguments here play that role, with the
default setup's units (s, nm, mm) as defaults. The motor state is interpolated
linearly onto the frame times, as CALISTO does (without its extrapolation:
frames outside the motor record are dropped, with a warning).
"""

from __future__ import annotations

import io

import numpy as np
import pandas as pd

from .._csvfile import check_path, read_text
from ..exceptions import DataError
from ..units import ureg
from .trace import build_trace, check_increasing, open_hdf5

__all__ = ["read_calisto"]

_NA = ["-1.#IND000"]


def _factor(unit, target, name):
    try:
        return float(ureg.Quantity(1.0, unit).m_as(target))
    except Exception as exc:  # pint parse or dimensionality error
        raise ValueError(f"{name}={unit!r} is not a unit convertible to {target}: {exc}"
                         ) from None


def _interp(t_log, v, t, where):
    check_increasing(t_log, where, "motor time")
    out = np.interp(t, t_log, v)
    out[(t < t_log[0]) | (t > t_log[-1])] = np.nan
    return out


def _read_text(path, min_cols, what):
    path, text = read_text(path, f"CALISTO {what} file")
    # comment lines are removed here, not by pandas: its comment="#" would cut the NaN
    # token -1.#IND000 in the middle of a line
    kept = [(i, ln) for i, ln in enumerate(text.splitlines(), start=1)
            if ln.strip() and not ln.lstrip().startswith("#")]
    if not kept:
        raise DataError(f"{path}: no data rows (expected whitespace-separated numbers)")
    lines = [i for i, _ in kept]
    counts = [len(ln.split()) for _, ln in kept]
    ncol = counts[0]
    bad = [i for i, c in enumerate(counts) if c != ncol]
    if bad:
        raise DataError(f"{path}, line {lines[bad[0]]}: {counts[bad[0]]} columns, the first "
                        f"data line has {ncol}; expected the same number on every line")
    df = pd.read_csv(io.StringIO("\n".join(ln for _, ln in kept)), sep=r"\s+", header=None,
                     na_values=_NA, engine="c")
    if ncol < min_cols:
        raise DataError(f"{path}, line {lines[0]}: {ncol} columns, expected at least {min_cols} "
                        f"for a CALISTO {what} file")
    for j in range(ncol):
        if not pd.api.types.is_numeric_dtype(df[j]):
            i = int(np.flatnonzero(pd.to_numeric(df[j], errors="coerce").isna()
                                   & df[j].notna())[0])
            raise DataError(f"{path}, line {lines[i]}, column {j}: non-numeric value "
                            f"{df[j].iloc[i]!r}; expected a number or -1.#IND000")
    return df.to_numpy(dtype=float), lines


def _calisto_text(path, motor_path, f_t, f_xy, f_z, f_mag, f_mt):
    if motor_path is None:
        raise DataError(f"{path}: a CALISTO text recording needs its motor file "
                        "(motor_path=...: frame, time, magnet position, rotation)")
    data, lines = _read_text(path, 5, "bead trace")
    if (data.shape[1] - 2) % 3:
        raise DataError(f"{path}, line {lines[0]}: {data.shape[1]} columns; expected "
                        "frame, time, then x, y, z per bead (2 + 3 n columns)")
    t = data[:, 1] * f_t
    check_increasing(t, f"{path}, column 1", "frame time")
    xyz = data[:, 2:].reshape(len(t), -1, 3) * np.array([f_xy, f_xy, f_z])
    motor, _ = _read_text(motor_path, 4, "motor")
    tm = motor[:, 1] * f_mt
    where = f"{motor_path}, column 1"
    height = _interp(tm, motor[:, 2] * f_mag, t, where)
    turns = _interp(tm, motor[:, 3], t, where)
    beads = [str(i) for i in range(xyz.shape[1])]
    return t, beads, xyz, turns, height, []


def _calisto_hdf5(path, f_t, f_xy, f_z, f_mag, f_mt):
    with open_hdf5(path, "CALISTO recording") as fh:
        if "timestamp" not in fh:
            raise DataError(f"{path}: no dataset '/timestamp' (the frame times); expected "
                            "/timestamp, /stage/{t_s, mag_pos_mm, mag_rot_turn}, /M<i>, /R<i>")
        if "stage" not in fh:
            raise DataError(f"{path}: no group '/stage'; expected /stage/t_s, "
                            "/stage/mag_pos_mm and /stage/mag_rot_turn")
        for name in ("t_s", "mag_pos_mm", "mag_rot_turn"):
            if name not in fh["stage"]:
                raise DataError(f"{path}, group '/stage': no dataset {name!r} (a rotation "
                                "recording has t_s, mag_pos_mm and mag_rot_turn)")
        t = np.asarray(fh["timestamp"][()], dtype=float) * f_t
        tm = np.asarray(fh["stage/t_s"][()], dtype=float) * f_mt
        pos = np.asarray(fh["stage/mag_pos_mm"][()], dtype=float) * f_mag
        rot = np.asarray(fh["stage/mag_rot_turn"][()], dtype=float)
        if not (tm.shape == pos.shape == rot.shape):
            raise DataError(f"{path}, group '/stage': t_s, mag_pos_mm, mag_rot_turn have "
                            f"shapes {tm.shape}, {pos.shape}, {rot.shape}; expected equal")
        keys = [k for k in fh if _bead_key(k) is not None]
        if not keys:
            raise DataError(f"{path}: no bead group (expected groups M<i>, R<i> or <i>)")
        keys.sort(key=lambda k: _bead_key(k)[1])
        xyz = np.full((t.size, len(keys), 3), np.nan)
        refs = []
        for j, k in enumerate(keys):
            g = fh[k]
            for c, name in enumerate(("x_nm", "y_nm", "z_nm")):
                if name not in g:
                    raise DataError(f"{path}, group '/{k}': no dataset {name!r}; expected "
                                    "x_nm, y_nm, z_nm")
                v = np.asarray(g[name][()], dtype=float)
                if v.shape != t.shape:
                    raise DataError(f"{path}, dataset '/{k}/{name}': {v.size} frames, expected "
                                    f"{t.size} (the length of '/timestamp')")
                xyz[:, j, c] = v * (f_z if c == 2 else f_xy)
            if _bead_key(k)[0] == "R":
                refs.append(k)
    check_increasing(t, f"{path}, dataset '/timestamp'", "frame time")
    where = f"{path}, dataset '/stage/t_s'"
    return t, keys, xyz, _interp(tm, rot, t, where), _interp(tm, pos, t, where), refs


def _bead_key(k):
    kind = k[0] if k[:1] in ("M", "R") else "M"
    num = k[1:] if k[:1] in ("M", "R") else k
    return (kind, int(num)) if num.isdigit() else None


def read_calisto(path, motor_path=None, *, time_unit="s", xy_unit="nm", z_unit="nm",
                 magnet_unit="mm", motor_time_unit="s", reference_beads=None):
    """Read a CALISTO rotation recording (HDF5, or headerless text) into a trace table.

    Parameters
    ----------
    path : str or Path
        ``.h5``/``.hdf5``: the single-file recording; anything else: the
        whitespace-separated bead trace file.
    motor_path : str or Path, optional
        The motor file of a text recording (required there).
    time_unit, xy_unit, z_unit, magnet_unit, motor_time_unit : str
        Units of the stored values (CALISTO's per-setup conversion factors);
        defaults: CALISTO's default setup (s, nm, nm, mm, s).
    reference_beads : sequence of str, optional
        Labels of reference beads. Default: the ``R<i>`` groups of an HDF5
        file, none for text. Text beads are labelled ``"0"``, ``"1"``, ...

    Returns
    -------
    pandas.DataFrame
        The trace table (time [s], bead, x, y, z [nm], turns, height [mm]).

    Raises
    ------
    DataError
        Missing file, group or dataset (named); a bead group whose length
        differs from ``/timestamp``; a bead with no finite z; time not strictly
        increasing (names the dataset or column and the index); ragged or
        non-numeric text (names the line).
    ImportError
        HDF5 without h5py (``pip install 'supercoil[hdf5]'``).
    """
    path = check_path(path, "path")
    if motor_path is not None:
        motor_path = check_path(motor_path, "motor_path")
    f_t = _factor(time_unit, "s", "time_unit")
    f_mt = _factor(motor_time_unit, "s", "motor_time_unit")
    f_xy = _factor(xy_unit, "nm", "xy_unit")
    f_z = _factor(z_unit, "nm", "z_unit")
    f_mag = _factor(magnet_unit, "mm", "magnet_unit")
    if path.suffix.lower() in (".h5", ".hdf5"):
        t, beads, xyz, turns, height, refs = _calisto_hdf5(path, f_t, f_xy, f_z, f_mag, f_mt)
        fmt = "calisto-hdf5"
    else:
        t, beads, xyz, turns, height, refs = _calisto_text(path, motor_path, f_t, f_xy, f_z,
                                                           f_mag, f_mt)
        fmt = "calisto-text"
    if reference_beads is not None:
        refs = [str(r) for r in reference_beads]
        missing = [r for r in refs if r not in beads]
        if missing:
            raise DataError(f"{path}: reference bead(s) {missing} not in the recording "
                            f"(beads: {beads})")
    extra = {"motor_path": str(motor_path)} if motor_path is not None else {}
    return build_trace(t, beads, xyz, turns, height, source=path, fmt=fmt,
                       reference_beads=refs, extra=extra)
