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
from supercoil.units import ureg

#: public names imported on first use (PEP 562): ``import supercoil`` builds only the
#: unit registry; pandas, scipy and matplotlib load with the first function that needs them
_LAZY = {
    "DNA": ("supercoil.dna.material", 'DNA'),
    "DNAModel": ("supercoil.dna.models", 'DNAModel'),
    "ElasticRod": ("supercoil.rod.material", 'ElasticRod'),
    "FitParameter": ("supercoil.dna.fitting", 'FitParameter'),
    "FitParameters": ("supercoil.dna.fitting", 'FitParameters'),
    "FitResult": ("supercoil.dna.fitting", 'FitResult'),
    "available_interactions": ("supercoil.dna.interactions", 'available_interactions'),
    "available_models": ("supercoil.dna.models", 'available_models'),
    "available_parameter_sets": ("supercoil.parameters", 'available_parameter_sets'),
    "buckling_turns": ("supercoil.dna.hat", 'buckling_turns'),
    "compare_models": ("supercoil.dna.fitting", 'compare_models'),
    "core": ("supercoil.core", None),
    "datasets": ("supercoil.datasets", None),
    "design_twist_schedule": ("supercoil.rod.design", 'design_twist_schedule'),
    "dna": ("supercoil.dna", None),
    "effective_twist_rigidity": ("supercoil.dna.moroz_nelson", 'effective_twist_rigidity'),
    "extension_factor": ("supercoil.dna.moroz_nelson", 'extension_factor'),
    "fit_hat_curves": ("supercoil.dna.fitting", 'fit_hat_curves'),
    "fit_many": ("supercoil.dna.fitting", 'fit_many'),
    "fit_parameters": ("supercoil.dna.fitting", 'fit_parameters'),
    "free_energy": ("supercoil.dna.hat", 'free_energy'),
    "geometry": ("supercoil.geometry", None),
    "hat_curve": ("supercoil.dna.hat", 'hat_curve'),
    "load_parameters": ("supercoil.parameters", 'load_parameters'),
    "parameters": ("supercoil.parameters", None),
    "plectoneme_equilibrium": ("supercoil.dna.plectoneme", 'plectoneme_equilibrium'),
    "post_buckling_slope": ("supercoil.dna.hat", 'post_buckling_slope'),
    "read_csv": ("supercoil.tables", 'read_csv'),
    "read_tweezers_csv": ("supercoil.dna.tweezers", 'read_tweezers_csv'),
    "register_interaction": ("supercoil.dna.interactions", 'register_interaction'),
    "register_model": ("supercoil.dna.models", 'register_model'),
    "rod": ("supercoil.rod", None),
    "rough_helix": ("supercoil.rod.rough", 'rough_helix'),
    "simulate_rotation_curves": ("supercoil.dna.fitting", 'simulate_rotation_curves'),
    "smooth_helix": ("supercoil.rod.smooth", 'smooth_helix'),
    "tables": ("supercoil.tables", None),
    "traces": ("supercoil.traces", None),
    "twist_spinning": ("supercoil.rod.spinning", 'twist_spinning'),
    "units": ("supercoil.units", None),
    "validation": ("supercoil.validation", None),
    "write_csv": ("supercoil.tables", 'write_csv'),
    "maxwell_check": ("supercoil.dna.fitting.consistency", 'maxwell_check'),
    "read_published_curves": ("supercoil.datasets.published", 'read_published_curves'),
    "Comparison": ("supercoil.dna.fitting", 'Comparison'),
    "FitOptions": ("supercoil.dna.fitting", 'FitOptions'),
}


def __getattr__(name):
    try:
        module, attr = _LAZY[name]
    except KeyError:
        raise AttributeError(f"module 'supercoil' has no attribute {name!r}") from None
    import importlib

    value = importlib.import_module(module)
    if attr is not None:
        value = getattr(value, attr)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_LAZY))


__all__ = [  # noqa: RUF022 (new names appended at the end: parallel merges stay clean)
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
    "maxwell_check",
    "read_published_curves",
    "Comparison",
    "FitOptions",
]


# --- modules moved in 0.2: the 0.1 attribute warns and gives the new
# module; `import supercoil.<old>` goes through the shim modules supercoil/<old>.py.
# Not in __all__; removed in 0.3.
_lazy_getattr = __getattr__


def __getattr__(name):  # the lazy loader above, plus the 0.1 module paths (supercoil._moved)
    from supercoil._moved import MOVED, warn_moved

    if name in MOVED:
        return warn_moved(name, stacklevel=2)
    return _lazy_getattr(name)
