"""read_tweezers_csv: the table convention, and errors that name the problem, line and column."""

import re

import numpy as np
import pandas as pd
import pytest

import supercoil as sc
from supercoil.dna.tweezers import check_tweezers_frame
from supercoil.exceptions import DataError, DataWarning
from supercoil.tables import row_lines

GOOD = """\
# instrument: "MT-1"
molecule, force [pN], turns, extension [um], sigma [nm]
a, 0.5, -1.0, 0.61, 5
a, 0.5, 0.0, 0.62, 5

a, 0.5, 1.0, 0.61, 5
b, 0.3, 0.5, 0.55, 4
"""


def write(tmp_path, text, name="data.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_reads_the_table_convention_with_file_lines(tmp_path):
    df = sc.read_tweezers_csv(write(tmp_path, GOOD))
    assert list(df.columns) == ["molecule", "force", "turns", "extension", "sigma"]
    assert df.attrs["units"] == {"molecule": "", "force": "pN", "turns": "", "extension": "um",
                                 "sigma": "nm"}
    assert df.attrs["provenance"]["instrument"] == "MT-1"
    assert df.attrs["provenance"]["source"].endswith("data.csv")
    # the blank line 5 is skipped; the rows keep their file lines
    assert row_lines(df).tolist() == [3, 4, 6, 7]
    np.testing.assert_allclose(df["extension"], [0.61, 0.62, 0.61, 0.55])
    assert df["force"].dtype == float and df["turns"].dtype == float
    assert list(df["molecule"]) == ["a", "a", "a", "b"]


def test_angle_units_for_turns_are_accepted(tmp_path):
    df = sc.read_tweezers_csv(write(tmp_path, "force [pN],turns [rad],extension [nm]\n"
                                              "0.5,6.283185307179586,600\n"))
    assert df.attrs["units"]["turns"] == "rad"


@pytest.mark.parametrize(
    ("text", "pattern"),
    [
        # missing column: named, with the header line
        ("# a: 1\nforce [pN], extension [um]\n0.5, 0.6\n",
         r"line 2 \(header\): missing column 'turns'"),
        # non-numeric cell: value, line and column
        ("force [pN], turns, extension [um]\n0.5, 1, 0.6\n0.5, two, 0.6\n",
         r"line 3, column 'turns': non-numeric value 'two'"),
        # unknown unit
        ("force [pN], turns, extension [furlongz]\n0.5, 1, 0.6\n",
         r"line 1 \(header\), column 'extension': unknown unit 'furlongz'"),
        # wrong dimension
        ("force [nm], turns, extension [um]\n0.5, 1, 0.6\n",
         r"line 1 \(header\), column 'force': 'nm' has dimension \[length\]"),
        ("force [pN], turns [nm], extension [um]\n0.5, 1, 0.6\n",
         r"column 'turns': 'nm' has dimension"),
        ("force [pN], turns, extension\n0.5, 1, 0.6\n",
         r"column 'extension': no unit has dimension dimensionless"),
        # empty cell and NaN, with the file line (comments and a blank line before it)
        ("# a: 1\n# b: 2\nforce [pN], turns, extension [um]\n0.5, 1, 0.6\n\n0.5, , 0.6\n",
         r"line 6, column 'turns': missing value \(empty cell or NaN\)"),
        ("force [pN], turns, extension [um]\n0.5, 1, 0.6\n0.5, 2, NaN\n",
         r"line 3, column 'extension': missing value"),
        ("force [pN], turns, extension [um]\n0.5, 1, inf\n",
         r"line 2, column 'extension': non-finite value"),
        ("force [pN], turns, extension [um]\n-0.5, 1, 0.6\n",
         r"line 2, column 'force': force must be positive"),
        ("molecule, force [pN], turns, extension [um]\na, 0.5, 1, 0.6\n, 0.5, 1, 0.6\n",
         r"line 3, column 'molecule': missing label"),
        ("force [pN], turns, extension [um], sigma [pN]\n0.5, 1, 0.6, 1\n",
         r"column 'sigma': 'pN' has dimension"),
        ("# only: 1\n", r"no header line"),
        ("force [pN], turns, extension [um]\n", r"no data rows"),
    ],
    ids=["missing-column", "non-numeric", "unknown-unit", "force-wrong-dim", "turns-wrong-dim",
         "no-extension-unit", "empty-cell", "nan", "inf", "negative-force", "missing-molecule",
         "sigma-wrong-dim", "no-header", "no-rows"],
)
def test_loader_errors_name_problem_line_and_column(tmp_path, text, pattern):
    with pytest.raises(DataError, match=pattern) as exc:
        sc.read_tweezers_csv(write(tmp_path, text))
    assert "data.csv" in str(exc.value)


def test_missing_file_is_a_data_error(tmp_path):
    with pytest.raises(DataError, match="no such file"):
        sc.read_tweezers_csv(tmp_path / "nope.csv")


def test_drop_incomplete_warns_with_count_and_lines(tmp_path):
    text = ("force [pN], turns, extension [um]\n"
            "0.5, 1, 0.6\n"
            "0.5, , 0.6\n"
            "0.5, 3, 0.6\n"
            "0.5, 4, nan\n"
            "0.5, 5, 0.6\n")
    with pytest.raises(DataError, match="line 3"):
        sc.read_tweezers_csv(write(tmp_path, text))
    with pytest.warns(DataWarning, match=r"dropped 2 incomplete row\(s\).*line\(s\) 3, 5"):
        df = sc.read_tweezers_csv(write(tmp_path, text), drop_incomplete=True)
    assert list(df["turns"]) == [1.0, 3.0, 5.0]
    assert row_lines(df).tolist() == [2, 4, 6]


def test_drop_incomplete_does_not_hide_bad_cells(tmp_path):
    text = "force [pN], turns, extension [um]\n0.5, 1, 0.6\n0.5, x, 0.6\n0.5, 3, \n"
    with pytest.warns(DataWarning, match="dropped 1"), \
            pytest.raises(DataError, match=r"line 3, column 'turns': non-numeric value 'x'"):
        sc.read_tweezers_csv(write(tmp_path, text), drop_incomplete=True)


def test_round_trip_through_write_csv(tmp_path):
    from supercoil.dna.fitting import simulate_rotation_curves

    dna = sc.load_parameters("dna")
    df = simulate_rotation_curves(dna, [0.5] * sc.ureg.pN, points_per_force=20, seed=3,
                                  molecules=2, sigma_column=True)
    path = sc.write_csv(df, tmp_path / "sim.csv")
    back = sc.read_tweezers_csv(path)
    pd.testing.assert_frame_equal(back.reset_index(drop=True), df, check_dtype=False,
                                  rtol=1e-10)
    assert back.attrs["units"] == df.attrs["units"]
    assert back.attrs["provenance"]["seed"] == 3


def test_check_frame_names_index_rows_for_in_memory_tables():
    df = pd.DataFrame({"force": [0.5, 0.5], "turns": [1.0, np.nan], "extension": [600, 600]},
                      index=[10, 11])
    with pytest.raises(DataError, match="no attrs"):
        check_tweezers_frame(df)
    df.attrs["units"] = {"force": "pN", "turns": "", "extension": "nm"}
    with pytest.raises(DataError, match=re.escape("row 11, column 'turns': missing value")):
        check_tweezers_frame(df)


def test_molecule_labels_are_text_as_written(tmp_path):
    """Labels "1", "01", "1.0" are three molecules, not one."""
    text = ("molecule, force [pN], turns, extension [um]\n"
            "1, 0.5, 0, 0.6\n01, 0.5, 0, 0.6\n1.0, 0.5, 0, 0.6\n1, 0.5, 1, 0.6\n")
    df = sc.read_tweezers_csv(write(tmp_path, text))
    assert list(df["molecule"]) == ["1", "01", "1.0", "1"]
    assert df["molecule"].nunique() == 3


def test_extra_field_is_a_data_error_with_the_file_line(tmp_path):
    """Pandas' ParserError (wrong line number) becomes a DataError."""
    text = "# a: 1\nforce [pN], turns, extension [um]\n1, 0, 0.7\n1, 2, 1,68\n"
    with pytest.raises(DataError, match=r"data\.csv, line 4: 4 fields.*decimal comma"):
        sc.read_tweezers_csv(write(tmp_path, text))


def test_semicolon_file_missing_column_has_a_hint(tmp_path):
    text = "force [pN];turns;extension [um]\n0.5;1;0.6\n"
    with pytest.raises(DataError, match=r"missing column 'force'.*hint: the header uses ';'"):
        sc.read_tweezers_csv(write(tmp_path, text))
    text = "force (pN), turns, extension (um)\n0.5, 1, 0.6\n"
    with pytest.raises(DataError, match=r"missing column 'force'.*square brackets"):
        sc.read_tweezers_csv(write(tmp_path, text))


@pytest.mark.parametrize("header", ["turns", "turns [turn]", "turns []", "turns [dimensionless]"])
def test_turns_header_variants_count_turns(tmp_path, header):
    df = sc.read_tweezers_csv(write(tmp_path, f"force [pN], {header}, extension [um]\n"
                                              "0.5, 2.5, 0.6\n"))
    q = sc.ureg.Quantity(df["turns"].to_numpy(), df.attrs["units"]["turns"] or "dimensionless")
    assert sc.units.as_turns(q, "turns")[0] == pytest.approx(2.5)


def test_non_finite_and_non_positive_messages_print_plain_numbers():
    """Audit P5: no np.float64(...) reprs in messages."""
    df = pd.DataFrame({"force": [0.5, -0.5], "turns": [1.0, 2.0], "extension": [600, 600]})
    df.attrs["units"] = {"force": "pN", "turns": "", "extension": "nm"}
    with pytest.raises(DataError, match=r"force must be positive, got -0\.5$"):
        check_tweezers_frame(df)
    df = pd.DataFrame({"force": [0.5, 0.5], "turns": [1.0, np.inf], "extension": [600, 600]})
    df.attrs["units"] = {"force": "pN", "turns": "", "extension": "nm"}
    with pytest.raises(DataError, match=r"non-finite value inf$"):
        check_tweezers_frame(df)
