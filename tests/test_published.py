"""Published data: the Figure S5 reader (on a synthetic workbook of the same layout and,
when the user gives it, on the real file) and the shipped summary numbers (published.csv).

References: the reader gives back the curves written into a workbook of the source's
layout (forces from the headers, two turns grids); the shipped numbers are those of
sheets S5C/S5D of the real file, cited on every line; the real curves' post-buckling
slopes measured by maxwell_check agree with the paper's own (S5C) within 3 %.
"""

import numpy as np
import pytest

import supercoil as sc
from supercoil.datasets import available_datasets, load_published_summary
from supercoil.datasets.published import (
    CITATION,
    ENV_VAR,
    read_published_curves,
    write_published_workbook,
)

FORCES = np.array([2.0, 1.5, 1.0, 0.75, 0.5, 0.3])  # pN, the source's column order


@pytest.fixture(scope="module")
def table():
    u = sc.ureg
    dna = sc.load_parameters("dna").replace(length=2190 * u.nm)
    return sc.simulate_rotation_curves(dna, FORCES * u.pN, model="marko2007",
                                       points_per_force=80, noise=2 * u.nm,
                                       torque_noise=0.2 * u.pN * u.nm, seed=2,
                                       extension_unit="nm")


@pytest.fixture(scope="module")
def workbook(table, tmp_path_factory):
    return write_published_workbook(table, tmp_path_factory.mktemp("s5") / "Figure S5.xlsx")


def test_reader_gives_back_the_curves_with_interpolated_torque(table, workbook):
    d = read_published_curves(workbook, points_per_force=None)
    assert d.attrs["units"] == {"force": "pN", "turns": "", "extension": "nm",
                                "torque": "pN nm"}
    prov = d.attrs["provenance"]
    assert prov["source"] == CITATION and "Qian_et_al" in prov["repository"]
    assert prov["file"] == "Source Data/Figure S5.xlsx"
    assert sorted(d["force"].unique()) == sorted(FORCES)  # read from the headers
    for f in FORCES:
        got = d[d["force"] == f]
        ref = table[table["force"] == f].sort_values("turns")
        even = ref.iloc[::2]
        # the extension rows are the even rows inside the torque sheet's (odd rows') range
        inside = even[(even["turns"] >= ref["turns"].iloc[1])
                      & (even["turns"] <= ref["turns"].iloc[-1 if len(ref) % 2 == 0 else -2])]
        np.testing.assert_allclose(got["extension"], inside["extension"], rtol=1e-12)
        # torque linearly interpolated between its neighbours: the model torque within noise
        np.testing.assert_allclose(got["torque"], np.interp(got["turns"], ref["turns"],
                                                            ref["torque"]), atol=1.0)
        assert prov["trimmed_points"][f"{f:g} pN"] == len(even) - len(inside)


def test_bin_means_and_options(workbook):
    d = read_published_curves(workbook, points_per_force=20, turns_range=(-3, None),
                              forces=[0.5, 1.0])
    assert sorted(d["force"].unique()) == [0.5, 1.0]
    assert d["turns"].min() >= -3
    assert all(15 <= n <= 20 for n in d.groupby("force").size())
    ext = read_published_curves(workbook, torque=False)
    assert "torque" not in ext.columns
    # what fit_hat_curves takes
    sc.read_tweezers_csv(sc.write_csv(d, workbook.parent / "d.csv"))


def test_missing_path_and_bad_files_are_named(tmp_path, monkeypatch):
    monkeypatch.delenv(ENV_VAR, raising=False)
    with pytest.raises(sc.DataError, match=ENV_VAR):
        read_published_curves()
    with pytest.raises(sc.DataError, match="no such file"):
        read_published_curves(tmp_path / "nothing.xlsx")
    bad = tmp_path / "bad.xlsx"
    bad.write_text("not a workbook")
    with pytest.raises(sc.DataError, match="cannot be read"):
        read_published_curves(bad)
    with pytest.raises(sc.DataError, match="points_per_force"):
        read_published_curves(bad, points_per_force=1)


