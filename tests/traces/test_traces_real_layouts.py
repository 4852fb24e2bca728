"""Readers against files in the instruments' own layouts, odd tokens included.

* CALISTO text (github.com/lipfertlab/calisto, README "Input File Formats" and
  ``load_bead_datafile`` in src/CALISTO/engines/landing_engine.py): headerless,
  whitespace-separated, frame index, time, x y z per bead; a lost bead is printed by MSVC
  as ``-1.#IND000``, which CALISTO fills by linear interpolation along the column.
* MagScope's ``force_calibrant.txt`` (github.com/7jameslondon/MagScope, README "Force
  Calibrants", examples/motors/force_calibrant.txt): ``numpy.savetxt`` rows ``position
  force`` with 18 digits, an optional ``# Motor Position (mm) Force (pN)`` header.
* Binary formats that are not CALISTO text: HDF5 under another suffix (read), HDF4 and
  LabVIEW TDMS (named as not supported).
"""

import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil import DataError
from supercoil.cli import main
from supercoil.traces import (
    read_calibration,
    read_calisto,
    read_force_calibrant,
    rotation_curves,
    synthetic_calibration,
)

u = sc.ureg


def _with_ind_tokens(src, dst, cells):
    """Copy a CALISTO text file, replacing (line index, column) cells by -1.#IND000."""
    lines = src.read_text().splitlines()
    for i, j in cells:
        fields = lines[i].split()
        fields[j] = "-1.#IND000"
        lines[i] = "\t".join(fields)  # CALISTO's files are tab-separated
    dst.write_text("\n".join(lines) + "\n")
    return lines


def test_calisto_text_with_ind_tokens_in_x_and_y_reads_and_gives_curves(written, tmp_path):
    """-1.#IND000 in an x and a y column was fatal (a non-finite trace row, named by its
    internal row number); it is interpolated as CALISTO does, and the curves follow."""
    rec = written["calisto-text"]
    path = tmp_path / "rot.txt"
    orig = _with_ind_tokens(rec.path, path, [(534, 2), (535, 2), (900, 6), (1200, 4)])
    with pytest.warns(sc.DataWarning, match=r"4 value\(s\) -1.#IND000 .*4 line\(s\).*"
                                            r"first at line 535.*as CALISTO does"):
        trace = read_calisto(path, rec.motor_path)
    bead0 = trace[trace["bead"] == "0"].reset_index(drop=True)
    x_before, x_after = float(orig[533].split()[2]), float(orig[536].split()[2])
    np.testing.assert_allclose(bead0["x"].iloc[534:536],
                               x_before + (x_after - x_before) * np.array([1, 2]) / 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.DataWarning)
        curves = rotation_curves(trace, calibration=synthetic_calibration(), reference=["2"])
        clean = rotation_curves(read_calisto(rec.path, rec.motor_path),
                                calibration=synthetic_calibration(), reference=["2"])
    np.testing.assert_allclose(curves["extension"], clean["extension"], atol=0.5)


def test_calisto_text_errors_name_the_file_line(written, tmp_path):
    """With comment and blank lines above, the file line differs from the row index."""
    rec = written["calisto-text"]
    lines = rec.path.read_text().splitlines()
    fields = lines[530].split()
    fields[1] = lines[528].split()[1]  # time goes back
    body = [*lines[:530], " ".join(fields), *lines[531:]]
    path = tmp_path / "back.txt"
    path.write_text("# CALISTO bead trace\n\n" + "\n".join(body) + "\n")
    with pytest.raises(DataError, match=r"back.txt, column 1: frame time is not strictly "
                                        r"increasing at line 533 "):
        read_calisto(path, rec.motor_path)
    fields = lines[10].split()
    fields[3] = "1,5"  # a decimal comma
    path.write_text("\n".join([*lines[:10], " ".join(fields), *lines[11:]]) + "\n")
    with pytest.raises(DataError, match=r"line 11, column 3: non-numeric value '1,5'"):
        read_calisto(path, rec.motor_path)


