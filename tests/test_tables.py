"""The table convention and its CSV round trip."""

import numpy as np
import pandas as pd
import pytest

import supercoil as sc
from supercoil.tables import column_quantity, line_runs, make_table, provenance, row_lines


def _table():
    return make_table(
        {"s": np.linspace(0, 1, 5), "pitch": np.linspace(10, 20, 5), "phase": list("abcde")},
        {"s": "mm", "pitch": "mm", "phase": ""},
        provenance(sc.load_parameters("silicone_rubber_rod"), turns=40),
    )


def test_make_table_records_units_and_provenance():
    df = _table()
    assert df.attrs["units"] == {"s": "mm", "pitch": "mm", "phase": ""}
    prov = df.attrs["provenance"]
    assert prov["supercoil_version"] == sc.__version__
    assert prov["parameters"]["kind"] == "ElasticRod"
    assert prov["parameters"]["young_modulus"].endswith("MPa")
    assert prov["turns"] == 40


def test_make_table_requires_a_unit_for_every_column():
    with pytest.raises(ValueError, match="no unit"):
        make_table({"a": [1.0]}, {})


def test_csv_round_trip(tmp_path):
    df = _table()
    path = sc.write_csv(df, tmp_path / "t.csv")
    text = path.read_text()
    assert "s [mm],pitch [mm],phase" in text
    assert text.startswith("# ")
    back = sc.read_csv(path)
    pd.testing.assert_frame_equal(back, df, check_exact=False, rtol=1e-12)
    assert back.attrs["units"] == df.attrs["units"]
    assert back.attrs["provenance"] == df.attrs["provenance"]


def test_column_quantity(ureg):
    q = column_quantity(_table(), "pitch")
    assert q.units == ureg.mm
    assert q[-1].m_as("m") == pytest.approx(0.02)


def test_read_csv_without_provenance_and_with_plain_comments(tmp_path):
    p = tmp_path / "x.csv"
    p.write_text("# measured on rig 2\nforce [pN],turns,extension [um]\n1,0,0.7\n")
    df = sc.read_csv(p)
    assert df.attrs["units"] == {"force": "pN", "turns": "", "extension": "um"}
    assert df.attrs["provenance"]["comments"] == ["measured on rig 2"]


def test_read_csv_errors(tmp_path):
    with pytest.raises(sc.DataError, match="no such file"):
        sc.read_csv(tmp_path / "missing.csv")
    p = tmp_path / "empty.csv"
    p.write_text("# only a comment\n")
    with pytest.raises(sc.DataError, match="no header"):
        sc.read_csv(p)


def test_write_csv_requires_units(tmp_path):
    with pytest.raises(ValueError, match="attrs"):
        sc.write_csv(pd.DataFrame({"a": [1]}), tmp_path / "a.csv")


def test_read_csv_extra_field_names_the_file_line(tmp_path):
    """A decimal comma adds a field; the file line counts the comment lines."""
    p = tmp_path / "dc.csv"
    p.write_text("# a: 1\n# b: 2\nforce [pN],turns,extension [um]\n1,0,0.7\n1,2,1,68\n")
    with pytest.raises(sc.DataError, match=r"dc\.csv, line 5: 4 fields, but the header "
                       r"\(line 3\) has 3 \(a decimal comma") as exc:
        sc.read_csv(p)
    assert "hint" not in str(exc.value)  # the header itself is fine
    # every row with one extra field: pandas would silently make it the index
    p.write_text("force [pN],turns,extension [um]\n1,0,0,7\n1,2,0,68\n")
    with pytest.raises(sc.DataError, match=r"line 2: 4 fields"):
        sc.read_csv(p)


def test_read_csv_hints_at_semicolons_and_round_brackets(tmp_path):
    p = tmp_path / "eu.csv"
    p.write_text("# exported\nforce (pN);turns;extension (um)\n1;0;0,7\n1;2;0,68\n")
    with pytest.raises(sc.DataError, match=r"line 3: 2 fields") as exc:
        sc.read_csv(p)
    msg = str(exc.value)
    assert "';' as delimiter" in msg and "'force [pN]', not 'force (pN)'" in msg


def test_read_csv_not_utf8_names_the_line(tmp_path):
    p = tmp_path / "latin1.csv"
    p.write_bytes("force [pN],turns,extension [um]\n1,0,0.7\n# \xb5m\n".encode("latin-1"))
    with pytest.raises(sc.DataError, match=r"latin1\.csv, line 3: not UTF-8 text"):
        sc.read_csv(p)


def test_read_csv_keeps_molecule_labels_as_written(tmp_path):
    """"1", "01" and "1.0" were all read as the number 1."""
    p = tmp_path / "m.csv"
    p.write_text("molecule,force [pN],turns,extension [um]\n1,1,0,0.7\n01,1,0,0.7\n"
                 "1.0,1,0,0.7\n,1,0,0.7\n")
    df = sc.read_csv(p)
    assert list(df["molecule"][:3]) == ["1", "01", "1.0"]
    assert pd.isna(df["molecule"].iloc[3])  # an empty cell stays missing
    assert df["force"].dtype.kind in "if"
    assert list(sc.read_csv(p, text_columns=())["molecule"][:3]) == [1, 1, 1]


# --- CR-only files, write_csv arguments, plain attrs -----------------------------------------


