"""Fitting hat-curve models to magnetic-tweezers rotation curves (docs/theory/fitting.md).

One concept per module: :mod:`~supercoil.dna.fitting.fit_parameters` (FitParameter,
FitParameters), :mod:`~supercoil.dna.fitting.data` (RotationData),
:mod:`~supercoil.dna.fitting.model` (HatCurveModel: residual and Jacobian
through the DNA model interface), :mod:`~supercoil.dna.fitting.covariance`
(thin-SVD covariance), :mod:`~supercoil.dna.fitting.diagnostics` (plausible
limits, goodness of fit), :mod:`~supercoil.dna.fitting.fit` (fit_hat_curves),
:mod:`~supercoil.dna.fitting.result` (FitResult), :mod:`~supercoil.dna.fitting.report`,
:mod:`~supercoil.dna.fitting.plot`, :mod:`~supercoil.dna.fitting.batch`
(fit_many), :mod:`~supercoil.dna.fitting.progress` (its progress bar or lines),
:mod:`~supercoil.dna.fitting.joint_noise` (extension and torque channels of a
joint fit), :mod:`~supercoil.dna.fitting.compare` (compare_models),
:mod:`~supercoil.dna.fitting.simulate` (simulate_rotation_curves),
:mod:`~supercoil.dna.fitting.options` (FitOptions, the shared keywords and their
defaults; FitSpec), :mod:`~supercoil.dna.fitting.solution` (FitSolution, what the
engine returns).
"""

from supercoil.dna.fitting.batch import fit_many
from supercoil.dna.fitting.compare import Comparison, compare_models, information_criteria
from supercoil.dna.fitting.data import RotationData
from supercoil.dna.fitting.fit import DEFAULT_VARY, fit_hat_curves, fit_parameters
from supercoil.dna.fitting.fit_parameters import (
    DNA_FIELDS,
    PLAUSIBLE,
    FitParameter,
    FitParameters,
)
from supercoil.dna.fitting.model import HatCurveModel
from supercoil.dna.fitting.options import DEFAULTS, FitOptions
from supercoil.dna.fitting.result import FitResult
from supercoil.dna.fitting.simulate import simulate_rotation_curves, valid_turns_range
from supercoil.dna.fitting.solution import FitSolution

#: DNA fields that can be fitted (the old name)
PHYSICAL_PARAMETERS = DNA_FIELDS

__all__ = [
    "DEFAULTS",
    "DEFAULT_VARY",
    "DNA_FIELDS",
    "PHYSICAL_PARAMETERS",
    "PLAUSIBLE",
    "Comparison",
    "FitOptions",
    "FitParameter",
    "FitParameters",
    "FitResult",
    "FitSolution",
    "HatCurveModel",
    "RotationData",
    "compare_models",
    "fit_hat_curves",
    "fit_many",
    "fit_parameters",
    "information_criteria",
    "simulate_rotation_curves",
    "valid_turns_range",
]
