"""Validity checks shared by the rod scenes (smooth, rough, designed, twist-spinning helices).

One place for the messages every rod scene gives the same way:

* :func:`warn_hard_contact`: a ValidityWarning where the Hertz contact half-width
  of the strands exceeds the rod radius (alpha > 0.699 rad), so hard contact
  R = r has failed (the criterion and its derivation are in
  :func:`supercoil.core.rod.contact.contact_width_ratio`);
* :func:`check_finite`: a ValidityError when a result leaves the floating-point
  range (e.g. a pitch beyond 1e308 mm for a tiny N), never an inf in a table;
* :func:`warn_no_friction`: a ValidityWarning that the no-slip condition
  [eq friction con] is not checked when the rod has no friction coefficient.
"""

from __future__ import annotations

import warnings

import numpy as np

from supercoil.core.rod import contact as _sc
from supercoil.exceptions import ValidityError, ValidityWarning

__all__ = ["check_finite", "warn_hard_contact", "warn_no_friction"]


def warn_hard_contact(alpha, where, stacklevel=3):
    """Warn (ValidityWarning) if some tilt ``alpha`` (rad, floats) breaks hard contact.

    ``where`` names the scene and its inputs for the message; ``stacklevel``
    3 points at the caller of the public function that calls this. Returns the
    message, or None when ``b / r <= 1`` everywhere.
    """
    msg = _sc.contact_warning(alpha, where)
    if msg:
        warnings.warn(msg, ValidityWarning, stacklevel=stacklevel)
    return msg


def check_finite(fields, where):
    """Raise :class:`ValidityError` if a result array has NaN/inf (float range exceeded).

    ``fields`` maps names to arrays in their display units (the units of the
    returned table, so an overflow in the conversion is caught too); ``where``
    names the inputs (e.g. the turns) for the message, which gives the first
    bad value and its position.
    """
    for name, x in fields.items():
        x = np.asarray(x, float)
        bad = ~np.isfinite(x)
        if np.any(bad):
            i = int(np.flatnonzero(bad.reshape(-1))[0])
            raise ValidityError(
                f"result {name!r} is {float(x.reshape(-1)[i])!r} at index {i} ({where}): the "
                "inputs leave the floating-point range (e.g. a pitch beyond 1e308); no "
                "finite result exists")


def check_finite_scaled(fields, where):
    """:func:`check_finite` of ``x * scale`` for ``fields`` mapping names to ``(x, scale)``.

    ``scale > 0``. The product is monotone in x and a NaN reaches both extremes, so
    ``x * scale`` is finite everywhere exactly when it is at ``min(x)`` and ``max(x)``:
    the products (a temporary of the array's size each) are formed only for a field
    that fails this, to give :func:`check_finite`'s message.
    """
    for name, (x, scale) in fields.items():
        x = np.asarray(x, float)
        with np.errstate(over="ignore", invalid="ignore"):
            if x.size and np.isfinite(np.min(x) * scale) and np.isfinite(np.max(x) * scale):
                continue
            check_finite({name: x * scale}, where)


def warn_no_friction(scene, consequence, stacklevel=3):
    """Warn that ``rod.friction_coefficient`` is None, so no-slip is not checked."""
    warnings.warn(
        f"rod.friction_coefficient is None: the no-slip condition [eq friction con] of the "
        f"{scene} is not checked; {consequence}", ValidityWarning, stacklevel=stacklevel)
