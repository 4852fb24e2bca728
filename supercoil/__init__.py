"""supercoil: mechanics and thermodynamics of twisted filaments that coil into double helices.

The model is that of Li, Zhao et al., "Formation of Non-uniform Double Helices
for Elastic Rods under Torsion", restated in MODEL.md. Build quantities with
the package's single unit registry :data:`supercoil.ureg`::

    import supercoil as sc
    u = sc.ureg
    dna = sc.load_parameters("dna")
"""

__version__ = "0.1.0"

from .units import ureg  # noqa: E402  (the one registry, created first)

from . import geometry  # noqa: E402
from .exceptions import (  # noqa: E402
    BoundWarning,
    DataError,
    FitError,
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
from .materials import DNA, ElasticRod  # noqa: E402
from .parameters import available_parameter_sets, load_parameters  # noqa: E402
from .tables import read_csv, write_csv  # noqa: E402
from .smooth import smooth_helix  # noqa: E402
from .rough import rough_helix  # noqa: E402
from .design import design_twist_schedule  # noqa: E402
from .spinning import twist_spinning  # noqa: E402
from .plectoneme import (  # noqa: E402
    effective_twist_rigidity,
    extension_factor,
    plectoneme_equilibrium,
)
from .hat import hat_curve  # noqa: E402
from .tweezers_data import read_tweezers_csv  # noqa: E402
from .fitting import FitResult, fit_hat_curves, fit_many  # noqa: E402

__all__ = [
    "DNA",
    "BoundWarning",
    "DataError",
    "ElasticRod",
    "FitError",
    "FitResult",
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
    "design_twist_schedule",
    "effective_twist_rigidity",
    "extension_factor",
    "fit_hat_curves",
    "fit_many",
    "hat_curve",
    "plectoneme_equilibrium",
    "read_tweezers_csv",
    "rough_helix",
    "smooth_helix",
    "twist_spinning",
    "geometry",
    "load_parameters",
    "read_csv",
    "ureg",
    "write_csv",
]
