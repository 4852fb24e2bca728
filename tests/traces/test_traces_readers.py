"""Readers of MagScope and CALISTO recordings: layout, values, malformed files."""

import shutil
import sys

import h5py
import numpy as np
import pytest

import supercoil as sc
from supercoil import DataError
from supercoil.traces import read_calisto, read_magscope, rotation_curves

u = sc.ureg


def _magscope(written, recording):
    return read_magscope(written["magscope"].path, reference_beads=recording.reference_beads)


def test_magscope_reader_restores_time_order_and_values(written, recording):
    """Frames are stored in shuffled batches (writer append order); the reader sorts them
    by frame_timestamps_ns and gives back the simulated positions exactly."""
    with h5py.File(written["magscope"].path) as fh:
        stored = fh["tracking/frame_timestamps_ns"][()]
    assert np.any(np.diff(stored.astype(np.int64)) < 0)  # the file really is out of order
    trace = _magscope(written, recording)
    n_fr, n_b = recording.xyz.shape[:2]
    assert len(trace) == n_fr * n_b
    assert trace.attrs["units"] == {"time": "s", "bead": "", "x": "nm", "y": "nm", "z": "nm",
                                    "turns": "", "height": "mm"}
    assert trace.attrs["reference_beads"] == ["2"]
    t = trace["time"].to_numpy()[::n_b]
    assert np.all(np.diff(t) > 0)
    np.testing.assert_allclose(t, recording.time, atol=1e-9)
    z = trace["z"].to_numpy().reshape(n_fr, n_b)
    np.testing.assert_array_equal(z, recording.xyz[:, :, 2])
    # motor state: the last log row at or before each frame (zero-order hold)
    # (frames within 1 us of a log row are ambiguous after the epoch-time round trip)
    idx = np.searchsorted(recording.log_time, recording.time, side="right") - 1
    gap = np.min(np.abs(recording.time[:, None] - recording.log_time[None, :]), axis=1)
    clear = gap > 1e-6
    assert clear.mean() > 0.6  # the 50 ms log grid meets every third 60 Hz frame
    np.testing.assert_allclose(trace["turns"].to_numpy()[::n_b][clear],
                               recording.log_turns[idx][clear], atol=1e-12)


@pytest.mark.parametrize("fmt", ["calisto-hdf5", "calisto-text"])
def test_calisto_readers(written, recording, fmt):
    rec = written[fmt]
    trace = read_calisto(rec.path, rec.motor_path,
                         reference_beads=None if fmt == "calisto-hdf5" else ["2"])
    labels = list(dict.fromkeys(trace["bead"]))
    if fmt == "calisto-hdf5":
        assert labels == ["M0", "M1", "R2"] and trace.attrs["reference_beads"] == ["R2"]
    else:
        assert labels == ["0", "1", "2"]
    n_b = len(labels)
    z = trace["z"].to_numpy().reshape(-1, n_b)
    np.testing.assert_allclose(z, recording.xyz[: len(z), :, 2], atol=1e-6)


def test_all_formats_give_the_same_rotation_curves(written, recording):
    cal = sc.read_csv(written["magscope"].path.parent / "force_calibration.csv")
    traces = [_magscope(written, recording), read_calisto(written["calisto-hdf5"].path),
              read_calisto(written["calisto-text"].path, written["calisto-text"].motor_path,
                           reference_beads=["2"])]
    a, b, c = (rotation_curves(t, calibration=cal) for t in traces)
    pa, pb, pc = (rotation_curves(t, calibration=cal, errors="pooled") for t in traces)
    for other, pooled in ((b, pb), (c, pc)):
        assert len(other) == len(a) == 36
        np.testing.assert_allclose(other["turns"], a["turns"], atol=1e-6)
        np.testing.assert_allclose(other["force"], a["force"], rtol=1e-5)
        # the kept windows differ by up to 3 frames (held log against interpolated stage,
        # 50 ms polls): means agree far below their error; the blocking errors of single
        # plateaus only to their own precision (7 blocks), the pooled ones closely
        assert np.all(np.abs(other["extension"] - a["extension"]) < 0.5 * a["sigma"])
        assert np.median(other["sigma"] / a["sigma"]) == pytest.approx(1, abs=0.1)
        np.testing.assert_allclose(pooled["sigma"], pa["sigma"], rtol=0.1)


def test_text_units_are_applied(written, recording):
    """A setup writing um and ms (CALISTO's conversion factors) reads the same."""
    rec = written["calisto-text"]
    data = np.loadtxt(rec.path)
    data[:, 1] *= 1e3
    data[:, 2:] /= 1e3
    path = rec.path.with_name("rot_um.txt")
    np.savetxt(path, data, fmt="%.9f")
    a = read_calisto(rec.path, rec.motor_path)
    b = read_calisto(path, rec.motor_path, time_unit="ms", xy_unit="um", z_unit="um")
    np.testing.assert_allclose(b["z"], a["z"], atol=1e-5)
    np.testing.assert_allclose(b["time"], a["time"], atol=1e-8)