def test_env_var_is_the_default_path(workbook, monkeypatch):
    monkeypatch.setenv(ENV_VAR, str(workbook))
    assert len(read_published_curves(points_per_force=10)) > 0


def test_summary_numbers_are_cited_on_every_line():
    s = load_published_summary()
    assert "published" not in available_datasets()  # not a rotation-curve data set
    assert len(s) == 12 and set(s["side"]) == {"+", "-"}
    assert s.attrs["units"]["slope"] == "nm/turn" and s.attrs["units"]["torque"] == "pN nm"
    assert all(src.startswith("table: Figure S5C/S5D source data, Qian et al.")
               for src in s["source"])
    assert "10.1101/2024.10.15.618270" in s.attrs["provenance"]["citation"]
    plus = s[s["side"] == "+"].sort_values("force")
    assert np.all(np.diff(plus["torque"]) > 0) and np.all(plus["slope"] < 0)


def test_shipped_numbers_are_those_of_the_real_file(qian_s5):
    import openpyxl

    wb = openpyxl.load_workbook(qian_s5, read_only=True, data_only=True)
    s = load_published_summary()
    for sheet, col in (("S5C", "slope"), ("S5D", "torque")):
        rows = list(wb[sheet].iter_rows(values_only=True))[2:]
        for r in rows:
            for side, (a, b) in (("+", (1, 2)), ("-", (3, 4))):
                row = s[(s["force"] == r[0]) & (s["side"] == side)].iloc[0]
                assert row[col] == r[a] and row[f"{col}_error"] == r[b]
    wb.close()


def test_real_curves_slopes_and_plateaus_match_the_papers_numbers(qian_s5):
    d = read_published_curves(qian_s5, points_per_force=200)
    assert len(d) > 1100 and sorted(d["force"].unique()) == sorted(FORCES)
    check = sc.maxwell_check(d).to_table()
    s = load_published_summary()
    for side in ("+",):
        mine = check[check["side"] == side].sort_values("force")
        paper = s[s["side"] == side].sort_values("force")
        np.testing.assert_allclose(mine["slope"], paper["slope"], rtol=0.03)
        np.testing.assert_allclose(mine["plateau_torque"], paper["torque"], rtol=0.03)


def test_real_curves_give_the_numbers_the_own_data_tutorial_quotes(qian_s5):
    """docs/tutorials/own-data.md quotes the fit of the real file (opt-in: slow, real data)."""
    import warnings

    u = sc.ureg
    data = read_published_curves(qian_s5, points_per_force=40, turns_range=(-3, None))
    dna = sc.load_parameters("dna").replace(length=6480 * 0.338 * u.nm)
    vary = ["length", "bending_persistence", "twist_persistence",
            "plectoneme_twist_persistence", "torque_scale"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fit = sc.fit_hat_curves(data, dna, vary=vary, model="marko2007",
                                bounds={"turns_offset": (-2, 2)}, fit_extension_offset=False)
    for name, value, err in (("length", 2124.7, 8.0), ("bending_persistence", 53.0, 1.7),
                             ("twist_persistence", 77.1, 1.4),
                             ("plectoneme_twist_persistence", 13.09, 0.19),
                             ("torque_scale", 0.800, 0.008), ("turns_offset", 0.46, 0.09)):
        assert fit.parameters[name].m == pytest.approx(value, abs=err / 10), name
        assert fit.stderr[name].m == pytest.approx(err, rel=0.1), name
    assert any("0.1909 turn from the torque zero crossing" in n for n in fit.notes)
    prof = fit.profile("plectoneme_twist_persistence")
    assert (round(prof.lower_bound, 2), round(prof.upper_bound, 2)) == (12.90, 13.28)
    # the default offsets: the length runs away along the extension offset, named
    with warnings.catch_warnings(), pytest.raises(sc.FitError, match="the length ran from"):
        warnings.simplefilter("ignore")
        sc.fit_hat_curves(data, dna, vary=vary[:4], model="marko2007",
                          bounds={"turns_offset": (-2, 2)})
