"""Shared constants and synthetic data of the fitting tests (imported by the test modules)."""

import numpy as np

import supercoil as sc
from supercoil.dna.fitting import simulate_rotation_curves

FORCES = (0.3, 0.5, 0.7)  # pN: below the denaturation force, so both signs of N are valid
TRUE_N0 = 0.4  # turns
TRUE_Z0 = 30.0  # nm
NOISE = 5.0  # nm


def simulate(dna, seed, **kw):
    u = sc.ureg
    kw.setdefault("noise", NOISE * u.nm)
    kw.setdefault("turns_offset", TRUE_N0)
    kw.setdefault("extension_offset", TRUE_Z0 * u.nm)
    return simulate_rotation_curves(dna, np.array(FORCES) * u.pN, seed=seed, **kw)


def truth(true_dna):
    return {"twist_persistence": true_dna.twist_persistence.m_as("nm"),
            "radius": true_dna.radius.m_as("nm"),
            "turns_offset": TRUE_N0, "extension_offset": TRUE_Z0}
