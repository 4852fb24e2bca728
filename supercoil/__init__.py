"""supercoil: mechanics and thermodynamics of twisted filaments that coil into double helices.

The model is that of Li, Zhao et al., "Formation of Non-uniform Double Helices
for Elastic Rods under Torsion", restated in MODEL.md. Build quantities with
the package's single unit registry :data:`supercoil.ureg`::

    import supercoil as sc
    u = sc.ureg
    dna = sc.load_parameters("dna")
"""

__version__ = "0.1.0"

from . import geometry
from .design import design_twist_schedule
from .exceptions import (
    BoundWarning,
    DataError,
    DataWarning,
    FitError,
    FitWarning,
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
from .fitting import FitResult, fit_hat_curves, fit_many, simulate_rotation_curves
from .hat import buckling_turns, hat_curve, post_buckling_slope
from .materials import DNA, ElasticRod
from .parameters import available_parameter_sets, load_parameters
from .plectoneme import (
    effective_twist_rigidity,
    extension_factor,
    plectoneme_equilibrium,
)
from .rough import rough_helix
from .smooth import smooth_helix
from .spinning import twist_spinning
from .tables import read_csv, write_csv
from .tweezers_data import read_tweezers_csv
from .units import ureg

__all__ = [
    "DNA",
    "BoundWarning",
    "DataError",
    "DataWarning",
    "ElasticRod",
    "FitError",
    "FitResult",
    "FitWarning",
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
    "available_parameter_sets",
    "buckling_turns",
    "design_twist_schedule",
    "effective_twist_rigidity",
    "extension_factor",
    "fit_hat_curves",
    "fit_many",
    "geometry",
    "hat_curve",
    "load_parameters",
    "plectoneme_equilibrium",
    "post_buckling_slope",
    "read_csv",
    "read_tweezers_csv",
    "rough_helix",
    "simulate_rotation_curves",
    "smooth_helix",
    "twist_spinning",
    "ureg",
    "write_csv",
]
