"""A DNA model registered from outside the package runs through hat_curve, the fits and the CLI.

The toy is a rod that never buckles: extension ``z = L / (1 + (N / w)^2)``
(a Lorentzian in the turns of width ``w``, its own parameter), torque
``C 2 pi N / L``, no plectoneme (``uses_interaction = False``). Closed forms
make every number checkable.
"""

import warnings
from typing import ClassVar

import numpy as np
import pytest

import supercoil as sc
from supercoil.cli import main
from supercoil.dna.model_parameters import ModelParameter
from supercoil.dna.models import Buckling, DNAModel, HatPoints
from supercoil.exceptions import FitWarning, ModelError


class ToyRod(DNAModel):
    name = "toy-rod"
    summary = "test toy: a rod that never buckles, Lorentzian extension in the turns"
    parameters: ClassVar[dict] = {
        "width": ModelParameter("width", "", 20.0, 1.0, 1000.0,
                                "half width of the extension (number of turns)", "test choice"),
    }
    uses_interaction = False

    def _buckling(self, force, dna, thermal, interaction):
        inf = np.full(np.shape(force), np.inf)
        return Buckling(inf, inf, np.zeros(np.shape(force)))

    def _points(self, turns, force, dna, thermal, interaction, short_tail_length):
        turns = np.asarray(turns, dtype=float)
        z = dna.length / (1.0 + (turns / self.values["width"]) ** 2)
        torque = dna.torsional_rigidity * 2 * np.pi * turns / dna.length
        zeros = np.zeros(turns.shape)
        return HatPoints(z, torque, zeros, zeros.astype(np.int8), zeros.astype(bool),
                         z / dna.length)


@pytest.fixture(autouse=True, scope="module")
def _toy_registered():
    """The toy is registered for this module's tests only: the registry is global, and
    other tests (the README's model list) check it holds the package's own models."""
    from supercoil.dna.models import unregister_model

    sc.register_model(ToyRod, replace=True)
    yield
    unregister_model(ToyRod.name)

WIDTH = 3.0  # true width of the toy data, turns
FORCES = [0.3, 0.5, 0.7]  # pN
TURNS = np.linspace(-4.5, 4.5, 41)  # |N - N0| < 5: the straight tail stays below the Euler
# torque (the fits apply the shared limits at the offset turns)


def toy_data(dna, seed, width=WIDTH, noise=3.0):
    u = sc.ureg
    return sc.simulate_rotation_curves(dna, FORCES * u.pN, turns=TURNS, noise=noise * u.nm,
                                       turns_offset=0.3, extension_offset=20 * u.nm, seed=seed,
                                       model=ToyRod(width=width))


def test_hat_curve_of_the_toy_is_its_closed_form(base):
    u = sc.ureg
    assert "toy-rod" in sc.available_models()
    df = sc.hat_curve(base, 0.5 * u.pN, TURNS, model="toy-rod")
    L = base.length.m_as("nm")
    np.testing.assert_allclose(df["extension"], L / (1 + (TURNS / 20.0) ** 2), rtol=1e-12)
    C = base.twist_persistence.m_as("nm") * base.kT.m_as("pN nm")  # pN nm^2
    np.testing.assert_allclose(df["torque"], C * 2 * np.pi * TURNS / L, rtol=1e-12)
    assert set(df["phase"]) == {"stretched"}
    narrow = sc.hat_curve(base, 0.5 * u.pN, [5.0], model=ToyRod(width=5))
    assert narrow["extension"].iloc[0] == pytest.approx(L / 2, rel=1e-12)
    with pytest.raises(ModelError, match="takes no interaction"):
        sc.hat_curve(base, 0.5 * u.pN, TURNS, model="toy-rod", interaction="other")


def test_fit_recovers_the_toy_parameter_by_name(base):
    df = toy_data(base, seed=3)
    r = sc.fit_hat_curves(df, base, vary=["width", "length"], model="toy-rod")
    assert r.model.name == "toy-rod"
    assert set(r.parameters) == {"width", "length", "turns_offset", "extension_offset"}
    assert r.parameters["width"].check("[]")
    for name, true in (("width", WIDTH), ("length", base.length.m_as("nm")),
                       ("turns_offset", 0.3), ("extension_offset", 20.0)):
        assert abs(r.parameters[name].m - true) < 4 * r.stderr[name].m, name
    assert r.model.values["width"] == pytest.approx(r.parameters["width"].m)
    assert "width" in r.report() and "toy-rod" in r.report()
    # a model instance is a start value; fixing the parameter by name holds it
    held = sc.fit_hat_curves(df, base, vary=["length"], fixed={"width": 3},
                             model=ToyRod(width=30))
    assert held.fixed["width"].m == pytest.approx(3.0)
    assert held.model.values["width"] == 3.0


