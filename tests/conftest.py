import os

import matplotlib
import pytest
from hypothesis import HealthCheck, settings

matplotlib.use("Agg")

settings.register_profile(
    "default", deadline=None, max_examples=60, suppress_health_check=[HealthCheck.too_slow]
)
settings.register_profile(  # derandomized: CI runs the same examples every time
    "ci", deadline=None, max_examples=40, derandomize=True,
    suppress_health_check=[HealthCheck.too_slow]
)
settings.load_profile("ci" if os.environ.get("CI") else "default")


@pytest.fixture
def ureg():
    import supercoil

    return supercoil.ureg


@pytest.fixture
def dna():
    import supercoil

    return supercoil.load_parameters("dna")


@pytest.fixture
def rubber_rod():
    import supercoil

    return supercoil.load_parameters("silicone_rubber_rod")
