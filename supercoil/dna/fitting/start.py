"""Before a fit: which parameters the model uses, and start values read from the data.

docs/theory/fitting.md#start-values. Three checks on the data and the model,
all at the float level (SI, turns):

* :func:`unused_parameters`: a parameter whose change leaves the model's
  extensions and torques bit-identical is not used by the model (``radius`` in
  ``marko2007``, ``end_loop_writhe`` with the end loop off); the default
  ``vary`` drops it (issue 22).
* :func:`length_start` and :func:`length_excess`: the contour length from the
  extensions at the turns nearest zero (Marko-Siggia worm-like chain
  inverted), and the check that the extensions do not exceed the length.
* :func:`turns_offset_start`: the zero of the turns from every channel that
  locates it (torque zero crossing, hat symmetry), chosen robustly.
"""

from __future__ import annotations

import math

import numpy as np

from supercoil.dna.fitting.model import dna_si
from supercoil.exceptions import NoEquilibriumError, ValidityError

__all__ = ["unused_parameters"]

_KERNEL_ERRORS = (NoEquilibriumError, ValidityError, FloatingPointError, ZeroDivisionError)
_SAMPLE = 48  # points at which the use of a parameter is tested
_HELIX_PITCH = 3.57e-9  # m of B-DNA per helical turn (10.5 bp x 0.34 nm): turns per length


def _sample(force, dna):
    """A grid over supercoiling densities -0.05..0.05 at up to four of the data's forces.

    Not the data points: the question is whether the *model* uses a parameter
    (data that do not determine it are the Jacobian's business).
    """
    forces = np.unique(force)
    if len(forces) > 4:
        forces = forces[np.linspace(0, len(forces) - 1, 4).round().astype(int)]
    n_max = 0.05 * dna.length / _HELIX_PITCH
    turns = np.linspace(-n_max, n_max, _SAMPLE // len(forces))
    return np.tile(turns, len(forces)), np.repeat(forces, len(turns))


def _outputs(model, turns, force, dna, thermal, inter):
    pts = model.points(turns, force, dna, thermal, inter, None)
    return np.asarray(pts.extension, dtype=float), np.asarray(pts.torque, dtype=float)


def _perturbed(value, lower=-math.inf, upper=math.inf):
    for v in (value * 1.1, value * 0.9) if value != 0 else (0.1, -0.1):
        if lower < v < upper:
            return v
    return 0.5 * (lower + upper) if math.isfinite(upper - lower) else value + 1.0


def unused_parameters(names, force, dna, model, inter, thermal, xi_is_bending=True):
    """The ``names`` (DNA fields, model or interaction parameters) the model does not use.

    Each is changed by 10 % (within its declared range) on a grid of 48
    points (supercoiling densities -0.05 to 0.05 at up to four of the forces
    ``force``); a parameter is unused when the model's extensions and torques
    stay bit-identical. Returns ``[]`` when the model fails on the grid
    (nothing can be told).
    """
    turns, force = _sample(np.asarray(force, float), dna)
    try:
        z0, t0 = _outputs(model, turns, force, dna, thermal, inter)
    except _KERNEL_ERRORS:
        return []
    out = []
    for name in names:
        m, i, d = model, inter, dna
        if name in model.parameters:
            spec = model.parameters[name]
            m = model.replace(**{name: _perturbed(model.values[name], spec.lower, spec.upper)})
        elif name in getattr(inter, "parameters", {}):
            spec = inter.parameters[name]
            i = inter.replace(**{name: _perturbed(inter.values[name], spec.lower, spec.upper)})
        else:
            d = dna_si(dna, {name: _perturbed(getattr(dna, name), 0.0)}, xi_is_bending)
        try:
            z, t = _outputs(m, turns, force, d, thermal, i)
        except _KERNEL_ERRORS:
            continue
        if np.array_equal(z, z0, equal_nan=True) and np.array_equal(t, t0, equal_nan=True):
            out.append(name)
    return out
