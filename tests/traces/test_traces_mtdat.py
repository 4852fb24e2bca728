"""MultiMT .mtdat files, written here exactly as MultiMT's writer lays them out.

Layout (github.com/ddunlap91/MagTweezer, multiMTgui_PylonMEX/Functions/mtdat_fileio/
mtdatwriteheader.m and mtdat_writerecord.m): '#!!#YAML_START\\n', SnakeYAML's dump of the
configuration (with the Record list, machinefmt and encoding filled in by the writer),
'#!!#YAML_END\\n', then per frame every Record field with fwrite (column-major, no padding).
The record list is the Chapeau Curve one of MultiMTgui_startChapeauCurve.m.
"""

import struct
import warnings

import numpy as np
import pytest

import supercoil as sc
from supercoil import DataError
from supercoil.traces import read_mtdat, read_mtdat_records, rotation_curves
from supercoil.traces.mtdat import parse_yaml_subset

u = sc.ureg
N_TRACKS = 3  # tracks 1, 2 measured, 3 the reference
RECORD = [("Date", "double", (1, 1)), ("Step", "uint32", (1, 1)),
          ("FrameCount", "double", (1, 1)), ("ObjectivePosition", "double", (1, 1)),
          ("MagnetHeight", "double", (1, 1)), ("MagnetRotation", "double", (1, 1)),
          ("X", "double", (N_TRACKS, 1)), ("Y", "double", (N_TRACKS, 1)),
          ("Z_REL", "double", (N_TRACKS, 1)), ("Z_ABS", "double", (N_TRACKS, 1)),
          ("dZ", "double", (N_TRACKS, 1)), ("UsingTilt", "int8", (1, 1))]
_CODES = {"double": "d", "uint32": "I", "int8": "b"}


def _header_yaml(n_tracks=N_TRACKS, machinefmt="ieee-le"):
    """The configuration as SnakeYAML 1.9 dumps it (default flow style: a collection of
    scalars only in flow style, wrapped at 80 columns; sequences in a mapping not indented;
    MATLAB numbers as Java doubles; an empty string quoted)."""
    tracks = "".join(
        f"- Type: {'Reference' if i == n_tracks - 1 else 'Measurement'}\n"
        f"  Radius: 30.0\n  IsCalibrated: 1\n  ZRef: {float(n_tracks)}\n"
        f"  Window: [{100.0 * i}, {100.0 * i + 10}, 60.0, 60.0]\n"
        "  CalibrationPositions: [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5,\n"
        "    6.0]\n" for i in range(n_tracks))
    record = "".join(f"- parameter: {p}\n  format: {f}\n  size: [{float(s[0])}, {float(s[1])}]\n"
                     f"  machinefmt: {machinefmt}\n  encoding: windows-1252\n"
                     for p, f, s in _record(n_tracks))
    return (
        "FileType: Chapeau Curve\n"
        "CreationDate: 2016-08-11 10:00\n"
        "Comments: ''\n"
        "InstrumentName: Black Tweezer\n"
        "CameraInterface: PylonMEX\n"
        "PxScale: 0.1678234\n"
        "PiezoController: PI E-665\n"
        "MotorCOM: COM6\n"
        "mag_rotscale: 1.0\n"
        "Temperature: .NaN\n"
        "LogFile: 'C:\\Users\\mt\\Documents\\MultiMT Data\\2016-08-11 log: run 1.txt'\n"
        f"num_tracks: {float(n_tracks)}\n"
        "TrackingInfo:\n" + tracks +
        "CameraSettings:\n  FrameRate: 30.0\n  UseFrameRate: 1\n  ROI: [0.0, 0.0, 1024.0, 768.0]\n"
        "ChapeauCurveScheme:\n"
        "  MagnetHeight: 1.0\n"
        "  MagnetRotationsPositions: [-10.0, -5.0, 0.0, 5.0, 10.0, 10.0, 5.0, 0.0, -5.0,\n"
        "    -10.0]\n"
        "  FrameCount: 100.0\n"
        "Record:\n" + record)


def _record(n_tracks):
    return [(p, f, (n_tracks, 1) if s[0] == N_TRACKS else s) for p, f, s in RECORD]


