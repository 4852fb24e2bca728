"""Classification of stability-map cells: call a solver, judge the outcome."""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np

#: the four outcome categories, in legend order
CATEGORIES = ("ok", "flagged", "named error", "WRONG")
#: colour of each category in :func:`plot`
COLORS = {"ok": "#4daf4a", "flagged": "#ffbf00", "named error": "#377eb8", "WRONG": "#e41a1c"}

IGNORED_WARNINGS = (DeprecationWarning, PendingDeprecationWarning, FutureWarning)

# rough-helix accuracy: distance to the reference curve in y and in s/L
ROUGH_TOL_Y = 1e-8
ROUGH_TOL_S = 1e-8


@dataclasses.dataclass(frozen=True)
class Axis:
    """One input axis of a map: table column, plot label, unit, grid values."""

    column: str
    label: str
    unit: str
    values: np.ndarray


# ---------------------------------------------------------------------------
# calling a solver and classifying what came out
# ---------------------------------------------------------------------------


def call(func):
    """``func()`` with every warning recorded: ``(value, exception, warnings)``."""
    with warnings.catch_warnings(record=True) as rec, \
            np.errstate(divide="warn", over="warn", invalid="warn", under="ignore"):
        warnings.simplefilter("always")
        try:
            value, exc = func(), None
        except Exception as e:  # classified by the caller
            value, exc = None, e
    return value, exc, [w for w in rec if not issubclass(w.category, IGNORED_WARNINGS)]


def named(exc):
    """Exception class name if ``exc`` is a named error, else None."""
    import pint

    from supercoil.exceptions import SupercoilError

    if isinstance(exc, SupercoilError | pint.DimensionalityError):
        return type(exc).__name__
    if type(exc) is ValueError and str(exc).strip():
        return "ValueError"
    return None


def verdict(exc=None, warns=(), problems=(), flags=(), soft=()):
    """``(outcome, detail)`` from an exception, recorded warnings, problems and flags.

    ``soft`` problems (a number outside its physical range) make the cell WRONG only
    if the solver issued no :class:`~supercoil.exceptions.SupercoilWarning`.
    """
    from supercoil.exceptions import SupercoilWarning

    foreign = [w for w in warns if not issubclass(w.category, SupercoilWarning)]
    ours = [w for w in warns if issubclass(w.category, SupercoilWarning)]
    if foreign:
        w = foreign[0]
        return "WRONG", f"unnamed warning {w.category.__name__}: {w.message}"
    if exc is not None:
        name = named(exc)
        if name is None:
            return "WRONG", f"unnamed exception {type(exc).__name__}: {exc}"
        return f"named error: {name}", str(exc)
    if problems or (soft and not ours):
        return "WRONG", "; ".join([*problems, *soft])
    if ours or flags:
        parts = [f"{w.category.__name__}: {w.message}" for w in ours] + list(flags)
        return "flagged", "; ".join(parts)
    return "ok", ""


def category(outcome):
    return "named error" if outcome.startswith("named error") else outcome


def root_ok(h, a, scale, rtol=1e-12, ulps=4):
    """Backward-error test of a root ``a`` of ``h``: ``|h(a)| <= rtol scale`` or within
    ``ulps`` float spacings of ``a`` times ``|h'(a)|`` (near pi/4 the equations are so
    steep that the best float tilt leaves a larger residual)."""
    with np.errstate(all="ignore"):
        d = 1e-7 * abs(a) if a != 0 else 1e-300
        slope = abs(h(a + d) - h(a - d)) / (2 * d)
        return abs(h(a)) <= rtol * scale + ulps * np.spacing(abs(a)) * slope


def finite_problems(values):
    """Problems for non-finite numbers among ``{name: array}``."""
    out = []
    for name, v in values.items():
        v = np.asarray(v, float)
        if not np.all(np.isfinite(v)):
            out.append(f"non-finite {name} returned ({v.ravel()[~np.isfinite(v.ravel())][0]})")
    return out


# ---------------------------------------------------------------------------
# grids
# ---------------------------------------------------------------------------


def log_grid(lo, hi, n):
    return np.geomspace(lo, hi, max(int(n), 2))


def end_fractions(quick):
    """s/s_max: uniform, then clustered toward 1 (down to 1 - 1e-9), then 1 and 1.01."""
    if quick:
        inner = np.concatenate([np.linspace(0.0, 0.8, 3), 1.0 - np.geomspace(1e-2, 1e-9, 3)])
    else:
        inner = np.concatenate([np.linspace(0.0, 0.9, 10), 1.0 - np.geomspace(1e-2, 1e-9, 8)])
    return np.concatenate([inner, [1.0, 1.01]])


# ---------------------------------------------------------------------------
# rods
# ---------------------------------------------------------------------------


