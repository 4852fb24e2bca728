"""The shipped sample data: loadable by name, documented, reproducible, in the wheel."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import supercoil as sc
from supercoil.datasets import available_datasets, dataset_path, load_dataset, make

ROOT = Path(__file__).resolve().parent.parent


def test_every_recipe_is_shipped_and_nothing_else():
    assert available_datasets() == sorted(make.RECIPES)
    for name in available_datasets():
        assert dataset_path(name).is_file()


def test_unknown_dataset_names_the_available_ones():
    with pytest.raises(sc.DataError, match="rotation_curves"):
        dataset_path("no_such_set")
    with pytest.raises(sc.DataError):
        load_dataset(None)


def test_rotation_curves_is_a_tweezers_table_with_its_recipe():
    data = load_dataset("rotation_curves")
    recipe = make.RECIPES["rotation_curves"]
    assert data.attrs["units"]["force"] == "pN"
    assert data.attrs["units"]["extension"] == "um"
    assert data.attrs["provenance"]["recipe"]["seed"] == recipe["seed"]
    assert sorted(data["molecule"].unique()) == recipe["molecules"]
    assert sorted(data["force"].unique()) == recipe["forces"]
    assert len(data) == len(recipe["molecules"]) * len(recipe["forces"]) * 110


def test_regenerating_gives_the_shipped_numbers(tmp_path):
    path = make.write("rotation_curves", tmp_path)
    fresh, shipped = sc.read_tweezers_csv(path), load_dataset("rotation_curves")
    for column in ("force", "turns", "extension"):
        np.testing.assert_allclose(fresh[column], shipped[column], rtol=1e-12, atol=0)
    assert list(fresh["molecule"]) == list(shipped["molecule"])


def test_the_data_are_the_stated_model_plus_the_stated_noise():
    """Residuals against the hat curve of the recipe's parameters: mean 0, sd = the noise."""
    recipe = make.RECIPES["rotation_curves"]
    u = sc.ureg
    data = load_dataset("rotation_curves")
    true = sc.load_parameters("dna").replace(
        **{k: v * u.nm for k, v in recipe["replace"].items()})
    residuals = []
    for i, molecule in enumerate(recipe["molecules"]):
        for force in recipe["forces"]:
            rows = data[(data["molecule"] == molecule) & (data["force"] == force)]
            curve = sc.hat_curve(true, force * u.pN, rows["turns"] - recipe["turns_offset"][i])
            model = curve["extension"].to_numpy() + recipe["extension_offset"][i]
            residuals.append(rows["extension"].to_numpy() * 1e3 - model)  # um -> nm
    r = np.concatenate(residuals)
    noise = recipe["noise"]
    # 660 draws: the sample sd is within 10 % and the mean within 4 standard errors
    assert abs(r.std() / noise - 1) < 0.1, r.std()
    assert abs(r.mean()) < 4 * noise / np.sqrt(r.size), r.mean()


@pytest.mark.background("wheel")
def test_the_sample_is_shipped_in_the_wheel(installed_wheel):
    names, site, run = installed_wheel
    assert "supercoil/datasets/rotation_curves.csv" in names
    out = run("import supercoil, supercoil.datasets as d; "
              f"assert supercoil.__file__.startswith({str(site)!r}); "
              "print(len(d.load_dataset('rotation_curves')))")
    assert out.split() == ["660"]
