"""Stability map: where each solver fails or loses accuracy over its inputs.

Every public solver is evaluated on a 2-D grid of its natural inputs that runs
well into its failure regions, and every cell is classified:

``ok``
    a finite result, no warning, and (where an independent reference is cheap)
    accurate to the tolerance stated below for that solver;
``flagged``
    a :class:`~supercoil.exceptions.SupercoilWarning` (``ValidityWarning``) was
    issued, or a flag of the result is set (``curvature_error_flag``, the rough
    helix slips at this s, ``short_tail``, the designed helix needs more
    friction than available);
``named error: <Class>``
    a supercoil exception, a ``pint.DimensionalityError`` or a plain
    ``ValueError`` with a message;
``WRONG``
    a NaN or inf returned silently, an unnamed exception (``ZeroDivisionError``,
    ``IndexError``, ...), a numpy floating-point ``RuntimeWarning`` or another
    foreign warning, or a number that misses its reference.

Grids and references (``quick=True`` uses coarser grids of the same ranges).
For the rods, a tilt returned with ``cos 2 alpha`` below the package's own
singularity guard (1e-9) is WRONG: the solver should have raised.

* ``smooth_helix``: turns N (0 and 1e-3 .. 1e13) x slack S/L (-0.05 .. 1.1).
  Reference: the hard-contact relation (HC) must hold for the omega of the
  linking balance, ``|omega - omega_HC| <= 1e-6 |omega_HC|`` (the tilt is
  solved to one float spacing; within ``cos 2 alpha ~ 1e-9`` of pi/4 that
  alone is ~1e-7), and ``Lk = Tw + Wr = N`` to 1e-12.
* ``rough_helix`` (closed form; ODE with k = 0, k = +100 and -100 rad/m):
  twist load N r / L (0 and 1e-9 .. 1e10) x s/s_max (0 .. 1 - 1e-9, and 1,
  1.01 beyond the end). References: the closed form for the ODE at k = 0, a
  DOP853 integration at rtol 1e-13 for the closed form, and LSODA at rtol
  1e-13 (checked against Radau) for k != 0. A cell is accurate when
  ``y = 1 - cos 2 alpha`` lies within 1e-8 of the reference curve in y or in
  s/L, i.e. ``|dy| <= 1e-8 + |dy/ds| 1e-8 L`` (alpha(s) has a vertical tangent
  at s_max); [eq ini] must hold for alpha_0 to a backward error of 1e-12.
* ``design_twist_schedule``: the paper's sinusoidal profile
  ``P = P0 + P1 sin(2 pi s / (10 P0))`` over P0 / (2 pi r) (0.5 .. 1000) x
  P1 / P0 (0 .. 1.2), whole rod. Reference: the linking number of the designed
  helix at the last slack, ``N = (1/pi) int (omega + tau) ds + omega (L - 2s)
  / 2 pi`` (adaptive quadrature of the analytic profile), to 1e-6 relative.
* ``twist_spinning``: turns N (0 and 1e-4 .. 1e13) x head tension T'
  (-1, 0 and 1e-6 .. 1e6 N). Reference: [f4] to a backward error of 1e-12,
  beta from the cancellation-free form ``sec(beta) - 1 = 2 T_s / T' -
  2 sin^2(alpha/2)`` to 1e-6 relative, and T' = 0 giving the slacking helix.
* ``plectoneme_equilibrium``: force (-1, 0 and 1e-4 .. 1e6 pN) x bending
  persistence A (2 .. 2000 nm; the molecule length does not enter).
  Reference: the residuals of (GE1), (GE2) and the tension equation in their
  unreduced form, each <= 1e-10.
* ``extension_factor``: force (0 and 1e-3 .. 1e6 pN) x torque (0 and
  1e-2 .. 1e5 pN nm), tail 750 nm. Reference: the formula in 40-digit decimal
  arithmetic, ``|d zeta| <= 1e-12 max(1, |zeta|)``.
* ``hat_curve`` (thermal and athermal): force (0 and 1e-3 .. 1e6 pN) x molecule
  length (20 nm .. 50 um). Each cell is one hat curve over 17 turns from 0 to
  the point where the plectoneme holds half the molecule (S = L/2). Reference:
  every point rebuilt from its phase (stretched: torque ``C_eff 2 pi N / L``,
  ``z = zeta L``; plectoneme: the linking balance and ``z = zeta (L - S)``)
  to 1e-9, and unflagged points physical: ``0 <= z <= L``, z not increasing
  with N.

:func:`run` returns the convention table, :func:`plot` draws the maps,
:func:`summary` counts outcomes and :func:`regions` gives the input ranges of
every outcome.
"""

