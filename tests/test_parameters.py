"""Parameter sets: loading, errors, and loading from an installed wheel."""

from pathlib import Path

import pytest

import supercoil as sc

ROOT = Path(__file__).resolve().parent.parent

ROD_TOML = """
kind = "ElasticRod"
title = "test rod"
[parameters]
radius = "{radius}"
length = "50 cm"
young_modulus = "4 MPa"
shear_modulus = "1.5 MPa"
[sources]
radius = "a"
length = "b"
young_modulus = "c"
shear_modulus = "d"
"""


def test_bundled_sets_are_listed():
    assert {"dna", "silicone_rubber_rod"} <= set(sc.available_parameter_sets())


def test_dna_seed_set_matches_model_section_6(ureg):
    dna = sc.load_parameters("dna")
    assert dna.length == 750 * ureg.nm
    assert dna.si.bending_persistence == pytest.approx(48e-9, rel=1e-6, abs=0)
    assert dna.si.twist_persistence == pytest.approx(86e-9, rel=1e-6, abs=0)
    assert dna.si.radius == pytest.approx(1.75e-9, rel=1e-6, abs=0)
    assert dna.si.temperature == 300.0
    assert dna.si.wlc_persistence == pytest.approx(52e-9, rel=1e-6, abs=0)


def test_rubber_rod_set_matches_model_section_4():
    rod = sc.load_parameters("silicone_rubber_rod")
    assert rod.si.radius == pytest.approx(1e-3)
    assert rod.si.length == pytest.approx(0.567)
    assert rod.si.young_modulus == pytest.approx(4.2e6)
    assert rod.si.shear_modulus == pytest.approx(1.51e6)
    assert rod.friction_coefficient == 0.5


def test_every_bundled_value_has_a_source():
    from supercoil.parameters import read_parameter_set

    for name in sc.available_parameter_sets():
        ps = read_parameter_set(name)
        assert set(ps.values) <= set(ps.sources)
        assert all(ps.sources[k].strip() for k in ps.values)


def test_load_from_path(tmp_path):
    p = tmp_path / "rod.toml"
    p.write_text(ROD_TOML.format(radius="2 mm"))
    assert sc.load_parameters(p).si.radius == pytest.approx(2e-3)
    assert sc.load_parameters(str(p)).si.radius == pytest.approx(2e-3)


@pytest.mark.parametrize(
    ("radius", "match"),
    [("2 furlongz", "unknown unit"), ("2 s", "wrong dimension"), ("-2 mm", "positive")],
)
def test_bad_values_give_parameter_errors(tmp_path, radius, match):
    p = tmp_path / "rod.toml"
    p.write_text(ROD_TOML.format(radius=radius))
    with pytest.raises(sc.ParameterError, match=match):
        sc.load_parameters(p)


def test_missing_key_and_missing_source(tmp_path):
    p = tmp_path / "rod.toml"
    p.write_text(ROD_TOML.format(radius="1 mm").replace('length = "50 cm"\n', "", 1))
    with pytest.raises(sc.ParameterError, match="missing key 'length'"):
        sc.load_parameters(p)
    p.write_text(ROD_TOML.format(radius="1 mm").replace('radius = "a"\n', ""))
    with pytest.raises(sc.ParameterError, match="no source line for 'radius'"):
        sc.load_parameters(p)


def test_unknown_name_and_unknown_key(tmp_path):
    with pytest.raises(sc.ParameterError, match=r"unknown parameter set 'nope'.*dna"):
        sc.load_parameters("nope")
    p = tmp_path / "rod.toml"
    p.write_text(ROD_TOML.format(radius="1 mm").replace("[sources]", 'colour = "red"\n[sources]'))
    with pytest.raises(sc.ParameterError, match="unknown key 'colour'"):
        sc.load_parameters(p)


