"""``supercoil curves RECORDING``: rotation-curve CSV, plateau table and figure; errors."""

import h5py
import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main
from supercoil.traces import (
    read_magscope,
    rotation_curves,
    simulate_recording,
    synthetic_calibration,
    write_synthetic_calisto,
    write_synthetic_magscope,
)


@pytest.fixture(scope="module")
def rec():
    return simulate_recording(molecules=2, reference=1, points_per_force=5, seed=21)


def test_curves_command_magscope_folder(tmp_path, capsys, rec):
    written = write_synthetic_magscope(tmp_path / "acq", rec)
    out = tmp_path / "out"
    rc = main(["curves", str(tmp_path / "acq"), "--reference", "2", "--calibration",
               str(tmp_path / "acq" / "force_calibration.csv"), "--settle", "1s",
               "--out", str(out)])
    assert rc == 0
    text = capsys.readouterr().out
    assert "10 plateaus" in text and "2 molecule(s)" in text
    curves = sc.read_tweezers_csv(out / "rotation_curves.csv")
    ref = rotation_curves(read_magscope(written.path, reference_beads=["2"]),
                          calibration=synthetic_calibration())
    np.testing.assert_allclose(curves["extension"], ref["extension"], rtol=1e-10)
    assert len(sc.read_csv(out / "plateaus.csv")) == 10
    assert (out / "recording.png").stat().st_size > 0
    # and the fit command takes the table as it is
    assert main(["fit", str(out / "rotation_curves.csv"), "--out", str(tmp_path / "fit"),
                 "--no-plot"]) == 0


def test_curves_command_calisto_text(tmp_path, capsys, rec):
    w = write_synthetic_calisto(tmp_path / "rot.txt", rec, text=True)
    rc = main(["curves", str(w.path), "--motor", str(w.motor_path), "--reference", "2",
               "--calibration", str(tmp_path / "force_calibration.csv"), "--no-plot",
               "--errors", "pooled", "--out", str(tmp_path / "out")])
    assert rc == 0
    curves = sc.read_tweezers_csv(tmp_path / "out" / "rotation_curves.csv")
    assert len(curves) == 20
    assert "pooled" in curves.attrs["provenance"]["error"]


def test_curves_command_errors_name_the_file(tmp_path, capsys, rec):
    w = write_synthetic_calisto(tmp_path / "rot.h5", rec)
    with h5py.File(w.path, "a") as fh:
        del fh["stage"]
    rc = main(["curves", str(w.path), "--out", str(tmp_path / "out")])
    assert rc == 2
    err = capsys.readouterr().err
    assert "supercoil curves: error:" in err and "rot.h5: no group '/stage'" in err
    w = write_synthetic_calisto(tmp_path / "ok.h5", rec)
    rc = main(["curves", str(w.path), "--out", str(tmp_path / "out")])  # no calibration
    assert rc == 2 and "no default calibration" in capsys.readouterr().err
    with pytest.raises(SystemExit):
        main(["curves", str(w.path), "--settle", "3nm"])
    assert "as a time" in capsys.readouterr().err
