"""FitParameter / FitParameters: vector view, tables, params= full control, model parameters."""

import dataclasses

import numpy as np
import pytest
from fitting_helpers import simulate

import supercoil as sc
from supercoil.dna.fitting import DNA_FIELDS, PLAUSIBLE, FitParameter, FitParameters
from supercoil.exceptions import FitError, FitWarning


def test_vector_round_trip_uses_the_scales():
    ps = FitParameters([
        FitParameter("radius", 2e-9, "nm", scale=1.75e-9),
        FitParameter("length", 7.5e-7, "nm", vary=False, scale=7.5e-7),
        FitParameter("turns_offset", 0.4, "turn", shared="per-molecule", molecule=0,
                     owner="offset", min=-1, max=1),
    ])
    assert ps.free == ["radius", "turns_offset"]
    np.testing.assert_allclose(ps.vector(), [2 / 1.75, 0.4])
    lo, hi = ps.bounds_vector()
    np.testing.assert_allclose(lo, [-np.inf, -1]) and np.testing.assert_allclose(hi, [np.inf, 1])
    ps.set_vector([1.0, -0.2], stderr=[1e-10, 0.01])
    assert ps["radius"].value == pytest.approx(1.75e-9, rel=1e-6, abs=0)
    assert ps["turns_offset"].value == -0.2
    assert ps["radius"].stderr == 1e-10
    frame = ps.to_frame()
    assert frame.loc["radius", "value"] == pytest.approx(1.75)  # display unit nm
    assert frame.loc["radius", "stderr"] == pytest.approx(0.1)
    assert frame.loc["turns_offset", "value"] == pytest.approx(-0.2)  # turns, not radians
    assert "radius" in repr(ps)
    other = ps.copy()
    other["radius"].value = 5.0
    assert ps["radius"].value == pytest.approx(1.75e-9, rel=1e-6, abs=0)


def test_parameter_declarations_are_checked():
    with pytest.raises(ValueError, match="shared must be one of"):
        FitParameter("radius", 1e-9, "nm", shared="per-bead")
    ps = FitParameters([FitParameter("radius", 1e-9, "nm")])
    with pytest.raises(ValueError, match="already exists"):
        ps.add(FitParameter("radius", 1e-9, "nm"))
    with pytest.raises(TypeError, match="must be a FitParameter named"):
        ps["length"] = FitParameter("radius", 1e-9, "nm")
    with pytest.raises(KeyError, match="no fit parameter 'pitch'"):
        ps["pitch"]


def test_plausible_limits_are_declared_with_a_reason():
    for name in (*DNA_FIELDS, "turns_offset", "extension_offset"):
        lo, hi, reason = PLAUSIBLE[name]
        assert lo < hi and reason
    p = FitParameter("radius", 0.03e-9, "nm", plausible=PLAUSIBLE["radius"][:2],
                     plausible_source=PLAUSIBLE["radius"][2])
    msg = p.implausible()
    assert "radius = 0.03 nm" in msg and "plausible lower limit 0.4375 nm" in msg
    assert p.implausible(2e-9) is None
    assert "upper" in p.implausible(7e-9)  # at the limit counts


def test_params_give_the_same_fit_as_the_keywords(data, base, result):
    params = sc.fit_parameters(data, base, vary=["twist_persistence", "radius"])
    assert params.free == ["twist_persistence", "radius", "turns_offset", "extension_offset"]
    assert not params["turns_offset"].given  # guessed by the fit
    r = sc.fit_hat_curves(data, base, params=params)
    for name in result.parameters:
        assert r.parameters[name].m == pytest.approx(result.parameters[name].m, rel=1e-12, abs=0)
        assert r.stderr[name].m == pytest.approx(result.stderr[name].m, rel=1e-12, abs=0)
    assert params["radius"].value == base.radius.m_as("m")  # the caller's set is not changed
    assert r.params["radius"].value == pytest.approx(result.parameters["radius"].m_as("m"),
                                                     rel=1e-6, abs=0)
    with pytest.raises(FitError, match="either params= or vary"):
        sc.fit_hat_curves(data, base, vary=["radius"], params=params)