# ---- malformed files --------------------------------------------------------------------------


def _copy_magscope(written, tmp_path):
    dst = tmp_path / "ms"
    shutil.copytree(written["magscope"].path.parent, dst)
    return dst / written["magscope"].path.name


def test_magscope_missing_group_and_dataset(written, tmp_path):
    path = _copy_magscope(written, tmp_path)
    with h5py.File(path, "a") as fh:
        del fh["tracking/positions_nm"]
    with pytest.raises(DataError, match=r"group '/tracking': no dataset 'positions_nm'"):
        read_magscope(path)
    with h5py.File(path, "a") as fh:
        del fh["tracking"]
    with pytest.raises(DataError, match=r"rot|no group '/tracking'"):
        read_magscope(path)


def test_magscope_inconsistent_offsets(written, tmp_path):
    path = _copy_magscope(written, tmp_path)
    with h5py.File(path, "a") as fh:
        off = fh["tracking/frame_offsets"][()]
        del fh["tracking/frame_offsets"]
        fh["tracking/frame_offsets"] = off[:-1]
    with pytest.raises(DataError, match="'frame_offsets' has shape"):
        read_magscope(path)


def test_magscope_motor_log_time_going_back_names_the_line(written, tmp_path):
    path = _copy_magscope(written, tmp_path)
    log = path.parent / "ZaberNmsMotor.txt"
    lines = log.read_text().splitlines()
    lines[10], lines[11] = lines[11], lines[10]
    log.write_text("\n".join(lines) + "\n")
    with pytest.raises(DataError, match=r"ZaberNmsMotor.txt, line 12: time .* before"):
        read_magscope(path)
    log.unlink()
    with pytest.raises(DataError, match=r"no such motor log: .*ZaberNmsMotor\.txt"):
        read_magscope(path)


def test_magscope_unknown_reference_and_duplicated_frame(written, tmp_path):
    path = _copy_magscope(written, tmp_path)
    with pytest.raises(DataError, match=r"reference bead\(s\) \['7'\] not in"):
        read_magscope(path, reference_beads=[7])
    with h5py.File(path, "a") as fh:
        ts = fh["tracking/frame_timestamps_ns"]
        ts[5] = ts[6]
    with pytest.raises(DataError, match=r"frame_timestamps_ns.*not strictly increasing"):
        read_magscope(path)


def _copy_calisto(written, tmp_path):
    path = tmp_path / "rot.h5"
    shutil.copy(written["calisto-hdf5"].path, path)
    return path


def test_calisto_missing_stage_and_short_bead(written, tmp_path):
    path = _copy_calisto(written, tmp_path)
    with h5py.File(path, "a") as fh:
        z = fh["M1/z_nm"][()]
        del fh["M1/z_nm"]
        fh["M1/z_nm"] = z[:-3]
    with pytest.raises(DataError, match=r"dataset '/M1/z_nm': \d+ frames, expected \d+"):
        read_calisto(path)
    with h5py.File(path, "a") as fh:
        del fh["stage/mag_rot_turn"]
    with pytest.raises(DataError, match=r"group '/stage': no dataset 'mag_rot_turn'"):
        read_calisto(path)
    with h5py.File(path, "a") as fh:
        del fh["stage"]
    with pytest.raises(DataError, match=r"no group '/stage'"):
        read_calisto(path)


def test_calisto_non_monotonic_time_and_empty_bead(written, tmp_path):
    path = _copy_calisto(written, tmp_path)
    with h5py.File(path, "a") as fh:
        fh["M0/z_nm"][...] = np.nan
    with pytest.warns(sc.DataWarning, match=r"dropped bead\(s\) \['M0'\]: no finite z"):
        trace = read_calisto(path)
    assert "M0" not in set(trace["bead"]) and trace.attrs["provenance"]["dropped_beads"] == ["M0"]
    with h5py.File(path, "a") as fh:
        t = fh["timestamp"]
        t[100] = t[99] - 0.01
    with pytest.raises(DataError, match=r"dataset '/timestamp'.*not strictly increasing at "
                                        r"index 100"):
        read_calisto(path)


def test_calisto_text_ragged_and_non_numeric_lines(written, tmp_path):
    rec = written["calisto-text"]
    lines = rec.path.read_text().splitlines()
    bad = tmp_path / "bad.txt"
    bad.write_text("\n".join([*lines[:20], lines[20] + " 1.0", *lines[21:40]]) + "\n")
    with pytest.raises(DataError, match=r"bad.txt, line 21: 12 columns, the first data line"):
        read_calisto(bad, rec.motor_path)
    fields = lines[30].split()
    fields[4] = "abc"
    bad.write_text("\n".join([*lines[:30], " ".join(fields), *lines[31:40]]) + "\n")
    with pytest.raises(DataError, match=r"line 31, column 4: non-numeric value 'abc'"):
        read_calisto(bad, rec.motor_path)
    with pytest.raises(DataError, match="needs its motor file"):
        read_calisto(rec.path)


