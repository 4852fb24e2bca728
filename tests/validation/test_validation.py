"""The shipped published measurements and the validation command (issue 13)."""

import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main
from supercoil.validation import DEFAULT_CONFIGS, load_published, validate

READ_FROM = {"table", "text", "text (abstract)", "text (figure legend)", "digitised"}


def test_published_values_load_with_units_and_a_source_on_every_row():
    df = load_published()
    assert len(df) > 0
    assert df.attrs["units"]["force"] == "pN" and df.attrs["units"]["salt"] == "mM"
    assert (df["source"].str.len() > 20).all()  # authors/title, journal, volume, page, year
    assert df["source"].str.contains(r"\(\d{4}\)").all()  # a year on every row
    assert set(df["read_from"]) <= READ_FROM
    assert np.isfinite(df["value"]).all()
    for unit in set(df["unit"]) - {""}:
        sc.ureg.Unit(unit)  # every row's unit parses


def test_validate_predicts_every_row_or_says_why():
    table = validate(configs=(("li-zhao", "dna", "hard-core"), ("marko2007", "dna", None)))
    assert len(table) == 2 * len(load_published())
    missing = table[~np.isfinite(table["predicted"])]
    assert (missing["note"].str.len() > 0).all()
    rel = table["predicted"] / table["measured"] - 1
    np.testing.assert_allclose(table["relative_error"], rel, equal_nan=True)
    # C_eff at 15 pN from the stretched-phase torque equals the Moroz-Nelson C_eff (li-zhao)
    dna = sc.load_parameters("dna")
    c = sc.effective_twist_rigidity(dna, 15 * sc.ureg.pN).m_as("pN nm^2")
    row = table[(table["model"] == "li-zhao") & (table["force"] == 15)
                & (table["unit"] == "pN nm^2")]
    assert row["predicted"].to_numpy() == pytest.approx(c, rel=1e-9)


def test_default_configs_name_bundled_sets_and_registered_models():
    for model, set_name, _ in DEFAULT_CONFIGS:
        assert model in sc.available_models()
        assert set_name in sc.available_parameter_sets()


def test_validate_command_writes_table_and_figure(tmp_path, capsys):
    assert main(["validate", "--out", str(tmp_path)]) == 0
    df = sc.read_csv(tmp_path / "validation.csv")
    assert {"model", "predicted", "relative_error", "source"} <= set(df.columns)
    assert (tmp_path / "validation.png").stat().st_size > 10_000
    assert "effective_twist_persistence" in capsys.readouterr().out