def test_hdf5_under_another_suffix_is_read_and_other_binaries_are_named(written, tmp_path):
    hdf = tmp_path / "rot.hdf"
    hdf.write_bytes(written["calisto-hdf5"].path.read_bytes())
    a = read_calisto(hdf)
    b = read_calisto(written["calisto-hdf5"].path)
    np.testing.assert_array_equal(a["z"], b["z"])
    tdms = tmp_path / "rot.tdms"
    tdms.write_bytes(b"TDSm\x0e\x00\x00\x00\x69\x12\x00\x00" + bytes(64))  # TDMS lead-in
    with pytest.raises(DataError, match=r"a LabVIEW TDMS file; this format is not supported"):
        read_calisto(tdms)
    hdf4 = tmp_path / "old.hdf"
    hdf4.write_bytes(b"\x0e\x03\x13\x01" + bytes(64))
    with pytest.raises(DataError, match=r"a HDF4 file; this format is not supported"):
        read_calisto(hdf4)
    other = tmp_path / "rot.dat"
    other.write_bytes(b"\x00\x01\x02\x03binary")
    with pytest.raises(DataError, match=r"not an HDF5 file nor text .*not supported"):
        read_calisto(other, written["calisto-text"].motor_path)
    fake = tmp_path / "empty.tdms"
    fake.write_bytes(b"")
    with pytest.raises(DataError, match="not supported"):
        read_calisto(fake)


def _force_calibrant(path, header=True):
    """MagScope's force_calibrant.txt: numpy.savetxt of (position, force), 18 digits, here the
    synthetic magnet's F = 20 pN exp(-h / 0.8 mm) on MagScope's example grid (0 to ~10 mm)."""
    h = np.linspace(0.0, 10.0, 1000)
    rows = np.column_stack([h, 20.0 * np.exp(-h / 0.8)])
    np.savetxt(path, rows[::-1] if not header else rows, fmt="%.18e",
               header="Motor Position (mm) Force (pN)" if header else "")
    return path


@pytest.mark.parametrize("header", [True, False])
def test_magscope_force_calibrant_is_read(tmp_path, header):
    path = _force_calibrant(tmp_path / "force_calibrant.txt", header)
    table = read_force_calibrant(path)
    assert table.attrs["units"] == {"height": "mm", "force": "pN"}
    assert np.all(np.diff(table["height"]) > 0)  # sorted by position, as MagScope does
    same = read_calibration(path)
    np.testing.assert_array_equal(same["force"], table["force"])
    f = sc.traces.force_from_height(table, [0.5, 2.0])
    np.testing.assert_allclose(f, 20 * np.exp(-np.array([0.5, 2.0]) / 0.8), rtol=1e-6)


def test_force_calibrant_errors_name_the_line(tmp_path):
    p = tmp_path / "force_calibrant.txt"
    p.write_text("# Motor Position (mm) Force (pN)\n1.000 5.000\n1.010 x\n")
    with pytest.raises(DataError, match=r"line 3: expected two numbers"):
        read_force_calibrant(p)
    p.write_text("1.000 5.000\n1.000 5.1\n")
    with pytest.raises(DataError, match=r"line 2: position 1 mm also on line 1"):
        read_force_calibrant(p)
    p.write_text("1.000 5.000\n")
    with pytest.raises(DataError, match="at least 2 finite rows"):
        read_force_calibrant(p)


def test_cli_curves_takes_magscope_force_calibrant(written, tmp_path, capsys):
    """--calibration force_calibrant.txt (MagScope's own file) was rejected as a CSV."""
    folder = written["magscope"].path.parent
    cal = _force_calibrant(tmp_path / "force_calibrant.txt")
    rc = main(["curves", str(folder), "--reference", "2", "--calibration", str(cal),
               "--no-plot", "--out", str(tmp_path / "out")])
    assert rc == 0, capsys.readouterr()
    got = sc.read_tweezers_csv(tmp_path / "out" / "rotation_curves.csv")
    rc = main(["curves", str(folder), "--reference", "2", "--calibration",
               str(folder / "force_calibration.csv"), "--no-plot", "--out", str(tmp_path / "o2")])
    assert rc == 0
    ref = sc.read_tweezers_csv(tmp_path / "o2" / "rotation_curves.csv")
    np.testing.assert_allclose(got["force"], ref["force"], rtol=1e-4)
