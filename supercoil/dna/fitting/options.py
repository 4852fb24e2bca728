"""The settings of a fit: keywords as given (:class:`FitOptions`), prepared (:class:`FitSpec`).

:func:`~supercoil.fit_hat_curves`, :func:`~supercoil.fit_parameters`,
:func:`~supercoil.fit_many` and :func:`~supercoil.compare_models` take the same
keywords; their defaults are defined here once (:data:`DEFAULTS`) and each
function builds one frozen :class:`FitOptions` from its keywords, which
:func:`~supercoil.dna.fitting.prepare.prepare` validates and converts to SI
(a :class:`FitSpec`).
"""

from __future__ import annotations

import dataclasses

from supercoil.dna.interactions import DEFAULT_INTERACTION
from supercoil.dna.models import DEFAULT_MODEL

__all__ = ["DEFAULTS", "DEFAULT_VARY", "FitOptions", "FitSpec"]

#: the DNA fields fitted by default
DEFAULT_VARY = ("twist_persistence", "radius")


@dataclasses.dataclass(frozen=True)
class FitOptions:
    """The keywords shared by the fitting functions, as given (not yet validated).

    The meaning of each field is that of the keyword of
    :func:`~supercoil.fit_hat_curves`: ``vary``, ``fixed``, ``bounds``,
    ``start``, ``sigma``, ``fit_turns_offset``, ``fit_extension_offset``,
    ``thermal``, ``max_nfev``, ``tol``, ``model``, ``interaction``. Frozen:
    :meth:`replace` gives a changed copy.
    """

    vary: object = DEFAULT_VARY
    fixed: object = None
    bounds: object = None
    start: object = None
    sigma: object = None
    fit_turns_offset: object = True
    fit_extension_offset: object = True
    thermal: object = True
    max_nfev: int | None = None
    tol: float = 1e-10
    model: object = DEFAULT_MODEL
    interaction: object = DEFAULT_INTERACTION

    def replace(self, **changes) -> FitOptions:
        """A copy with ``changes`` (keyword names as above); TypeError for an unknown one."""
        unknown = set(changes) - {f.name for f in dataclasses.fields(self)}
        if unknown:
            raise TypeError(f"unknown fit option(s) {sorted(unknown)}; the options are "
                            f"{[f.name for f in dataclasses.fields(self)]}")
        return dataclasses.replace(self, **changes)

    @classmethod
    def names(cls) -> tuple[str, ...]:
        """The option names, in order."""
        return tuple(f.name for f in dataclasses.fields(cls))


#: the defaults of every fitting function's keywords
DEFAULTS = FitOptions()


@dataclasses.dataclass
class FitSpec:
    """Everything one fit needs, as plain picklable data (SI floats, numpy arrays)."""

    data: object  # RotationData
    params: object  # FitParameters
    dna: object  # DNASI
    xi_is_bending: bool
    model: object
    interaction: object
    thermal: bool
    max_nfev: int | None
    tol: float
    vary: list
    #: what the preparation decided for the user (a dropped parameter, ...): the report's notes
    notes: list = dataclasses.field(default_factory=list)