from __future__ import annotations

import functools
import time

import numpy as np

from supercoil.benchmark.stability.classify import (
    CATEGORIES,
    COLORS,
    ROUGH_TOL_S,
    ROUGH_TOL_Y,
    Axis,
    call,
    category,
    finite_problems,
    verdict,
)
from supercoil.benchmark.stability.maps_dna import extension_map, hat_map, plectoneme_map
from supercoil.benchmark.stability.maps_family import cases as family_cases
from supercoil.benchmark.stability.maps_family import family_map
from supercoil.benchmark.stability.maps_rod import (
    design_map,
    rough_map,
    rough_reference,
    smooth_map,
    spinning_map,
)
from supercoil.benchmark.stability.plot import plot

__all__ = ["CATEGORIES", "COLORS", "MAPS", "ROUGH_TOL_S", "ROUGH_TOL_Y", "Axis", "call",
           "finite_problems", "map_builders", "plot", "regions", "rough_reference", "run",
           "summary", "verdict"]

#: the maps, in plotting order: (key, builder(rod, dna, quick))
MAPS = (
    ("smooth_helix", lambda rod, dna, q: smooth_map(rod, q)),
    ("rough closed_form", lambda rod, dna, q: rough_map(rod, "closed_form", 0.0, q)),
    ("rough ode k=0", lambda rod, dna, q: rough_map(rod, "ode", 0.0, q)),
    ("rough ode k>0", lambda rod, dna, q: rough_map(rod, "ode", 100.0, q)),
    ("rough ode k<0", lambda rod, dna, q: rough_map(rod, "ode", -100.0, q)),
    ("design_twist_schedule", lambda rod, dna, q: design_map(rod, q)),
    ("twist_spinning", lambda rod, dna, q: spinning_map(rod, q)),
    ("plectoneme_equilibrium", lambda rod, dna, q: plectoneme_map(dna, q)),
    ("extension_factor", lambda rod, dna, q: extension_map(dna, q)),
    ("hat_curve thermal", lambda rod, dna, q: hat_map(dna, True, q)),
    ("hat_curve athermal", lambda rod, dna, q: hat_map(dna, False, q)),
)


def map_builders():
    """:data:`MAPS` and one map per registered DNA model and interaction (read now)."""
    family = tuple((key, lambda rod, dna, q, n=name, i=inter: family_map(dna, n, i, q))
                   for key, name, inter in family_cases())
    return MAPS + family


def run(quick=False, rod=None, dna=None, only=None):
    """Evaluate every solver over its grid and classify every cell.

    Parameters
    ----------
    quick : bool
        Coarse grids (same ranges), for tests and a fast look.
    rod, dna : ElasticRod, DNA, optional
        Default: the parameter sets ``silicone_rubber_rod`` and ``dna``.
    only : iterable of str, optional
        Keys of :func:`map_builders` to run (default all: :data:`MAPS` and the family maps of
        every registered model and interaction, ``"family <model>[/<interaction>]"``).

    Returns
    -------
    pandas.DataFrame
        One row per cell: ``solver``, ``x_quantity`` and ``y_quantity`` (the
        names of the two input columns of this solver), the input columns
        (``turns``, ``slack_fraction``, ``twist_load``, ``s_fraction``,
        ``pitch_ratio``, ``amplitude_ratio``, ``head_tension`` [N], ``force``
        [pN], ``bending_persistence`` [nm], ``torque`` [pN nm], ``length`` [nm];
        NaN where not an input of that solver), ``ix``, ``iy`` (grid indices),
        ``outcome`` (``ok``, ``flagged``, ``named error: <Class>``, ``WRONG``),
        ``category`` (one of :data:`CATEGORIES`) and ``detail`` (the message).
        ``attrs["provenance"]`` holds the wall time of every map.

    The map of the default materials is computed once per process and
    copied on later calls (the test suite and ``supercoil bench`` share it).
    """
    if rod is None and dna is None and only is None:
        return _default_map(bool(quick)).copy(deep=True)
    return _run(quick, rod, dna, only)


