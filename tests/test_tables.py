"""The table convention and its CSV round trip."""

import numpy as np
import pandas as pd
import pytest

import supercoil as sc
from supercoil.tables import column_quantity, make_table, provenance


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
    """Audit B3: a decimal comma adds a field; the file line counts the comment lines."""
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
    """Audit B4: "1", "01" and "1.0" were all read as the number 1."""
    p = tmp_path / "m.csv"
    p.write_text("molecule,force [pN],turns,extension [um]\n1,1,0,0.7\n01,1,0,0.7\n"
                 "1.0,1,0,0.7\n,1,0,0.7\n")
    df = sc.read_csv(p)
    assert list(df["molecule"][:3]) == ["1", "01", "1.0"]
    assert pd.isna(df["molecule"].iloc[3])  # an empty cell stays missing
    assert df["force"].dtype.kind in "if"
    assert list(sc.read_csv(p, text_columns=())["molecule"][:3]) == [1, 1, 1]
