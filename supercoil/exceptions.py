"""Exceptions and warnings of supercoil.

Every failure of a method (a singularity, no solution, a formula used outside
its validity) raises or warns with one of these classes, and the message names
the quantity and the limit. The package never returns a silent NaN.

Hierarchy
---------
``SupercoilError`` (base of all errors, a ``ValueError``)
    ``NoSolutionError``: the equations have no solution for these inputs
        ``NoHelixError``: no double helix forms (rod scenes)
        ``NoEquilibriumError``: no plectoneme equilibrium at this force (DNA)
    ``SingularityError``: the inputs reach a singular point of the model
        (alpha -> pi/4 where the tension diverges, alpha -> 0 at s_max)
    ``ValidityError``: a formula is evaluated where it is not defined
        (e.g. the Moroz-Nelson bracket is not positive)
    ``ParameterError``: a parameter set is malformed (missing key, bad unit)
    ``DataError``: user data cannot be read (names the row and column)
    ``FitError``: a fit could not be set up or did not converge

Every ``SupercoilError`` has an ``argument`` attribute: the name of the public
function's argument the error is about (``"sigma"``, ``"fixed"``), or ``None``.
The command line maps it to its flag (``supercoil.commands._common.ARGUMENT_FLAGS``)
instead of rewriting the message; the argument checks of ``supercoil._checks`` set
the same attribute on the ``TypeError``/``ValueError`` they raise.

``SupercoilWarning`` (base of all warnings, a ``UserWarning``)
    ``ValidityWarning``: a result is computed but lies outside the range where
        the model is trustworthy (short tail, curvature error, denaturation)
    ``BoundWarning``: a fitted estimate sits on a bound
    ``FitWarning``: a fit diagnostic (e.g. a singular covariance matrix)
    ``DataWarning``: user data was changed on request (incomplete rows dropped)
"""

from __future__ import annotations

__all__ = [
    "BoundWarning",
    "DataError",
    "DataWarning",
    "FitError",
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
]


class SupercoilError(ValueError):
    """Base class of all errors raised by supercoil.

    Parameters
    ----------
    *args
        The message (as for any exception).
    argument : str, optional
        The name of the argument of the public function that the error is about
        (e.g. ``"sigma"``); ``None`` (the default) when it is about no single argument.
    """

    def __init__(self, *args, argument=None):
        super().__init__(*args)
        self.argument = argument

    def __reduce__(self):
        # keep ``argument`` through pickling (errors of fit_many's worker processes)
        return (_rebuild, (type(self), self.args, self.argument))


def _rebuild(cls, args, argument):
    try:
        return cls(*args, argument=argument)
    except TypeError:  # a subclass whose constructor takes no ``argument``
        exc = cls(*args)
        exc.argument = argument
        return exc


class NoSolutionError(SupercoilError):
    """The model's equations have no solution for the given inputs."""


class NoHelixError(NoSolutionError):
    """No double helix exists for the given rod, turns and slack."""


class NoEquilibriumError(NoSolutionError):
    """No plectoneme equilibrium exists at the given force."""


class SingularityError(SupercoilError):
    """The inputs reach a singular point of the model (named in the message)."""


class ValidityError(SupercoilError):
    """A formula is evaluated outside the domain where it is defined."""


class ParameterError(SupercoilError):
    """A parameter set is malformed: missing key, unknown unit, wrong dimension."""


class ModelError(SupercoilError):
    """A DNA model or interaction was asked for something it does not provide.

    For example the free energy of the thermal ``"li-zhao"`` construction (it
    is not derived from one), an unknown model name, or an interaction given
    to a model without a plectoneme helix state.
    """


class DataError(SupercoilError):
    """User data cannot be read; the message names the row and the column."""


class FitError(SupercoilError):
    """A fit cannot be set up or did not converge."""


class SupercoilWarning(UserWarning):
    """Base class of all warnings issued by supercoil."""


class ValidityWarning(SupercoilWarning):
    """A result lies outside the range where the model is trustworthy."""


class BoundWarning(SupercoilWarning):
    """A fitted parameter estimate sits on one of its bounds."""


class FitWarning(SupercoilWarning):
    """A fit diagnostic: e.g. a singular covariance matrix (pseudo-inverse used)."""


class DataWarning(SupercoilWarning):
    """User data was changed on request, e.g. incomplete rows dropped (says which)."""
