"""Force spread between averaged molecules: the Gauss-Hermite average of a model's points.

A published rotation curve is often the average of the curves of several
molecules, each held by its own bead or trapped particle. Their calibrations
differ (a magnetic bead's moment, a trapped particle's size), so at one nominal
force the molecules feel different true forces. The calibration
nuisance parameter ``force_spread`` (``s``, dimensionless) is the relative
standard deviation of that true force: with ``xi`` a standard normal variable,
the model of the averaged curve is (docs/theory/fitting.md#force-spread-of-averaged-curves)::

    y(N; F) = E_xi[ y_model(N; force_scale x F x (1 + s xi)) ]
            ~ sum_k w_k y_model(N; force_scale x F x (1 + s xi_k))

for the extension and the torque alike, with the probabilists' Gauss-Hermite
nodes ``xi_k`` and weights ``w_k`` (normalised to sum 1) of
:func:`numpy.polynomial.hermite_e.hermegauss`.

Node count
----------
:data:`NODE_COUNT` = 5, from a measurement of the quadrature error against a
229-point trapezoid average over ``xi`` in [-3.8, 3.8] (renormalised), for the
ensemble model with the parameter set ``dna_qian2024_fit``, turns -30..30 and
s = 0.16 (about the spread of the real averaged curves). The torque error is below
0.015 pN nm at every force and node count from 3 on. The extension error (RMS over
the turns / largest) with 5 nodes: 0.07 / 0.1 nm at 0.3 and 2 pN, 0.09 / 0.3 nm at
1.5 pN, but 7.1 / 31 nm at 0.75 pN and 3.9 / 16 nm at 1 pN, where the curves of
the lower node forces are steep (melting on the negative side; the largest error
at -30 turns); 7, 9 and 11 nodes give 5.6, 4.6 and 3.9 nm (0.75 pN) and 5.4, 2.3
and 0.8 nm (1 pN): the integrand is not smooth there and the error falls slowly and
not steadily. Each node costs one model evaluation and more nodes lower the largest
allowed spread (below), so the count is 5; the error is below the extension
residual of the real-data fit (docs/theory/ensemble.md) but not negligible at the
steep ends of the 0.75 and 1 pN curves.

Positivity
----------
Every node force must stay positive: ``1 + s xi_k > 0`` for the most negative
node. The optimiser's upper bound is :data:`FORCE_SPREAD_MAX` (the lowest node
force at 10 % of the nominal one); a value outside ``[0, FORCE_SPREAD_MAX]``
raises :class:`~supercoil.exceptions.FitError` naming ``force_spread``
(:func:`check_force_spread`).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.polynomial.hermite_e import hermegauss

from supercoil.core.dna.interface import HatPoints
from supercoil.exceptions import FitError

__all__ = ["FORCE_SPREAD_MAX", "FORCE_SPREAD_START", "NODES", "NODE_COUNT", "WEIGHTS",
           "check_force_spread", "spread_average", "spread_nodes"]

#: Gauss-Hermite node count (see the module docstring for the measurement behind it)
NODE_COUNT = 5
NODES, _W = hermegauss(NODE_COUNT)
#: weights normalised to sum 1 (an average over the standard normal)
WEIGHTS = _W / _W.sum()
#: upper bound of force_spread: the lowest node force is 10 % of the nominal force
FORCE_SPREAD_MAX = 0.9 / float(np.max(np.abs(NODES)))
#: start value of a varied force_spread given no start: the averaged curve is even in s
#: (its derivative in s vanishes at 0), so a fit started at 0 could not leave it
FORCE_SPREAD_START = 0.1


def check_force_spread(value):
    """``value`` as a float; FitError naming ``force_spread`` outside ``[0, FORCE_SPREAD_MAX]``."""
    s = float(value)
    if not (math.isfinite(s) and 0.0 <= s <= FORCE_SPREAD_MAX):
        raise FitError(f"force_spread = {value!r} is outside [0, {FORCE_SPREAD_MAX:.4g}]: the "
                       f"{NODE_COUNT}-node Gauss-Hermite average needs every node force "
                       f"F (1 + force_spread x xi), xi down to {NODES.min():.4g}, at 10 % of "
                       "F or more")
    return s


def spread_nodes(turns, force, spread):
    """The node points of a spread ``spread``: ``(turns, force, factor)`` tiled node by node.

    The model is to be evaluated at ``force x factor`` (``factor = 1 + spread x xi_k``,
    node ``k`` in block ``k``); :func:`spread_average` takes the result back.
    """
    s = check_force_spread(spread)
    turns = np.asarray(turns, dtype=float)
    n = len(turns)
    return (np.tile(turns, NODE_COUNT), np.tile(np.asarray(force, dtype=float), NODE_COUNT),
            np.repeat(1.0 + s * NODES, n))


def spread_average(pts, n):
    """The weighted node average of points from :func:`spread_nodes` (``n`` data points).

    Extension, torque and the other float arrays: the Gauss-Hermite mean. The
    phase: the highest over the nodes (the most coiled molecule); the short-tail
    flag: any node. The kernel's summary (of the node call) is dropped.
    """
    out = []
    for a in pts[:-1]:
        if a is None:
            out.append(None)
            continue
        a = np.asarray(a)
        if a.size != NODE_COUNT * n:  # e.g. an empty array of a model without the field
            out.append(a)
            continue
        blocks = a.reshape(NODE_COUNT, n)
        if a.dtype == bool:
            out.append(blocks.any(axis=0))
        elif np.issubdtype(a.dtype, np.integer):
            out.append(blocks.max(axis=0))
        else:
            out.append(WEIGHTS @ blocks)
    return HatPoints(*out, None)
