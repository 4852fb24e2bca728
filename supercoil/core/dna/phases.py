"""The phase interface of the real-DNA model: per-length Gibbs free energy and derivatives.

A phase of the molecule is described by its Gibbs free energy per unit B-DNA contour
length in the (force F, torque M) ensemble, with its derivatives (SI floats, broadcast):

* ``phi(F, M)`` (J/m = N);
* ``dphi/dF = -x`` (dimensionless: extension per B contour length of that phase);
* ``dphi/dM = -Omega`` (1/m: excess twist density relative to relaxed B-DNA, rad/m);
* ``d2phi/dM2 = -dOmega/dM`` (1/(N m^2), negative).

Each phase module exposes ``<phase>_gibbs(F, M, *params) -> PhaseGibbs``.
Float-only kernel.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["PhaseGibbs"]


class PhaseGibbs(NamedTuple):
    """Gibbs free energy per B contour length of one phase and its derivatives (SI)."""

    phi: np.ndarray  # J/m (= N)
    dphi_dF: np.ndarray  # dimensionless, = -extension per contour length
    dphi_dM: np.ndarray  # 1/m, = -excess twist density (rad/m)
    d2phi_dM2: np.ndarray  # 1/(N m^2), = -dOmega/dM (negative)
