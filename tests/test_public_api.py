"""The public API: every name of 0.1's ``supercoil.__all__`` still works; start-up is lazy."""

import subprocess
import sys

import pytest

import supercoil as sc

#: supercoil.__all__ of version 0.1 (the contract: these keep working)
NAMES_0_1 = [
    "DNA", "BoundWarning", "DataError", "DataWarning", "ElasticRod", "FitError", "FitResult",
    "FitWarning", "NoEquilibriumError", "NoHelixError", "NoSolutionError", "ParameterError",
    "SingularityError", "SupercoilError", "SupercoilWarning", "ValidityError", "ValidityWarning",
    "__version__", "available_parameter_sets", "buckling_turns", "design_twist_schedule",
    "effective_twist_rigidity", "extension_factor", "fit_hat_curves", "fit_many", "geometry",
    "hat_curve", "load_parameters", "plectoneme_equilibrium", "post_buckling_slope",
    "read_csv", "read_tweezers_csv", "rough_helix", "simulate_rotation_curves",
    "smooth_helix", "twist_spinning", "ureg", "write_csv",
]


@pytest.mark.parametrize("name", NAMES_0_1)
def test_every_0_1_name_is_still_public(name):
    assert name in sc.__all__
    assert getattr(sc, name) is not None


def test_every_public_name_resolves_and_star_import_works():
    ns = {}
    exec("from supercoil import *", ns)
    assert set(sc.__all__) <= set(ns)
    assert set(sc.__all__) <= set(dir(sc))
    with pytest.raises(AttributeError, match="no attribute 'hat_curves'"):
        sc.hat_curves  # noqa: B018  (a typo is an AttributeError, not a silent None)


def test_import_builds_only_the_registry():
    """``import supercoil`` loads neither pandas, scipy's solvers nor matplotlib (import time).

    (pint itself imports the bare ``scipy`` package, a few ms; not its submodules.) The
    fits and the command line do not load scipy.stats either (~0.5-1 s of every
    ``supercoil`` command): their p-values call scipy.special.
    """
    code = ("import sys, supercoil; heavy = [m for m in ('pandas', 'scipy.optimize', "
            "'scipy.integrate', 'scipy.special', 'matplotlib') if m in sys.modules]; "
            "print(','.join(heavy)); import supercoil.dna.fitting, supercoil.cli; "
            "print('scipy.stats' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.split("\n")
    assert out[:2] == ["", "False"]


def test_behaviour_unchanged_through_the_lazy_names():
    u = sc.ureg
    dna = sc.load_parameters("dna")
    eq = sc.plectoneme_equilibrium(dna, 1.2 * u.pN)
    assert eq.radius.m_as("nm") == pytest.approx(2.2991, abs=5e-5)  # 0.1's README value
    assert sc.buckling_turns(dna, 1.2 * u.pN).m == pytest.approx(6.122, abs=5e-4)
