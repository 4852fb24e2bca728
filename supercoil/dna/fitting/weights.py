"""The fit's weights: checks of the stated standard errors of the extensions.

A stated ``sigma`` (argument or ``sigma`` column) is a scalar or one value per data row,
and lies in ``[1e-150 L, L]`` (docs/theory/fitting.md#the-global-fit).
"""

from __future__ import annotations

import numpy as np

from supercoil import display
from supercoil._checks import named
from supercoil.exceptions import FitError

__all__ = ["SIGMA_MIN_PER_LENGTH", "check_sigma_scale", "checked_sigma"]


def checked_sigma(sigma, rot):
    """``sigma`` if it is a scalar or one value per data row; else ValueError naming the shapes.

    A sigma per force (or any other length) is not guessed: with as many rows
    as forces it would be ambiguous. Map it onto the rows, e.g.
    ``per_force[np.searchsorted(forces, data["force"])]``.
    """
    shape = np.shape(getattr(sigma, "magnitude", sigma))
    if shape not in ((), (rot.n,)):
        raise named(ValueError(f"sigma has shape {shape}; give a scalar or one value per "
                               f"data row (shape ({rot.n},)); for one sigma per force, map it "
                               "onto the rows (e.g. s[np.searchsorted(forces, "
                               "data['force'])])"), "sigma")
    return sigma


#: smallest stated sigma, in contour lengths: weighted residuals |z - model| / sigma
#: of at most L / sigma = 1e150, whose squares sum within the float range (~1.8e308)
SIGMA_MIN_PER_LENGTH = 1e-150


def check_sigma_scale(rot, length):
    """FitError naming sigma if a stated standard error is outside ``[1e-150 L, L]``.

    Above the contour length L (larger than any extension) the data would
    determine nothing: the optimiser stopped at its start (measured: sigma =
    1e7 nm for 0.7 um extensions). Below 1e-150 L the weights 1/sigma (1e-300
    nm: inf) leave the float range (the fit could not start).
    """
    if rot.weighting == "unit":
        return
    lo, hi = float(np.min(rot.sigma)), float(np.max(rot.sigma))
    if not (lo >= SIGMA_MIN_PER_LENGTH * length and hi <= length):
        floor = display.text(SIGMA_MIN_PER_LENGTH * length, "length", ".3g")
        bad, limit = (lo, f"below 1e-150 L = {floor}") if lo < SIGMA_MIN_PER_LENGTH * length \
            else (hi, f"above the contour length L = {display.text(length, 'length')}")
        raise FitError(f"sigma ({rot.weighting}) of {display.text(bad, 'extension')} is {limit}: "
                       "the "
                       "standard error of an extension lies in [1e-150 L, L] (its weights "
                       "1/sigma leave the float range below; the data determine nothing above)",
                       argument="sigma" if rot.weighting == "sigma argument" else None)