def test_read_tweezers_csv_reads_a_cr_only_file_with_its_lines(tmp_path):
    """Old Mac line ends (bare CR): read, with the file lines of the rows (was _csv.Error)."""
    path = tmp_path / "mac.csv"
    path.write_bytes(b"# x: 1\rmolecule,force [pN],turns,extension [um]\rm1,0.5,-1,0.4\r\r"
                     b"m1,0.5,0,0.5\r")
    df = sc.read_tweezers_csv(path)
    assert df["extension"].tolist() == [0.4, 0.5]
    assert df.attrs["provenance"]["x"] == 1
    assert row_lines(df).tolist() == [3, 5]


def test_read_tweezers_csv_cr_only_file_error_names_the_line(tmp_path):
    path = tmp_path / "mac.csv"
    path.write_bytes(b"force [pN],turns,extension [um]\r0.5,-1,0.4\r0.5,x,0.5\r")
    with pytest.raises(sc.DataError, match=r"line 3.*'turns'"):
        sc.read_tweezers_csv(path)


@pytest.mark.parametrize("df", [{"a": [1.0]}, None, [1.0]])
def test_write_csv_rejects_a_non_table_by_name(tmp_path, df):
    with pytest.raises(TypeError, match=r"df must be a pandas DataFrame.*make_table"):
        sc.write_csv(df, tmp_path / "x.csv")


def test_write_csv_names_a_directory_path(tmp_path):
    with pytest.raises(ValueError, match="is a directory; give a file name"):
        sc.write_csv(_table(), tmp_path)
    with pytest.raises(TypeError, match="path must be a str or a path"):
        sc.write_csv(_table(), None)
    (tmp_path / "f").write_text("")
    with pytest.raises(ValueError, match="cannot write"):
        sc.write_csv(_table(), tmp_path / "f" / "x.csv")  # a parent that is a file


def _plain(value):
    """True if ``value`` is made of JSON-like plain Python values only."""
    if isinstance(value, dict):
        return all(isinstance(k, str) and _plain(v) for k, v in value.items())
    if isinstance(value, list | tuple):
        return all(_plain(v) for v in value)
    return value is None or type(value) in (str, int, float, bool)


def _public_tables(tmp_path):
    """One table from every public producer of tables (readers, models, simulators)."""
    import warnings

    from supercoil import traces

    u = sc.ureg
    dna = sc.load_parameters("dna")
    curves = sc.simulate_rotation_curves(dna, [0.5, 1.0] * u.pN, seed=1)
    path = sc.write_csv(curves, tmp_path / "curves.csv")
    rec = traces.simulate_recording(molecules=1, reference=1, seed=3, points_per_force=4)
    folder = traces.write_synthetic_magscope(tmp_path / "ms", rec).path.parent
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", sc.DataWarning)
        trace = traces.read_magscope(folder, reference_beads=rec.reference_beads)
        calisto = traces.read_calisto(
            traces.write_synthetic_calisto(tmp_path / "c" / "rot.h5", rec).path)
    cal = traces.synthetic_calibration()
    return {
        "read_tweezers_csv": sc.read_tweezers_csv(path),
        "read_csv": sc.read_csv(path),
        "simulate_rotation_curves": curves,
        "hat_curve": sc.hat_curve(dna, [0.5, 1.0] * u.pN, [0, 5, 10]),
        "read_magscope": trace,
        "read_calisto": calisto,
        "find_plateaus": traces.find_plateaus(trace),
        "rotation_curves": traces.rotation_curves(trace, calibration=cal),
    }


def test_every_public_table_holds_plain_attrs_and_concatenates(tmp_path):
    """attrs hold plain JSON-like values only; pd.concat of two tables works (was ValueError)."""
    import json

    for name, table in _public_tables(tmp_path).items():
        assert _plain(table.attrs), (name, table.attrs)
        json.dumps(table.attrs)
        both = pd.concat([table, table], ignore_index=True)
        assert len(both) == 2 * len(table), name
        assert both.attrs == table.attrs, name  # equal attrs are kept
        table.copy()  # a deep copy of the attrs


def test_concat_of_two_read_files_and_the_file_lines(tmp_path):
    a = tmp_path / "a.csv"
    b = tmp_path / "b.csv"
    a.write_text("force [pN],turns,extension [um]\n0.5,0,0.4\n\n0.5,1,0.39\n")
    b.write_text("force [pN],turns,extension [um]\n0.6,0,0.45\n")
    da, db = sc.read_tweezers_csv(a), sc.read_tweezers_csv(b)
    assert da.attrs["lines"] == [[2, 2], [4, 4]] and db.attrs["lines"] == [[2, 2]]
    both = pd.concat([da, db], ignore_index=True)
    assert both["extension"].tolist() == [0.4, 0.39, 0.45]
    assert row_lines(both) is None  # lines of one file no longer match the rows


def test_line_runs_round_trip():
    lines = np.array([3, 4, 5, 9, 11, 12])
    runs = line_runs(lines)
    assert runs == [[3, 5], [9, 9], [11, 12]]
    assert all(type(v) is int for r in runs for v in r)
    frame = pd.DataFrame({"a": np.zeros(6)})
    frame.attrs["lines"] = runs
    assert row_lines(frame).tolist() == lines.tolist()
