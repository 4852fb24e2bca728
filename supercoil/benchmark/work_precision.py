"""Work-precision diagrams (error against wall time, one line per method).

Follows the rules of the SciML DiffEqDevTools benchmarks: one point per
tolerance setting; the error on the x axis is measured against a reference
computed by a different method at a much tighter tolerance; the wall time on
the y axis is the minimum of repeated runs after a discarded warm-up
(:func:`supercoil.benchmark.timing.best_time`); both axes logarithmic; errors
are computed outside the timed code; a setting that fails is a missing point.
"""

from __future__ import annotations

import numpy as np

from supercoil.benchmark.timing import best_time

COLUMNS = ("scene", "method", "tolerance", "error", "time", "failed")
UNITS = {"scene": "", "method": "", "tolerance": "", "error": "", "time": "s", "failed": ""}


def measure(scene, methods, tolerances, reference, repeat=3):
    """Rows of a work-precision table.

    Parameters
    ----------
    scene : str
        Name of the scene (chart title).
    methods : dict of str -> callable(tol) -> array
        Each callable solves the scene at tolerance ``tol`` and returns the
        solution sampled where ``reference`` is.
    tolerances : sequence of float
    reference : array
        The reference solution (different method, much tighter tolerance).

    Returns
    -------
    dict of lists, keys :data:`COLUMNS`.
    """
    rows = {k: [] for k in COLUMNS}
    ref = np.asarray(reference, float)
    for name, solve in methods.items():
        for tol in tolerances:
            err, t, failed = np.nan, np.nan, False
            try:
                sol = np.asarray(solve(tol), float)  # error computed outside the timing
                err = float(np.max(np.abs(sol - ref)))
                if not np.isfinite(err):
                    raise FloatingPointError("non-finite solution")
                t = best_time(lambda solve=solve, tol=tol: solve(tol), repeat=repeat)
            except Exception:
                failed, err, t = True, np.nan, np.nan
            rows["scene"].append(scene)
            rows["method"].append(name)
            rows["tolerance"].append(tol)
            rows["error"].append(err)
            rows["time"].append(t)
            rows["failed"].append(failed)
    return rows


#: error floor drawn for a solution that equals its reference to the last bit
ERROR_FLOOR = 1e-17
#: one colour per method, the same in every chart
_COLOURS = {"closed form": "k", "RK45": "C0", "DOP853": "C1", "Radau": "C2", "LSODA": "C3",
            "vectorised over forces": "C4", "scalar loop": "C5"}


def plot(table, ax, title=None, error_label="max error"):
    """Draw one work-precision diagram (one line per method) on ``ax``.

    Failed settings are missing points; an error of exactly 0 is drawn at
    :data:`ERROR_FLOOR` (open marker).
    """
    for name, sub in table.groupby("method", sort=False):
        ok = sub[~sub["failed"].astype(bool)]
        err = ok["error"].clip(lower=ERROR_FLOOR)
        colour = _COLOURS.get(name)
        (line,) = ax.loglog(err, ok["time"], "o-", label=name, color=colour)
        exact = ok["error"] <= 0
        if exact.any():
            ax.loglog(err[exact], ok["time"][exact], "o", mfc="white", color=line.get_color())
        for (_, row), e in zip(ok.iterrows(), err, strict=True):
            ax.annotate(f"{row['tolerance']:.0e}", (e, row["time"]), fontsize=5,
                        color=line.get_color(), xytext=(2, 2), textcoords="offset points")
    ax.set(xlabel=error_label, ylabel="wall time (s)",
           title=title or str(table["scene"].iloc[0]))
    ax.legend(fontsize=7)
    ax.grid(True, which="both", alpha=0.3)