MODEL_TOML = """kind = "DNAModel"
model = "ensemble"
[parameters]
twist_bend_softening = "1.5"
plectoneme_twist_persistence_ref = "{p0}"
[calibration]
torque_scale = {scale}
[sources]
twist_bend_softening = "a"
plectoneme_twist_persistence_ref = "b"
torque_scale = "c"
"""


def test_a_model_set_gives_the_model_with_its_values_in_si(tmp_path):
    from supercoil.dna.models import get_model
    from supercoil.parameters import read_parameter_set

    p = tmp_path / "m.toml"
    p.write_text(MODEL_TOML.format(p0="0.0124 um", scale=0.7))
    ps = read_parameter_set(p)
    assert ps.kind == "DNAModel" and ps.calibration == {"torque_scale": 0.7}
    m = ps.material
    want = get_model("ensemble", twist_bend_softening=1.5,
                     plectoneme_twist_persistence_ref=12.4e-9).values
    assert m.values == pytest.approx(want, rel=1e-15, abs=0)
    assert m.values["plectoneme_twist_persistence_ref"] == pytest.approx(12.4e-9, rel=1e-15, abs=0)
    assert m.values["domain_nucleation"] == get_model("ensemble").values["domain_nucleation"]
    bundled = sc.load_parameters("ensemble_qian2024_spread_fit")
    assert bundled.values["twist_bend_softening"] == 1.0  # the Moroz-Nelson floor
    text = read_parameter_set("ensemble_qian2024_spread_fit").describe()
    assert "torque_scale" in text and "0.684" in text and "calibration of the fit" in text


@pytest.mark.parametrize(("p0", "scale", "match"), [
    ("12.4 pN", 0.7, "wrong dimension, plectoneme_twist_persistence_ref is in nm"),
    ("12.4 nm", -1, "torque_scale must be a positive number"),
    ("12.4 nm", '"0.7"', "torque_scale must be a positive number"),
])
def test_bad_model_sets_give_parameter_errors(tmp_path, p0, scale, match):
    p = tmp_path / "m.toml"
    p.write_text(MODEL_TOML.format(p0=p0, scale=scale))
    with pytest.raises(sc.ParameterError, match=match):
        sc.load_parameters(p)


def test_model_set_names_its_unknown_model_key_and_calibration(tmp_path):
    p = tmp_path / "m.toml"
    good = MODEL_TOML.format(p0="12 nm", scale=0.7)
    for text, match in ((good.replace('"ensemble"', '"nope"'), "'model' must be one of"),
                        (good.replace("[calibration]", 'colour = "1"\n[calibration]'),
                         "unknown key 'colour' in \\[parameters\\]; model 'ensemble'"),
                        (good.replace("torque_scale = 0", "force_scale = 0"),
                         "unknown key 'force_scale' in \\[calibration\\]"),
                        (good.replace('torque_scale = "c"\n', ""),
                         "no source line for 'torque_scale'")):
        p.write_text(text)
        with pytest.raises(sc.ParameterError, match=match):
            sc.load_parameters(p)


@pytest.mark.background("wheel")
def test_parameter_sets_load_from_a_built_wheel(installed_wheel):
    """Build the wheel, unpack it away from the checkout and load both sets from it."""
    names, site, run = installed_wheel
    assert "supercoil/parameters/dna.toml" in names
    assert "supercoil/parameters/silicone_rubber_rod.toml" in names
    out = run("import supercoil, pathlib; "
              "p = pathlib.Path(supercoil.__file__).parent; "
              f"assert str(p).startswith({str(site)!r}), p; "
              "print(supercoil.load_parameters('dna').si.length, "
              "supercoil.load_parameters('silicone_rubber_rod').si.radius)")
    assert out.split() == ["7.5e-07", "0.001"]


def test_params_cli_prints_units_and_sources(capsys):
    from supercoil.cli import main

    assert main(["params", "silicone_rubber_rod"]) == 0
    out = capsys.readouterr().out
    assert "young_modulus" in out and "4.2 MPa" in out and "tensile test" in out
    assert main(["params", "nope"]) == 2