def write_mtdat(path, frames, n_tracks=N_TRACKS, machinefmt="ieee-le", header=None):
    """Write ``frames`` (dicts of Record values) as mtdatwriteheader + mtdat_writerecord do."""
    endian = "<" if machinefmt == "ieee-le" else ">"
    with open(path, "wb") as fh:
        fh.write(b"#!!#YAML_START\n")
        fh.write((header or _header_yaml(n_tracks, machinefmt)).encode("latin-1"))
        fh.write(b"#!!#YAML_END\n")
        for fr in frames:
            for p, f, _s in _record(n_tracks):
                v = np.asarray(fr[p], dtype=float).reshape(-1, order="F")  # fwrite: column-major
                fh.write(struct.pack(f"{endian}{v.size}{_CODES[f]}", *(
                    int(x) if f != "double" else float(x) for x in v)))
    return path


def _frames(n_steps=4, per_step=90, seed=0):
    """A chapeau-curve run: 30 Hz frames, rotation steps, z = extension + noise (um)."""
    rng = np.random.default_rng(seed)
    date0 = 736553.4166666666  # datenum of 2016-08-11 10:00
    frames, k = [], 0
    for step in range(n_steps):
        turns = -10.0 + 5.0 * step
        level = np.array([1.2 - 0.02 * abs(turns), 1.1 - 0.03 * abs(turns), 0.05])
        for i in range(per_step):
            z = level + rng.normal(0, 0.01, N_TRACKS) + 0.001 * k  # drift of 1 nm per frame
            frames.append({"Date": date0 + k / 30.0 / 86400.0, "Step": step + 1,
                           "FrameCount": i + 1, "ObjectivePosition": 50.0,
                           "MagnetHeight": 1.0, "MagnetRotation": turns,
                           "X": 100.0 + rng.normal(0, 0.1, N_TRACKS), "Y": np.full(N_TRACKS, 60.0),
                           "Z_REL": z, "Z_ABS": z + 10.0, "dZ": z[2] - z, "UsingTilt": 0})
            k += 1
    return frames


def test_header_and_records_read_as_the_writer_laid_them_out(tmp_path):
    frames = _frames()
    path = write_mtdat(tmp_path / "2016-08-11_ChapeauCurve_001.mtdat", frames)
    header, rec = read_mtdat_records(path)
    assert header["FileType"] == "Chapeau Curve" and header["Comments"] == ""
    assert header["CreationDate"] == "2016-08-11 10:00" and np.isnan(header["Temperature"])
    assert header["LogFile"].endswith("2016-08-11 log: run 1.txt")
    assert header["ChapeauCurveScheme"]["MagnetRotationsPositions"][-1] == -10.0
    assert len(header["ChapeauCurveScheme"]["MagnetRotationsPositions"]) == 10  # wrapped line
    assert [t["Type"] for t in header["TrackingInfo"]] == ["Measurement"] * 2 + ["Reference"]
    assert len(header["TrackingInfo"][0]["CalibrationPositions"]) == 13
    assert [r["parameter"] for r in header["Record"]] == [p for p, _, _ in RECORD]
    assert rec["Step"].dtype == np.uint32 and rec["UsingTilt"].dtype == np.int8
    assert rec["Z_ABS"].shape == (len(frames), N_TRACKS, 1)
    np.testing.assert_array_equal(rec["Z_ABS"][:, :, 0], [f["Z_ABS"] for f in frames])
    np.testing.assert_array_equal(rec["Step"], [f["Step"] for f in frames])


def test_read_mtdat_gives_the_trace_and_rotation_curves(tmp_path):
    frames = _frames()
    path = write_mtdat(tmp_path / "cc.mtdat", frames)
    trace = read_mtdat(path)
    assert trace.attrs["reference_beads"] == ["3"]
    assert sorted(set(trace["bead"])) == ["1", "2", "3"]
    t = trace[trace["bead"] == "1"]
    np.testing.assert_allclose(t["time"].to_numpy(), np.arange(len(frames)) / 30.0, atol=2e-5)
    np.testing.assert_allclose(t["z"].to_numpy(), [(f["Z_ABS"][0]) * 1e3 for f in frames])
    np.testing.assert_allclose(t["x"].to_numpy(), [f["X"][0] * 0.1678234e3 for f in frames])
    assert trace.attrs["units"]["z"] == "nm"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.DataWarning)
        curves = rotation_curves(trace, 0.5 * u.s, min_frames=16,
                                 calibration=lambda h: np.ones(np.shape(h.magnitude)) * u.pN)
        plateaus = sc.traces.find_plateaus(trace, 0.5 * u.s, min_frames=16)
    assert curves["turns"].tolist() == [-10.0, -5.0, 0.0, 5.0] * 2
    # the drift (1 nm per frame) removed with the reference track, frame by frame
    z = np.array([f["Z_ABS"] for f in frames]) * 1e3
    ref = z[:, 2] - z[:, 2].mean()
    for m in (0, 1):
        got = curves[curves["molecule"] == str(m + 1)]["extension"].to_numpy()
        want = [np.mean(z[a:b, m] - ref[a:b]) for a, b in zip(plateaus["first"],
                                                              plateaus["stop"], strict=True)]
        np.testing.assert_allclose(got, want, rtol=1e-12)
    m1 = curves[curves["molecule"] == "1"]["extension"].to_numpy()
    assert np.allclose(np.diff(m1), [100, 100, -100], atol=10)  # the schedule's levels


