"""Fixtures of the fitting tests: the seed DNA, a non-default truth, one data set and its fit."""

import numpy as np
import pytest
from fitting_helpers import FORCES, simulate

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves


@pytest.fixture(scope="module")
def base():
    return sc.load_parameters("dna")


@pytest.fixture(scope="module")
def dna(base):
    """The seed set under the name the result-convention and label tests use."""
    return base


@pytest.fixture(scope="module")
def one_force_data(base):
    """li-zhao curves at 1.2 pN, -20..20 turns (41 points), seed 1: no noise options."""
    return sc.simulate_rotation_curves(base, [1.2] * sc.ureg.pN, np.linspace(-20, 20, 41),
                                       seed=1)


@pytest.fixture(scope="module")
def true_dna(base):
    u = sc.ureg
    # not the defaults (86 nm, 1.75 nm): the fit has to move
    return base.replace(twist_persistence=95 * u.nm, radius=2.0 * u.nm)


@pytest.fixture(scope="module")
def data(true_dna):
    return simulate(true_dna, seed=11)


@pytest.fixture(scope="module")
def result(data, base):
    return sc.fit_hat_curves(data, base, vary=["twist_persistence", "radius"])


@pytest.fixture(scope="module")
def many(true_dna):
    u = sc.ureg
    df = simulate_rotation_curves(true_dna, np.array(FORCES) * u.pN, points_per_force=50,
                                  molecules=4, turns_offset=[0.2, -0.3, 0.5, 0.0],
                                  extension_offset=[10, 0, -5, 20] * u.nm, seed=8)
    # molecule m3 was measured at a force without plectoneme equilibrium
    df.loc[(df["molecule"] == "m3") & (df["force"] == 0.7), "force"] = 2e5
    return df