@functools.lru_cache(maxsize=2)
def _default_map(quick):
    return _run(quick, None, None, None)


def _run(quick, rod, dna, only):
    import supercoil as sc
    from supercoil.tables import make_table, provenance

    rod = rod or sc.load_parameters("silicone_rubber_rod")
    dna = dna or sc.load_parameters("dna")
    maps, timings = [], {}
    for key, build in map_builders():
        if only is not None and key not in only:
            continue
        t0 = time.perf_counter()
        maps.append(build(rod, dna, quick))
        timings[maps[-1][0]] = round(time.perf_counter() - t0, 3)
    input_units = {}
    for _, xa, ya, _ in maps:
        input_units[xa.column] = xa.unit
        input_units[ya.column] = ya.unit
    cols = {k: [] for k in ("solver", "x_quantity", "y_quantity", *input_units, "ix", "iy",
                            "outcome", "category", "detail")}
    for name, xa, ya, out in maps:
        for iy, yv in enumerate(ya.values):
            for ix, xv in enumerate(xa.values):
                outcome, detail = out[iy, ix]
                cols["solver"].append(name)
                cols["x_quantity"].append(xa.column)
                cols["y_quantity"].append(ya.column)
                for c in input_units:
                    cols[c].append(xv if c == xa.column else yv if c == ya.column else np.nan)
                cols["ix"].append(ix)
                cols["iy"].append(iy)
                cols["outcome"].append(outcome)
                cols["category"].append(category(outcome))
                cols["detail"].append(detail)
    units = {"solver": "", "x_quantity": "", "y_quantity": "", **input_units, "ix": "",
             "iy": "", "outcome": "", "category": "", "detail": ""}
    labels = {name: [xa.label, ya.label] for name, xa, ya, _ in maps}
    return make_table(cols, units, provenance(
        None, benchmark="stability map", quick=bool(quick), rod=rod.as_dict(),
        dna=dna.as_dict(), axis_labels=labels, map_seconds=timings,
        tolerances={"rough_y": ROUGH_TOL_Y, "rough_s_over_L": ROUGH_TOL_S}))


def summary(table):
    """Counts of cells per solver and category (columns in :data:`CATEGORIES` order)."""
    counts = table.groupby(["solver", "category"], sort=False).size().unstack(fill_value=0)
    for c in CATEGORIES:
        if c not in counts:
            counts[c] = 0
    return counts[list(CATEGORIES)]


def regions(table):
    """Input ranges of every outcome of every solver: one row per (solver, outcome).

    Columns ``solver``, ``outcome``, ``cells``, ``x_quantity``, ``x_min``,
    ``x_max``, ``y_quantity``, ``y_min``, ``y_max`` (a bounding box, not a
    boundary: read the map for the shape).
    """
    import pandas as pd

    rows = []
    for (solver, outcome), g in table.groupby(["solver", "outcome"], sort=False):
        xq, yq = g["x_quantity"].iloc[0], g["y_quantity"].iloc[0]
        rows.append({"solver": solver, "outcome": outcome, "cells": len(g), "x_quantity": xq,
                     "x_min": g[xq].min(), "x_max": g[xq].max(), "y_quantity": yq,
                     "y_min": g[yq].min(), "y_max": g[yq].max()})
    return pd.DataFrame(rows)


