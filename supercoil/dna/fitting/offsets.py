"""Extension offsets per force (on request): the fitted model with one offset per curve.

docs/theory/fitting.md#offsets. A molecule is one bead: by default its
extension offset (the bead-height reference) is one value for all its forces
(``fit_extension_offset=True``). With ``fit_extension_offset="per-force"``
each (molecule, force) curve gets its own, named ``extension_offset[0.3 pN]``
(``extension_offset[m1, 0.3 pN]`` with a molecule column), for data whose
curves were referenced separately. A force-calibration or length difference
between curves is another parameter, not this one.

:class:`PerForceOffsetModel` adds these offsets to
:class:`~supercoil.dna.fitting.model.HatCurveModel` (their Jacobian columns
are exact: the weights on the curve's rows).
"""

from __future__ import annotations

import numpy as np

from supercoil.dna.fitting.model import HatCurveModel

__all__ = ["EXTENSION_OFFSET_MODES", "PerForceOffsetModel", "has_per_force_offsets"]

#: accepted values of ``fit_extension_offset``
EXTENSION_OFFSET_MODES = (True, False, "per-molecule", "per-force")


def has_per_force_offsets(params):
    return any(p.owner == "offset" and p.shared == "per-force" for p in params.values())


def curve_rows(data, p):
    """Row indices of the curve of a per-force offset (its molecule at its force)."""
    return np.flatnonzero((data.mol_index == p.molecule)
                          & np.isclose(data.force, p.force, rtol=1e-9, atol=0))


class PerForceOffsetModel(HatCurveModel):
    """:class:`HatCurveModel` with extension offsets per (molecule, force) curve."""

    def __init__(self, data, params, *args, **kw):
        super().__init__(data, params, *args, **kw)
        # per-force physics only when a non-offset parameter is per force
        self._per_force = any(p.shared == "per-force" and p.owner != "offset"
                              for p in params.values())
        self._curves = [(p, curve_rows(data, p)) for p in params.values()
                        if p.owner == "offset" and p.shared == "per-force"]
        self._free_index = {p.name: j for j, p in enumerate(self.free)}

    def points(self, u):
        pts, z0 = super().points(u)
        z0 = np.array(z0, dtype=float)
        for p, rows in self._curves:
            j = self._free_index.get(p.name)
            z0[rows] += p.value if j is None else p.scale * u[j]
        return pts, z0

    def jacobian(self, u):
        J = super().jacobian(u)
        for p, rows in self._curves:
            j = self._free_index.get(p.name)
            if j is not None:
                J[:, j] = 0.0
                J[rows, j] = p.scale * self.w[rows]
        self._jac = (np.asarray(u, dtype=float).copy(), J.copy())
        return J
