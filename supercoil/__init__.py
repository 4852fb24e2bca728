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

__all__ = [
    "DNA",
    "BoundWarning",
    "DataError",
    "ElasticRod",
    "FitError",
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
    "geometry",
    "load_parameters",
    "read_csv",
    "ureg",
    "write_csv",
]