def test_editing_params_equals_fixed_and_bounds(true_dna, base):
    u = sc.ureg
    df = simulate(true_dna, seed=3, points_per_force=60)
    ref = sc.fit_hat_curves(df, base, vary=["twist_persistence"],
                            fixed={"radius": 2 * u.nm, "turns_offset": 0.4},
                            bounds={"twist_persistence": (50 * u.nm, 150 * u.nm)})
    params = sc.fit_parameters(df, base.replace(radius=2 * u.nm), vary=["twist_persistence"])
    params["turns_offset"] = dataclasses.replace(params["turns_offset"], vary=False, value=0.4)
    params["twist_persistence"].min, params["twist_persistence"].max = 50e-9, 150e-9
    r = sc.fit_hat_curves(df, base.replace(radius=2 * u.nm), params=params)
    for name in ref.parameters:
        assert r.parameters[name].m == pytest.approx(ref.parameters[name].m, rel=1e-10)
    assert "(50, 150)" in r.report()


def test_params_with_unsupported_sharing_or_names_fail(data, base):
    params = sc.fit_parameters(data, base)
    params["turns_offset"].shared = "global"
    with pytest.raises(FitError, match="shared='global' is not supported for offset"):
        sc.fit_hat_curves(data, base, params=params)
    params = sc.fit_parameters(data, base)
    params.add(FitParameter("pitch", 1e-9, "nm"))
    with pytest.raises(FitError, match="'pitch' is not one of"):
        sc.fit_hat_curves(data, base, params=params)
    with pytest.raises(TypeError, match="params must be a FitParameters"):
        sc.fit_hat_curves(data, base, params={"radius": 1})


@pytest.mark.parametrize("flag", ["thermal", "fit_turns_offset", "fit_extension_offset"])
def test_boolean_flags_are_checked(data, base, flag):
    with pytest.raises(TypeError, match=f"{flag} must be True or False, got 'no'"):
        sc.fit_hat_curves(data, base, **{flag: "no"})


def test_per_force_parameter_recovers_a_force_dependent_value(base):
    """Each force's curve made with its own C_t; one shared radius and offsets."""
    import pandas as pd

    u = sc.ureg
    forces, twist = [0.3, 0.5, 0.7], [80.0, 95.0, 110.0]
    parts = [sc.simulate_rotation_curves(base.replace(twist_persistence=c * u.nm), [f] * u.pN,
                                         points_per_force=70, noise=4 * u.nm, turns_offset=0.2,
                                         seed=i)
             for i, (f, c) in enumerate(zip(forces, twist, strict=True))]
    df = pd.concat(parts, ignore_index=True)
    df.attrs = dict(parts[0].attrs)
    params = sc.fit_parameters(df, base, vary=["twist_persistence", "radius"])
    names = params.split_per_force("twist_persistence", forces * u.pN)
    assert names == ["twist_persistence[0.3 pN]", "twist_persistence[0.5 pN]",
                     "twist_persistence[0.7 pN]"]
    assert list(params)[:3] == names and params[names[0]].shared == "per-force"
    r = sc.fit_hat_curves(df, base, params=params)
    for name, c in zip(names, twist, strict=True):
        assert abs(r.parameters[name].m - c) < 4 * r.stderr[name].m, (name, r.parameters[name])
    assert abs(r.parameters["radius"].m - base.radius.m_as("nm")) < 4 * r.stderr["radius"].m
    assert "twist_persistence" not in r.fixed
    # the same data with one global C_t: the misfit shows in the runs test
    with pytest.warns(FitWarning, match="runs test"):
        sc.fit_hat_curves(df, base)
    fig = r.plot()  # each force's curve drawn with its own C_t
    import matplotlib.pyplot as plt

    plt.close(fig)
    bad = sc.fit_parameters(df, base)
    bad.split_per_force("radius", [0.4] * u.pN)
    with pytest.raises(FitError, match="its force is not one of the data's forces"):
        sc.fit_hat_curves(df, base, params=bad)
    with pytest.raises(ValueError, match="only a global parameter"):
        bad.split_per_force("turns_offset", [0.3] * u.pN)
