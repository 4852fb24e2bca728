"""Argument checks shared by the public functions (one helper per kind of argument)."""

from __future__ import annotations

import numpy as np

__all__ = ["broadcast_shape", "check_callable", "check_finite_output", "check_flag",
           "check_material", "check_scale", "named", "profile_values", "scalar"]


def named(exc, argument):
    """``exc`` with its ``argument`` attribute set (the argument's name; the CLI maps it to a flag).

    The checks below raise ``named(TypeError(...), name)``; ``SupercoilError`` takes
    ``argument=`` in its constructor (supercoil.exceptions).
    """
    exc.argument = argument
    return exc


def check_flag(value, name):
    """``value`` as a bool; TypeError naming ``name`` unless it is True/False (or numpy bool).

    Strings such as ``"no"`` or ``"False"`` are rejected, not read as truthy.
    """
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise named(TypeError(f"{name} must be True or False, got {value!r}"), name)


def check_material(value, cls, name):
    """The SI view of ``value``; TypeError naming ``name`` unless it is a ``cls``.

    One check for every public function taking a material (``rod``, ``dna``):
    ``None``, a parameter-set name or the other material give a message that
    says what was expected instead of an AttributeError on ``.si``.
    """
    if isinstance(value, cls):
        return value.si
    hint = ""
    if isinstance(value, str):
        hint = f" (load it first: supercoil.load_parameters({value!r}))"
    elif type(value).__name__ in ("DNA", "ElasticRod"):
        hint = " (an ElasticRod is a rod scene's material, a DNA the tweezers scenes')"
    raise named(TypeError(f"{name} must be a supercoil.{cls.__name__}, got "
                          f"{type(value).__name__}{hint}"), name)


def broadcast_shape(**arrays):
    """The common shape of the arguments; ValueError naming them if they do not broadcast.

    ``broadcast_shape(turns=n, slack=S)``: numpy's own message ("shape mismatch:
    objects cannot be broadcast") names neither argument.
    """
    shapes = {k: np.shape(v) for k, v in arrays.items()}
    try:
        return np.broadcast_shapes(*shapes.values())
    except ValueError:
        listed = ", ".join(f"{k} {v}" for k, v in shapes.items())
        raise named(ValueError(f"the shapes of {', '.join(arrays)} do not broadcast together "
                               f"({listed}); give scalars, equal shapes, or "
                               "numpy-broadcastable ones"), tuple(arrays)) from None


def check_finite_output(value, name, inputs):
    """``value`` unchanged if all finite; else ValidityError naming ``name`` and ``inputs``.

    For results that leave the floating-point range (e.g. ``curvature_error``
    of a slope of 1e200); ``inputs`` describes the arguments in the message.
    """
    from supercoil.exceptions import ValidityError

    a = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(a)):
        bad = float(a[~np.isfinite(a)].reshape(-1)[0])
        raise ValidityError(f"{name} is {bad!r} for {inputs}: the result leaves the "
                            "floating-point range (about 1.8e308)")
    return value


def check_scale(value, what, lo=-np.inf, hi=np.inf, why=""):
    """``value`` unchanged if ``lo <= value <= hi``; else ValidityError naming it and the limit.

    One check for a derived scale of the inputs that a kernel divides by or
    exponentiates (the reduced stiffness A/r0 of the hard-core plectoneme, the
    Debye length of a buffer): absurd inputs such as a radius of 1e-300 nm or
    a salt of 1e300 M give a message naming the quantity, its value and the
    limit instead of a ZeroDivisionError or an overflow deep in the kernel.
    ``what`` describes the quantity (e.g. ``"the Debye length (salt 1e+300 M)"``; or a
    callable returning it, formatted only on failure), ``why`` the reason of the limit.
    NaN fails both bounds.
    """
    from supercoil.exceptions import ValidityError

    v = float(value)
    if lo <= v <= hi:
        return value
    side, limit = ("below", lo) if not v >= lo else ("above", hi)
    what = what() if callable(what) else what
    raise ValidityError(f"{what} is {v:.6g}, {side} its limit {limit:.6g}"
                        + (f": {why}" if why else ""))


def check_callable(value, name, signature):
    """``value`` if it is callable; TypeError naming ``name`` and the ``signature`` expected.

    For the profile arguments (``pitch(s)`` of the design, ``pitch_derivative(s)``):
    a quantity or None gave "'Quantity' object is not callable" from inside.
    """
    if callable(value):
        return value
    hint = ""
    if hasattr(value, "_units"):
        hint = (f" ({value} is a value; a constant profile is a callable too: "
                "lambda s: value * numpy.ones(numpy.shape(s)))")
    raise TypeError(f"{name} must be a callable {signature}, got "
                    f"{type(value).__name__}{hint}")


def profile_values(values, shape, name):
    """A profile callable's magnitudes broadcast to the grid ``shape``; ValueError naming it.

    One check for every user callable evaluated on a grid (``pitch(s)``,
    ``pitch_derivative(s)``, ``twist_rate(slack)``): a scalar or one value per
    point; any other shape gave numpy's broadcast message, naming neither the
    callable nor the shape it must return.
    """
    a = np.asarray(values, dtype=float)
    try:
        return np.broadcast_to(a, shape)
    except ValueError:
        raise ValueError(f"{name} returned an array of shape {a.shape}; it must return a "
                         f"scalar or one value per point of its argument (shape {shape})"
                         ) from None


def scalar(mag, name):
    """``mag`` (a magnitude from :func:`~supercoil.units.magnitude`) as a float; ValueError
    naming ``name`` unless it is one number (``float()`` of an array raised numpy's
    "only 0-dimensional arrays can be converted to Python scalars")."""
    if np.ndim(mag) != 0:
        raise ValueError(f"{name} must be a scalar, got an array of shape {np.shape(mag)}")
    return float(mag)
