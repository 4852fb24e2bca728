"""Every recording reader names a bad path, a directory and a non-UTF-8 byte.

The checks are the ones of read_tweezers_csv (one shared check, supercoil._csvfile).
"""

import math
import shutil

import pytest

import supercoil as sc
from supercoil import DataError
from supercoil.traces import read_calisto, read_magscope, read_motor_log, rotation_curves


def test_read_calisto_names_a_directory_and_a_non_path(tmp_path):
    (tmp_path / "motor.txt").write_text("0 0 1 0\n")
    with pytest.raises(DataError, match=r"cannot read \..*is a directory"):
        read_calisto(".", tmp_path / "motor.txt")
    with pytest.raises(TypeError, match="path must be a str or a path, got NoneType"):
        read_calisto(None, "motor.txt")
    with pytest.raises(TypeError, match="motor_path must be a str or a path, got int"):
        read_calisto(tmp_path / "rot.txt", 3)
    h5dir = tmp_path / "rec.h5"
    h5dir.mkdir()
    with pytest.raises(DataError, match=r"rec.h5: it is a directory"):
        read_calisto(h5dir)


def test_read_calisto_names_a_latin1_byte_by_line(written, tmp_path):
    bead = tmp_path / "rot.txt"
    lines = written["calisto-text"].path.read_bytes().splitlines(keepends=True)
    lines[2] = b"# R\xe9f\xe9rence\n"  # a Latin-1 comment line
    bead.write_bytes(b"".join(lines))
    with pytest.raises(DataError, match=r"rot.txt, line 3: not UTF-8 text"):
        read_calisto(bead, written["calisto-text"].motor_path)
    motor = tmp_path / "motor.txt"
    motor.write_bytes(b"0 0.0 1.0 0\n1 0.1 1.0 \xb0\n")
    with pytest.raises(DataError, match=r"motor.txt, line 2: not UTF-8"):
        read_calisto(written["calisto-text"].path, motor)


def test_read_calisto_missing_files_are_named(written, tmp_path):
    with pytest.raises(DataError, match="no such CALISTO recording"):
        read_calisto(tmp_path / "none.txt", written["calisto-text"].motor_path)
    with pytest.raises(DataError, match="no such CALISTO motor file"):
        read_calisto(written["calisto-text"].path, tmp_path / "none.txt")


def test_magscope_reader_names_a_bad_path_and_a_latin1_log(written, tmp_path):
    with pytest.raises(TypeError, match="path must be a str or a path, got NoneType"):
        read_magscope(None)
    with pytest.raises(TypeError, match="path must be a str or a path"):
        read_magscope([None])
    with pytest.raises(DataError, match="is a directory"):
        read_magscope([tmp_path])
    log = tmp_path / "ZaberNmsMotor.txt"
    log.write_bytes(b"# timestamp value_1\n1.0 0.0\n2.0 \xb0\n")
    with pytest.raises(DataError, match=r"line 3: not UTF-8 text.*MagScope hardware log"):
        read_motor_log(log, 1)
    with pytest.raises(DataError, match="is a directory"):
        read_motor_log(tmp_path, 1)
    folder = tmp_path / "acq"
    shutil.copytree(written["magscope"].path.parent, folder)
    (folder / "ZaberNmsMotor.txt").unlink()
    (folder / "ZaberNmsMotor.txt").mkdir()
    with pytest.raises(DataError, match=r"ZaberNmsMotor\.txt: it is a directory"):
        read_magscope(folder)


@pytest.mark.parametrize("bad, exc", [("abc", TypeError), (math.nan, ValueError),
                                      (math.inf, ValueError), (3, ValueError),
                                      (16.5, ValueError), (True, TypeError), (None, TypeError)])
def test_rotation_curves_names_a_bad_min_frames(written, recording, bad, exc):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.DataWarning)
        trace = read_calisto(written["calisto-hdf5"].path)
    with pytest.raises(exc, match=r"min_frames must be a whole number of frames"):
        rotation_curves(trace, calibration=sc.traces.synthetic_calibration(), min_frames=bad)
    with pytest.raises(exc, match=r"min_frames must be a whole number of frames"):
        sc.traces.find_plateaus(trace, min_frames=bad)
