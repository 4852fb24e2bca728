"""Rotation-curve data of a fit: SI arrays, molecule index and labels, weights.

:class:`RotationData` is built once from a checked table
(:func:`~supercoil.dna.tweezers.check_tweezers_frame`) and is plain and
picklable (numpy arrays and strings), so :func:`~supercoil.fit_many` can send a
molecule's slice to a worker process without pandas or pint.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from supercoil.dna.fitting.fit_parameters import parse_unit
from supercoil.dna.tweezers import check_tweezers_frame
from supercoil.exceptions import FitError
from supercoil.units import U, as_turns, magnitude, ureg

__all__ = ["UNIT_TORQUE_WEIGHT", "UNIT_WEIGHT", "RotationData"]

#: residual scale with unit weights (1 nm); it cancels in the rescaled covariance
UNIT_WEIGHT = 1e-9
#: start scale of the torque residuals without ``torque_sigma`` (1 pN nm); the fit
#: replaces it by the torque channel's own noise estimate
UNIT_TORQUE_WEIGHT = 1e-21


def _column_si(df, units, column, unit, converter=None):
    q = ureg.Quantity(df[column].to_numpy(dtype=float), parse_unit(units[column]))
    if converter is not None:
        return np.asarray(converter(q, column), dtype=float)
    return np.asarray(magnitude(q, unit, f"data column {column!r}"), dtype=float)


@dataclasses.dataclass(frozen=True)
class RotationData:
    """Rotation curves as SI arrays (one entry per data point, in the table's row order).

    Attributes
    ----------
    force : ndarray
        Force (N).
    turns : ndarray
        Applied turns.
    extension : ndarray
        Measured extension (m).
    sigma : ndarray
        Standard error of the extension (m); ``UNIT_WEIGHT`` (1 nm) with unit weights.
    weighting : str
        ``"sigma column"``, ``"sigma argument"`` or ``"unit"``.
    mol_index : ndarray of int
        Molecule of each point (index into ``labels``).
    labels : tuple of str
        Molecule labels in order of first appearance (``("0",)`` without a column).
    has_molecule : bool
        The table had a ``molecule`` column.
    units : dict
        The table's ``attrs["units"]``.
    torque : ndarray or None
        Measured torque (N m), None without a ``torque`` column.
    torque_sigma : ndarray or None
        Standard error of the torque (N m); ``UNIT_TORQUE_WEIGHT`` per point
        without a ``torque_sigma`` column (the fit then estimates the torque noise).
    torque_weighting : str
        ``"sigma column"``, ``"unit"`` or ``""`` (no torque).
    """

    force: np.ndarray
    turns: np.ndarray
    extension: np.ndarray
    sigma: np.ndarray
    weighting: str
    mol_index: np.ndarray
    labels: tuple
    has_molecule: bool
    units: dict
    torque: np.ndarray | None = None
    torque_sigma: np.ndarray | None = None
    torque_weighting: str = ""

    @classmethod
    def from_frame(cls, data, sigma=None, source="data") -> RotationData:
        """Check the table (names the row or file line and column) and convert it to SI."""
        lines = getattr(data, "attrs", {}).get("lines")  # file lines from read_tweezers_csv
        if lines is not None and not data.index.equals(pd.RangeIndex(len(data))):
            lines = None
        df = check_tweezers_frame(data, lines=lines, source=source)
        units = dict(df.attrs["units"])
        if df is data:  # never touch the caller's frame
            df = df.copy(deep=False)
        # without attrs: pandas deep-copies a frame's attrs into every column it hands out
        df.attrs = {}
        force = _column_si(df, units, "force", U.N)
        turns = _column_si(df, units, "turns", U.turn, as_turns)
        extension = _column_si(df, units, "extension", U.m)
        n = len(df)
        if "molecule" in df.columns:
            codes, uniques = pd.factorize(df["molecule"].astype(str), sort=False)
            labels, mol_index, has_molecule = tuple(uniques), codes.astype(np.intp), True
        else:
            labels, mol_index, has_molecule = ("0",), np.zeros(n, dtype=np.intp), False
        if "sigma" in df.columns:
            sig, weighting = _column_si(df, units, "sigma", U.m), "sigma column"
        else:
            sig, weighting = np.full(n, UNIT_WEIGHT), "unit"
        tq = tsig = None
        tweighting = ""
        if "torque" in df.columns:
            tq = _column_si(df, units, "torque", U.N * U.m)
            if "torque_sigma" in df.columns:
                tsig, tweighting = _column_si(df, units, "torque_sigma", U.N * U.m), "sigma column"
            else:
                tsig, tweighting = np.full(n, UNIT_TORQUE_WEIGHT), "unit"
        rot = cls(force, turns, extension, sig, weighting, mol_index, labels, has_molecule,
                  units, tq, tsig, tweighting)
        return rot if sigma is None else rot.with_sigma(sigma)

    def with_sigma(self, sigma) -> RotationData:
        """The same points with the standard error ``sigma`` (Quantity, scalar or per point)."""
        s = np.broadcast_to(np.asarray(magnitude(sigma, U.m, "sigma"), dtype=float), (self.n,))
        if not np.all(np.isfinite(s)) or np.any(s <= 0):
            raise FitError("sigma must be finite and positive", argument="sigma")
        return dataclasses.replace(self, sigma=np.array(s, dtype=float),
                                   weighting="sigma argument")

    @property
    def n(self) -> int:
        return len(self.extension)

    @property
    def n_molecules(self) -> int:
        return len(self.labels)

    def groups(self) -> list[np.ndarray]:
        """Indices of each molecule's points (one stable sort, not one mask per molecule)."""
        order = np.argsort(self.mol_index, kind="stable")
        cuts = np.searchsorted(self.mol_index[order], np.arange(1, self.n_molecules))
        return np.split(order, cuts)

    def take(self, index, label) -> RotationData:
        """The points ``index`` as a one-molecule data set labelled ``label`` (no column)."""
        tq = None if self.torque is None else self.torque[index]
        ts = None if self.torque_sigma is None else self.torque_sigma[index]
        return RotationData(self.force[index], self.turns[index], self.extension[index],
                            self.sigma[index], self.weighting,
                            np.zeros(len(index), dtype=np.intp), (str(label),), False,
                            self.units, tq, ts, self.torque_weighting)

    @property
    def has_torque(self) -> bool:
        return self.torque is not None

    def curve_order(self) -> np.ndarray:
        """Point indices sorted by molecule, force and turns (the curves one after another)."""
        return np.lexsort((self.turns, self.force, self.mol_index))