def test_toy_parameter_outside_its_declared_range_is_named(base):
    df = toy_data(base, seed=3)
    with pytest.raises(ValueError, match=r"toy-rod\.width .* outside its allowed range"):
        sc.fit_hat_curves(df, base, vary=["width"], model=ToyRod(width=2000))


def test_hat_command_accepts_a_model_registered_at_run_time(tmp_path, base):
    out = tmp_path / "out"
    assert main(["hat", "--model", "toy-rod", "--force", "0.5pN", "--turns=-5:5:1",
                 "--out", str(out), "--no-plot"]) == 0
    df = sc.read_csv(out / "hat_curve.csv")
    L = base.length.m_as("nm")
    np.testing.assert_allclose(df["extension"], L / (1 + (np.arange(-5, 6) / 20.0) ** 2),
                               rtol=1e-10)
    assert df.attrs["provenance"]["model"] == "toy-rod"


def test_hat_command_names_unknown_models(tmp_path, capsys):
    assert main(["hat", "--model", "no-such-model", "--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "'no-such-model' is not a registered model" in err and "toy-rod" in err
    assert main(["hat", "--interaction", "none-such", "--out", str(tmp_path)]) == 2
    assert "hard-core" in capsys.readouterr().err


def test_fit_command_with_the_toy_model(tmp_path, base):
    path = sc.write_csv(toy_data(base, seed=4), tmp_path / "toy.csv")
    out = tmp_path / "fit"
    assert main(["fit", str(path), "--model", "toy-rod", "--vary", "width", "length",
                 "--out", str(out), "--no-plot"]) == 0
    params = sc.read_csv(out / "fit_parameters.csv")
    assert abs(params["width"].iloc[0] - WIDTH) < 4 * params["width_stderr"].iloc[0]
    assert params.attrs["units"]["width"] == ""


#: what each model fits in the comparison (a model registered later: C_t and its own parameters)
COMPARE_VARY = {"li-zhao": ["twist_persistence", "radius"],
                "free-energy": ["twist_persistence", "radius"],
                "marko2007": ["twist_persistence", "plectoneme_twist_persistence"],
                "toy-rod": ["length", "width"]}


def _vary():
    from supercoil.dna.models import get_model

    return {m: COMPARE_VARY.get(m, ["twist_persistence", *get_model(m).parameters])
            for m in sc.available_models()}


def _compare(data, base, models=None):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        table = sc.compare_models(data, base, models or ["li-zhao", "toy-rod"],
                                  vary=_vary()).table
    return table, [str(w.message) for w in caught if issubclass(w.category, FitWarning)]


#: the closed-form and one-solve models (an ensemble fit costs ~100x one of these; its
#: parameter recovery is tested in tests/dna/test_ensemble.py)
COMPARED = ("free-energy", "li-zhao", "marko2007", "toy-rod")


@pytest.mark.parametrize("truth", COMPARED)
def test_compare_models_prefers_the_model_that_made_the_data(base, true_dna, truth):
    """Every registered model (li-zhao, free-energy, marko2007 on main, the toy): data made
    by model X (5 nm noise, 180 points) are best described by X, by AIC and BIC."""
    u = sc.ureg
    if truth == "toy-rod":
        data = toy_data(base, seed=5)
    else:
        data = sc.simulate_rotation_curves(true_dna, FORCES * u.pN, points_per_force=60,
                                           noise=5 * u.nm, seed=2, model=truth)
    table, fit_warnings = _compare(data, base, list(COMPARED))
    assert table["success"].all(), table["error"]
    assert table.loc[0, "model"] == truth
    assert (table["delta_aic"].iloc[1:] > 10).all() and (table["delta_bic"].iloc[1:] > 10).all()
    # the true model passes the runs test; the worst one fails it and says so
    assert not any(m.startswith(f"model {truth}: goodness") for m in fit_warnings)
    worst = table["model"].iloc[-1]
    assert any(m.startswith(f"model {worst}: goodness of fit") for m in fit_warnings)


def test_compare_table_statistics_are_lmfits(base, true_dna):
    u = sc.ureg
    hat = sc.simulate_rotation_curves(true_dna, FORCES * u.pN, points_per_force=40,
                                      noise=5 * u.nm, seed=6)
    table, _ = _compare(hat, base)
    for _, row in table.iterrows():
        # unit weights: the criteria use the sum of squares on the 1 nm scale (the
        # table's chi_square is dimensionless, nfree)
        n, k = row["ndata"], row["nparams"]
        chi2 = row["residual_rms"] ** 2 * (n - k)
        assert row["aic"] == pytest.approx(n * np.log(chi2 / n) + 2 * k, rel=1e-12)
        assert row["bic"] == pytest.approx(n * np.log(chi2 / n) + np.log(n) * k, rel=1e-12)
        assert row["reduced_chi_square"] == pytest.approx(1.0, rel=1e-12)
    li = table.set_index("model").loc["li-zhao"]
    assert li["nparams"] == 4 and np.isnan(li["width"])
    assert table.attrs["units"]["width"] == ""
    assert table.attrs["units"]["twist_persistence_stderr"] == "nm"
    assert "lmfit" in table.attrs["provenance"]["criteria"]


def test_fit_command_compares_models(tmp_path, true_dna):
    u = sc.ureg
    hat = sc.simulate_rotation_curves(true_dna, FORCES * u.pN, points_per_force=40,
                                      noise=5 * u.nm, seed=7)
    path = sc.write_csv(hat, tmp_path / "hat.csv")
    out = tmp_path / "cmp"
    assert main(["fit", str(path), "--model", "li-zhao", "--model", "toy-rod",
                 "--vary", "twist_persistence", "radius", "--out", str(out)]) == 0
    table = sc.read_csv(out / "fit_comparison.csv")
    assert list(table["model"]) == ["li-zhao", "toy-rod"]
    assert (out / "fit_comparison.png").stat().st_size > 0
    report = (out / "fit_report.txt").read_text()
    assert "[[Model comparison]]" in report and "==== model toy-rod ====" in report


def test_fit_many_with_the_toy_model(base):
    u = sc.ureg
    df = sc.simulate_rotation_curves(base, FORCES * u.pN, turns=TURNS, noise=3 * u.nm,
                                     molecules=2, seed=8, model=ToyRod(width=WIDTH))
    table = sc.fit_many(df, base, vary=["width", "length"], model="toy-rod")
    assert table["success"].all() and table.attrs["provenance"]["model"] == "toy-rod"
    assert (abs(table["width"] - WIDTH) < 4 * table["width_stderr"]).all()


def test_fit_command_names_unknown_models_and_interactions(tmp_path, base, capsys):
    path = sc.write_csv(toy_data(base, seed=4), tmp_path / "toy.csv")
    assert main(["fit", str(path), "--model", "nope", "--out", str(tmp_path / "o")]) == 2
    assert "--model 'nope' is not a registered model" in capsys.readouterr().err
    assert main(["fit", str(path), "--interaction", "nope", "--out", str(tmp_path / "o")]) == 2
    assert "--interaction 'nope' is not a registered interaction" in capsys.readouterr().err


def test_jacobian_columns_of_a_model_parameter(base):
    from supercoil.dna.fitting import fit as fitting
    from supercoil.dna.fitting.model import HatCurveModel

    spec = fitting.prepare(toy_data(base, seed=3), base, vary=["width", "length"],
                           model="toy-rod", start={"turns_offset": 0.2})
    prob = HatCurveModel(spec.data, spec.params, spec.dna, spec.model, spec.interaction,
                         spec.thermal)
    u = spec.params.vector()
    u[0] = WIDTH / spec.params["width"].scale  # near the truth, where the curve bends
    J = prob.jacobian(u)
    for j in range(len(u)):
        up, um = u.copy(), u.copy()
        up[j] += 1e-5
        um[j] -= 1e-5
        ref = (prob.residual(up) - prob.residual(um)) / 2e-5
        np.testing.assert_allclose(J[:, j], ref, rtol=0, atol=1e-4 * np.abs(ref).max(),
                                   err_msg=prob.names[j])
    # closed form of the width column: dz/dw = 2 L N^2 / (w^3 (1 + (N/w)^2)^2)
    N = spec.data.turns - spec.params["turns_offset"].value
    w, L = WIDTH, base.length.m_as("m")
    dz = 2 * L * N**2 / (w**3 * (1 + (N / w) ** 2) ** 2)
    np.testing.assert_allclose(J[:, 0], dz * spec.params["width"].scale / spec.data.sigma,
                               rtol=1e-4, atol=1e-6 * np.abs(J[:, 0]).max())


def test_a_fixed_model_parameter_in_params_is_used(base):
    df = toy_data(base, seed=3)
    params = sc.fit_parameters(df, base, vary=["width", "length"], model="toy-rod")
    params["width"].vary = False
    params["width"].value = WIDTH
    r = sc.fit_hat_curves(df, base, params=params, model="toy-rod")  # instance default: 20
    ref = sc.fit_hat_curves(df, base, vary=["length"], model=ToyRod(width=WIDTH))
    assert r.parameters["length"].m == pytest.approx(ref.parameters["length"].m, rel=1e-9)