def test_big_endian_file_and_a_single_track(tmp_path):
    frames = _frames(n_steps=1, per_step=5)
    path = write_mtdat(tmp_path / "be.mtdat", frames, machinefmt="ieee-be")
    _, rec = read_mtdat_records(path)
    np.testing.assert_array_equal(rec["MagnetRotation"], [-10.0] * 5)
    one = [dict(f, X=f["X"][:1], Y=f["Y"][:1], Z_REL=f["Z_REL"][:1], Z_ABS=f["Z_ABS"][:1],
                dZ=f["dZ"][:1]) for f in frames]
    text = _header_yaml(1).replace("- Type: Reference", "- Type: Measurement")
    text = text.replace("TrackingInfo:\n- Type", "TrackingInfo:\n  Type").replace(
        "\n  Radius", "\n  Radius")  # a struct array of one: SnakeYAML writes a mapping
    trace = read_mtdat(write_mtdat(tmp_path / "one.mtdat", one, n_tracks=1, header=text))
    assert sorted(set(trace["bead"])) == ["1"] and trace.attrs["reference_beads"] == []


def test_truncated_record_is_dropped_with_a_warning(tmp_path):
    path = write_mtdat(tmp_path / "cut.mtdat", _frames(n_steps=1, per_step=10))
    raw = path.read_bytes()
    path.write_bytes(raw[:-7])
    with pytest.warns(sc.DataWarning, match=r"do not make a whole record.*dropped"):
        _, rec = read_mtdat_records(path)
    assert rec["Date"].size == 9


def test_bad_files_are_named(tmp_path):
    p = tmp_path / "x.mtdat"
    p.write_bytes(b"hello\n")
    with pytest.raises(DataError, match="no line '#!!#YAML_START'"):
        read_mtdat(p)
    p.write_bytes(b"#!!#YAML_START\nFileType: x\n")
    with pytest.raises(DataError, match="no line '#!!#YAML_END'"):
        read_mtdat(p)
    p.write_bytes(b"#!!#YAML_START\nFileType: x\n#!!#YAML_END\n")
    with pytest.raises(DataError, match="no 'Record' list"):
        read_mtdat(p)
    p.write_bytes(b"#!!#YAML_START\nFileType: x\nRecord: &a [1]\n#!!#YAML_END\n")
    with pytest.raises(DataError, match=r"line 3: YAML feature '&' is not supported"):
        read_mtdat(p)
    with pytest.raises(DataError, match="is a directory"):
        read_mtdat(tmp_path)
    with pytest.raises(TypeError, match="path must be a str or a path"):
        read_mtdat(None)
    frames = [{k: v for k, v in f.items()} for f in _frames(n_steps=1, per_step=3)]
    text = _header_yaml().replace("parameter: MagnetRotation", "parameter: MagnetAngle")
    q = write_mtdat(tmp_path / "no_rot.mtdat",
                    [dict(f, MagnetAngle=f["MagnetRotation"]) for f in frames], header=text)
    with pytest.raises(DataError, match="no record parameter 'MagnetRotation'"):
        read_mtdat(q)


def test_yaml_subset_parses_snakeyaml_scalars():
    doc = parse_yaml_subset("a: 'it''s'\nb: \"tab\\there\"\nc: -.inf\nd: ~\ne: true\n"
                            "f: {x: 1.5, y: plain text}\ng:\n- [1.0, 2.0]\n- [3.0, 4.0]\n")
    assert doc == {"a": "it's", "b": "tab\there", "c": float("-inf"), "d": None, "e": True,
                   "f": {"x": 1.5, "y": "plain text"}, "g": [[1.0, 2.0], [3.0, 4.0]]}
