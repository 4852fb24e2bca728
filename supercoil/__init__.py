"""supercoil: mechanics and thermodynamics of twisted filaments that coil into double helices.

Rods (:mod:`supercoil.rod`) follow Li, Zhao et al., "Formation of Non-uniform
Double Helices for Elastic Rods under Torsion"; DNA (:mod:`supercoil.dna`) is a
family of models on one interface (:mod:`supercoil.dna.models`). The physics is
documented in the repository's docs/theory/. Build quantities with the
package's single unit registry :data:`supercoil.ureg`::

    import supercoil as sc
    u = sc.ureg
    dna = sc.load_parameters("dna")
"""

__version__ = "0.1.0"

from supercoil import geometry
from supercoil.dna.fitting import (
    FitParameter,
    FitParameters,
    FitResult,
    compare_models,
    fit_hat_curves,
    fit_many,
    fit_parameters,
    simulate_rotation_curves,
)
from supercoil.dna.hat import buckling_turns, free_energy, hat_curve, post_buckling_slope
from supercoil.dna.interactions import available_interactions, register_interaction
from supercoil.dna.material import DNA
from supercoil.dna.models import DNAModel, available_models, register_model
from supercoil.dna.moroz_nelson import effective_twist_rigidity, extension_factor
from supercoil.dna.plectoneme import plectoneme_equilibrium
from supercoil.dna.tweezers import read_tweezers_csv
from supercoil.exceptions import (
    BoundWarning,
    DataError,
    DataWarning,
    FitError,
    FitWarning,
    ModelError,
    NoEquilibriumError,
    NoHelixError,
    NoSolutionError,
    ParameterError,
    SingularityError,
    SupercoilError,
    SupercoilWarning,
    ValidityError,
    ValidityWarning,
)
from supercoil.parameters import available_parameter_sets, load_parameters
from supercoil.rod.design import design_twist_schedule
from supercoil.rod.material import ElasticRod
from supercoil.rod.rough import rough_helix
from supercoil.rod.smooth import smooth_helix
from supercoil.rod.spinning import twist_spinning
from supercoil.tables import read_csv, write_csv
from supercoil.units import ureg

__all__ = [
    "DNA",
    "BoundWarning",
    "DNAModel",
    "DataError",
    "DataWarning",
    "ElasticRod",
    "FitError",
    "FitParameter",
    "FitParameters",
    "FitResult",
    "FitWarning",
    "ModelError",
    "NoEquilibriumError",
    "NoHelixError",
    "NoSolutionError",
    "ParameterError",
    "SingularityError",
    "SupercoilError",
    "SupercoilWarning",
    "ValidityError",
    "ValidityWarning",
    "__version__",
    "available_interactions",
    "available_models",
    "available_parameter_sets",
    "buckling_turns",
    "compare_models",
    "design_twist_schedule",
    "effective_twist_rigidity",
    "extension_factor",
    "fit_hat_curves",
    "fit_many",
    "fit_parameters",
    "free_energy",
    "geometry",
    "hat_curve",
    "load_parameters",
    "plectoneme_equilibrium",
    "post_buckling_slope",
    "read_csv",
    "read_tweezers_csv",
    "register_interaction",
    "register_model",
    "rough_helix",
    "simulate_rotation_curves",
    "smooth_helix",
    "twist_spinning",
    "ureg",
    "write_csv",
]