def test_calisto_text_nan_token_is_interpolated_with_a_warning(written, tmp_path):
    """CALISTO fills -1.#IND000 linearly along the column; so does the reader (was: dropped)."""
    rec = written["calisto-text"]
    lines = rec.path.read_text().splitlines()
    fields = lines[50].split()
    fields[4] = "-1.#IND000"
    path = tmp_path / "nan.txt"
    path.write_text("\n".join([*lines[:50], " ".join(fields), *lines[51:]]) + "\n")
    with pytest.warns(sc.DataWarning, match=r"1 value\(s\) -1.#IND000 .* at line 51"):
        trace = read_calisto(path, rec.motor_path)
    assert trace.attrs["provenance"]["dropped_records"] == 0
    z = trace[trace["bead"] == "0"]["z"].to_numpy()
    before, after = float(lines[49].split()[4]), float(lines[51].split()[4])
    assert z[50] == pytest.approx((before + after) / 2)


def test_missing_h5py_names_the_extra(written, monkeypatch):
    monkeypatch.setitem(sys.modules, "h5py", None)
    with pytest.raises(ImportError, match=r"pip install 'supercoil\[hdf5\]'"):
        read_magscope(written["magscope"].path)
    with pytest.raises(ImportError, match=r"supercoil\[hdf5\]"):
        read_calisto(written["calisto-hdf5"].path)


def test_magscope_bead_with_no_frames(written, tmp_path):
    """A bead whose z is NaN in every record (no Z-LUT for it) is dropped and named (it
    once aborted the whole read)."""
    path = _copy_magscope(written, tmp_path)
    with h5py.File(path, "a") as fh:
        ids = fh["tracking/bead_ids"][()]
        pos = fh["tracking/positions_nm"]
        z = pos[:, 2]
        z[ids == 1] = np.nan
        pos[:, 2] = z
    with pytest.warns(sc.DataWarning, match=r"dropped bead\(s\) \['1'\]: no finite z value"):
        trace = read_magscope(path)
    assert sorted(set(trace["bead"])) == ["0", "2"]
    assert trace.attrs["provenance"]["dropped_beads"] == ["1"]


def test_magscope_recording_split_over_two_files(written, recording, tmp_path):
    """MagScope rotates tracking files (hourly by default): a folder with two files reads as
    the one file did; the same frame in both files is an error."""
    src = written["magscope"].path
    dst = tmp_path / "split"
    shutil.copytree(src.parent, dst)
    (dst / src.name).unlink()
    with h5py.File(src) as fh:
        g = fh["tracking"]
        ts, pos, ids = g["frame_timestamps_ns"][()], g["positions_nm"][()], g["bead_ids"][()]
    n_b = 3
    half = ts.size // 2
    for name, sl in (("Tracking Data A.h5", slice(0, half)), ("Tracking Data B.h5",
                                                             slice(half - 1, None))):
        rows = slice(sl.start * n_b, None if sl.stop is None else sl.stop * n_b)
        with h5py.File(dst / name, "w") as fh:
            g = fh.create_group("tracking")
            g.attrs["schema_version"] = 1
            g["frame_timestamps_ns"] = ts[sl]
            g["frame_offsets"] = np.arange(0, (ts[sl].size + 1) * n_b, n_b, dtype=np.uint64)
            g["bead_ids"] = ids[rows]
            g["positions_nm"] = pos[rows]
    with pytest.raises(DataError, match=r"2 tracking files .*not strictly increasing"):
        read_magscope(dst)  # frame half - 1 is in both
    with h5py.File(dst / "Tracking Data B.h5", "a") as fh:
        g = fh["tracking"]
        data = {k: g[k][()] for k in ("frame_timestamps_ns", "bead_ids", "positions_nm")}
        for k in list(g):
            del g[k]
        g["frame_timestamps_ns"] = data["frame_timestamps_ns"][1:]
        g["frame_offsets"] = np.arange(0, data["frame_timestamps_ns"].size * n_b, n_b,
                                       dtype=np.uint64)
        g["bead_ids"] = data["bead_ids"][n_b:]
        g["positions_nm"] = data["positions_nm"][n_b:]
    a = read_magscope(dst, reference_beads=["2"])
    b = _magscope(written, recording)
    np.testing.assert_array_equal(a["z"].to_numpy(), b["z"].to_numpy())
    assert len(a.attrs["provenance"]["files"]) == 2
