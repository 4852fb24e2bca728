"""Issue 9, item 8: quantities, materials, result records, tables and fit results pickle.

The package registers its registry as pint's application registry, so a
quantity unpickled anywhere (this process, a worker of a
ProcessPoolExecutor) belongs to ``supercoil.ureg`` and passes the unit
boundary. Every round trip is compared field by field with the original.
"""

import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pandas as pd
import pint
import pytest

import supercoil as sc

u = sc.ureg


def roundtrip(obj):
    return pickle.loads(pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL))


@pytest.fixture(scope="module")
def dna():
    return sc.load_parameters("dna")


@pytest.fixture(scope="module")
def rod():
    return sc.load_parameters("silicone_rubber_rod")


def test_application_registry_is_the_package_registry():
    assert pint.get_application_registry().get() is u


@pytest.mark.parametrize("q", [1.2 * u.pN, np.array([0.4, 1.2]) * u.pN, 40 * u.turn,
                               u.Quantity(25, "degC")])
def test_quantities_come_back_in_the_package_registry(q):
    back = roundtrip(q)
    assert back._REGISTRY is u
    assert back.units == q.units
    np.testing.assert_array_equal(back.magnitude, q.magnitude)


def test_unpickled_force_passes_the_unit_boundary(dna):
    # main: "built with another pint UnitRegistry"
    eq = sc.plectoneme_equilibrium(dna, roundtrip(1.2 * u.pN))
    assert eq.radius == sc.plectoneme_equilibrium(dna, 1.2 * u.pN).radius


def test_materials_roundtrip_and_replace(dna, rod):
    for mat, change in ((dna, {"length": 1 * u.um}), (rod, {"length": 2 * u.m})):
        back = roundtrip(mat)
        assert back == mat and hash(back) == hash(mat) and back.si == mat.si
        # main: an unpickled DNA cannot be .replace()d
        assert back.replace(**change) == mat.replace(**change)


def test_a_model_parameter_set_roundtrips_with_its_values():
    from supercoil.parameters import read_parameter_set

    pset = read_parameter_set("ensemble_qian2024_spread_fit")
    back = roundtrip(pset)
    assert back.material == pset.material and hash(back.material) == hash(pset.material)
    assert back.calibration == {"torque_scale": 0.684}
    assert back.values == pset.values


def test_salted_dna_roundtrip(dna):
    salty = dna.replace(salt=150 * u.mM)
    assert roundtrip(salty).si.salt == pytest.approx(150.0)


def test_result_records_roundtrip(dna, rod):
    eq = sc.plectoneme_equilibrium(dna, [0.5, 1.2] * u.pN)
    back = roundtrip(eq)
    assert type(back) is type(eq)
    for a, b in zip(eq, back, strict=True):
        assert a.units == b.units
        np.testing.assert_array_equal(a.m, b.m)
    h = sc.smooth_helix(rod, [10, 40], 10 * u.cm)
    hb = roundtrip(h)
    np.testing.assert_array_equal(hb.pitch.m, h.pitch.m)
    assert hb.provenance == h.provenance
    t = sc.twist_spinning(rod, 40, [0.0, 0.1] * u.N)
    np.testing.assert_array_equal(roundtrip(t).beta.m, t.beta.m)


def test_tables_roundtrip_with_attrs(dna):
    df = sc.hat_curve(dna, [0.5, 0.7] * u.pN, np.linspace(-20, 20, 9))
    back = roundtrip(df)
    pd.testing.assert_frame_equal(back, df)
    assert back.attrs == df.attrs


def test_fit_result_roundtrip(dna):
    data = sc.simulate_rotation_curves(dna, [0.5, 0.7] * u.pN, np.linspace(-15, 15, 31),
                                       noise=2 * u.nm, seed=3)
    res = sc.fit_hat_curves(data, dna, vary=("twist_persistence",))
    back = roundtrip(res)
    assert set(back.parameters) == set(res.parameters)
    for k, q in res.parameters.items():
        assert back.parameters[k] == q and back.parameters[k]._REGISTRY is u
    assert back.chi_square == res.chi_square


def _worker_equilibrium(dna, force):
    eq = sc.plectoneme_equilibrium(dna, force)
    return eq, eq.radius, dna.replace(length=dna.length * 2)


def test_through_a_process_pool(dna):
    force = np.array([0.5, 1.2, 3.0]) * u.pN
    with ProcessPoolExecutor(max_workers=1) as pool:
        eq, radius, longer = pool.submit(_worker_equilibrium, dna, force).result()
    here = sc.plectoneme_equilibrium(dna, force)
    np.testing.assert_array_equal(radius.m, here.radius.m)
    assert radius._REGISTRY is u and eq.torque._REGISTRY is u
    assert longer == dna.replace(length=1500 * u.nm)

