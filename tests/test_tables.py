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
