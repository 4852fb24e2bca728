"""Thermodynamic consistency of measured extension and torque: :func:`maxwell_check`.

docs/theory/fitting.md#maxwell-check. With the free enthalpy ``G(F, N)``,
``dG = -z dF + 2 pi tau dN``, the Maxwell relation is ``dz/dN = -2 pi dtau/dF``;
in the coexistence of the stretched and the plectoneme phase the torque is the
plateau torque ``tau_b(F)`` at every N, so the post-buckling slope is

    dz/dN = -2 pi dtau_b/dF        (N in turns, tau in pN nm, F in pN: nm/turn).

From the data alone, per force and side: the plateau torque and the buckling
turns from a hinge fit of the torque (linear rise, then a plateau), the slope
from a straight-line fit of the extension past buckling, in the same window
the mean torque as ``tau_b``. Per force also the twist stiffness of the stretched
DNA from the same torque channel: the slope ``dtau/dN`` of a straight line
through the torques before buckling on both sides, and, with a DNA of known
length and temperature, ``C_eff = L (dtau/dN) / (2 pi kT)`` (the pre-buckling
torque ``tau = 2 pi kT C_eff N / L``). The summary ratio is the rise of the plateau
torque between the lowest and the highest force over the rise the slopes allow,
``[tau_b(F_max) - tau_b(F_min)] / [-(1/2 pi) integral slope dF]`` (trapezoid
rule): 1 for consistent channels, ``k`` when the torque is k times the torque
that goes with the extensions (a torque calibration off by k).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pandas as pd

from supercoil import display
from supercoil.dna.fitting.data import RotationData
from supercoil.exceptions import DataError
from supercoil.tables import make_table, provenance

__all__ = ["MaxwellCheck", "maxwell_check"]

_TWO_PI = 2.0 * math.pi
_COLUMNS = {"force": "pN", "side": "", "centre": "turn", "buckling_turns": "turn",
            "window_start": "turn", "window_end": "turn", "n_points": "", "slope": "nm/turn",
            "slope_error": "nm/turn",
            "plateau_torque": "pN nm", "plateau_torque_error": "pN nm",
            "maxwell_slope": "nm/turn", "maxwell_slope_error": "nm/turn",
            "twist_slope": "pN nm/turn", "twist_slope_error": "pN nm/turn",
            "twist_stiffness": "nm", "twist_stiffness_error": "nm", "note": ""}


def _centre(turns, tau):
    """Turns where the torque crosses zero: a line through the points with small |tau|."""
    small = np.abs(tau) < 0.5 * min(tau.max(), -tau.min())
    if small.sum() < 3 or np.ptp(turns[small]) <= 0:
        raise DataError("the torque does not change sign around a linear region: no "
                        "centre of the rotation curve")
    a, b = np.polyfit(turns[small], tau[small], 1)
    if a <= 0:
        raise DataError("the torque falls with the turns near its zero (sign convention: "
                        "positive torque for positive turns)")
    return -b / a


def _hinge(x, tau):
    """``(x_b, tau_b)`` of ``tau = tau_b min(x / x_b, 1)`` by least squares (x >= 0)."""
    cand = np.unique(x)[1:-2]
    if len(cand) < 3:
        return None
    g = np.minimum(x[None, :] / cand[:, None], 1.0)
    tb = (g @ tau) / np.einsum("ij,ij->i", g, g)
    sse = np.einsum("ij,ij->i", tau[None, :] - tb[:, None] * g, tau[None, :] - tb[:, None] * g)
    k = int(np.argmin(sse))
    return float(cand[k]), float(tb[k])


def _line(x, y):
    """Slope and its standard error of a straight-line fit."""
    a, b = np.polyfit(x, y, 1)
    r = y - (a * x + b)
    s2 = r @ r / max(len(x) - 2, 1)
    return float(a), float(math.sqrt(s2 / np.sum((x - x.mean()) ** 2)))


def _one_side(x, z, tau, margin, floor):
    """Per side (turns from the centre, >= 0; torque positive): the row's numbers or a note."""
    hinge = _hinge(x, tau)
    if hinge is None:
        return None, "too few points on this side"
    xb, tb = hinge
    if not (tb > 0 and xb < x.max()):
        return None, "no torque plateau (the curve does not buckle within the data)"
    start = xb + max(1.0, margin * (x.max() - xb))
    zb = np.interp(xb, x, z)
    sel = (x >= start) & (z >= floor * zb)
    if sel.sum() < 5:
        return None, "fewer than 5 points past buckling"
    slope, slope_err = _line(x[sel], z[sel])
    t = tau[sel]
    return (xb, start, float(x[sel].max()), int(sel.sum()), slope, slope_err, float(t.mean()),
            float(t.std(ddof=1) / math.sqrt(len(t)))), ""


def _twist(nn, tt, c, buckling, margin):
    """``(dtau/dN, its standard error)`` before buckling, or NaNs with no plateau.

    The straight line through the torques within ``(1 - margin)`` of the nearer
    buckling turns on both sides of the centre ``c`` (at least 4 points).
    """
    xb = [b for b in buckling if np.isfinite(b)]
    if c is None or not xb:
        return np.nan, np.nan
    sel = np.abs(nn - c) <= (1.0 - margin) * min(xb)
    if sel.sum() < 4 or np.ptp(nn[sel]) <= 0:
        return np.nan, np.nan
    return _line(nn[sel], tt[sel])


def _derivative(f, y, e):
    """dy/dF and its error: second-order differences (non-uniform forces, one-sided
    second order at the ends; numpy.gradient), the error propagated linearly."""
    n = len(f)
    if n < 2:
        return np.full(n, np.nan), np.full(n, np.nan)
    order = 2 if n >= 3 else 1
    d = np.gradient(y, f, edge_order=order)
    coef = np.array([np.gradient(col, f, edge_order=order) for col in np.eye(n)]).T
    return d, np.sqrt((coef**2) @ (e**2))


@dataclasses.dataclass
class MaxwellCheck:
    """The result of :func:`maxwell_check` (per-force numbers and the summary ratio).

    Attributes
    ----------
    rows : list of dict
        One per molecule, side and force (see :meth:`to_table`).
    summary : dict
        Per side (``"+"``, ``"-"``; with several molecules ``"<molecule> +"``): the
        ``ratio`` (rise of the plateau torque over the rise the slopes allow) and its
        ``ratio_error``, ``torque_rise`` and ``slope_rise`` (pN nm), the forces used.
    """

    rows: list
    summary: dict

    @property
    def ratio(self) -> float:
        """The summary ratio of the + side (NaN only with a note in :attr:`summary`)."""
        keys = [k for k in self.summary if k.endswith("+")]
        if not keys:
            return float("nan")
        return self.summary[keys[0]]["ratio"]

    @property
    def ratio_error(self) -> float:
        keys = [k for k in self.summary if k.endswith("+")]
        return self.summary[keys[0]]["ratio_error"] if keys else float("nan")

    def to_table(self) -> pd.DataFrame:
        """Per-force table: plateau torque, slope, the slope the Maxwell relation gives.

        Columns (units in ``attrs["units"]``): ``[molecule,] force [pN], side,
        centre`` (the turns where the torque crosses zero: an estimate of the
        turns offset), ``buckling_turns, window_start, window_end`` (turns from
        the centre),
        ``n_points, slope, slope_error`` (nm/turn), ``plateau_torque,
        plateau_torque_error`` (pN nm, signed), ``maxwell_slope,
        maxwell_slope_error`` (``-2 pi dtau_b/dF``, nm/turn), ``note`` (why a
        row has no numbers, else empty).
        """
        cols = {k: [r[k] for r in self.rows] for k in ("molecule", *_COLUMNS)
                if k != "molecule" or any(r.get("molecule") is not None for r in self.rows)}
        units = {"molecule": "", **_COLUMNS}
        return make_table(cols, {k: units[k] for k in cols},
                          provenance(check="maxwell", summary=self.summary))

    def lines(self, torque_scale=None) -> list[str]:
        """Report lines: the ratio per side with its error and the rises, then the
        twist stiffness per force (:meth:`twist_lines`)."""
        return [*self._ratio_lines(), *self.twist_lines(torque_scale)]

    def twist_lines(self, torque_scale=None) -> list[str]:
        """The pre-buckling twist stiffness per force (molecule): ``C_eff`` in nm
        with a DNA, else the torque slope in pN nm/turn; with ``torque_scale``
        (a fit's, model torque = scale x measured) also ``C_eff`` times it, the
        stretched phase's stiffness that fit's model has to give."""
        out = []
        for label in dict.fromkeys(r.get("molecule") for r in self.rows):
            part = [r for r in self.rows if r.get("molecule") == label and r["side"] == "+"
                    and np.isfinite(r["twist_slope"])]
            if not part:
                continue
            forces = " / ".join(f"{r['force']:g}" for r in part)
            who = "" if label is None else f" ({label})"
            if np.isfinite(part[0]["twist_stiffness"]):
                vals = [r["twist_stiffness"] for r in part]
                text = f"C_eff {' / '.join(f'{v:.1f}' for v in vals)} nm"
                if torque_scale is not None and torque_scale != 1:
                    text += (f"; x torque scale {torque_scale:.3g}: "
                             f"{' / '.join(f'{v * torque_scale:.1f}' for v in vals)} nm")
            else:
                text = ("torque slope " + " / ".join(f"{r['twist_slope']:.3g}" for r in part)
                        + " pN nm/turn")
            out.append(f"    twist stiffness{who}: {text} at {forces} pN (the torque before "
                       "buckling; docs/theory/fitting.md#maxwell-check)")
        return out

    def _ratio_lines(self) -> list[str]:
        out = []
        for key, s in self.summary.items():
            if not np.isfinite(s["ratio"]):
                out.append(f"    Maxwell check {key:<3}: {s['note']}")
                continue
            out.append(
                f"    Maxwell check {key:<3}: plateau-torque rise {s['torque_rise']:.3g} pN nm "
                f"({s['forces'][0]:g}-{s['forces'][-1]:g} pN), the slopes allow "
                f"{s['slope_rise']:.3g}: ratio {s['ratio']:.3f} ± {s['ratio_error']:.3f} "
                "(1: extension and torque consistent; docs/theory/fitting.md#maxwell-check)")
        return out

    def __repr__(self):
        return "MaxwellCheck\n" + "\n".join(self.lines())


def _summary(rows):
    ok = [r for r in rows if not r["note"]]
    if len(ok) < 2:
        return {"ratio": float("nan"), "ratio_error": float("nan"),
                "note": f"{len(ok)} force(s) with a plateau: needs at least 2"}
    f = np.array([r["force"] for r in ok])
    s = np.array([r["slope"] for r in ok])
    se = np.array([r["slope_error"] for r in ok])
    t = np.array([r["plateau_torque"] for r in ok])
    te = np.array([r["plateau_torque_error"] for r in ok])
    w = np.zeros(len(f))  # trapezoid weights
    w[1:] += np.diff(f) / 2
    w[:-1] += np.diff(f) / 2
    allowed = -(w @ s) / _TWO_PI
    allowed_e = math.sqrt(np.sum((w * se) ** 2)) / _TWO_PI
    rise, rise_e = t[-1] - t[0], math.hypot(te[-1], te[0])
    ratio = rise / allowed if allowed != 0 else float("nan")
    err = abs(ratio) * math.hypot(rise_e / rise, allowed_e / allowed) if rise else float("inf")
    return {"ratio": float(ratio), "ratio_error": float(err), "torque_rise": float(rise),
            "torque_rise_error": float(rise_e), "slope_rise": float(allowed),
            "slope_rise_error": float(allowed_e), "forces": [float(x) for x in f], "note": ""}


def _curves(rot, idx, margin, floor, label):
    rows = []
    n, f_all = rot.turns[idx], display.to_display(rot.force[idx], "force")
    z = display.to_display(rot.extension[idx], "extension")
    tau = display.to_display(rot.torque[idx], "torque")
    for f in np.unique(f_all):
        sel = f_all == f
        order = np.argsort(n[sel], kind="stable")
        nn, zz, tt = n[sel][order], z[sel][order], tau[sel][order]
        try:
            c = _centre(nn, tt)
            note = ""
        except DataError as exc:
            c, note = None, str(exc)
        for side, sgn in (("+", 1.0), ("-", -1.0)):
            row = {"molecule": label, "force": float(f), "side": side,
                   "centre": np.nan if c is None else float(c)}
            got = None
            if c is not None:
                m = sgn * (nn - c) >= 0
                x, k = sgn * (nn[m] - c), np.argsort(sgn * (nn[m] - c), kind="stable")
                got, note_side = _one_side(x[k], zz[m][k], sgn * tt[m][k], margin, floor)
            else:
                note_side = note
            keys = ("buckling_turns", "window_start", "window_end", "n_points", "slope",
                    "slope_error", "plateau_torque", "plateau_torque_error")
            vals = got if got is not None else (np.nan,) * 3 + (0,) + (np.nan,) * 4
            row.update(zip(keys, vals, strict=True))
            if got is not None:  # back to the signs of the data
                row["slope"] *= sgn
                row["plateau_torque"] *= sgn
            row["note"] = note_side
            rows.append(row)
        slope, err = _twist(nn, tt, c, [r["buckling_turns"] for r in rows[-2:]], margin)
        for r in rows[-2:]:
            r["twist_slope"], r["twist_slope_error"] = slope, err
    for side in ("+", "-"):
        part = [r for r in rows if r["side"] == side]
        ok = [r for r in part if not r["note"]]
        d, de = _derivative(np.array([r["force"] for r in ok]),
                            np.array([r["plateau_torque"] for r in ok]),
                            np.array([r["plateau_torque_error"] for r in ok]))
        for r in part:
            r["maxwell_slope"] = r["maxwell_slope_error"] = np.nan
        for r, di, dei in zip(ok, d, de, strict=True):
            r["maxwell_slope"], r["maxwell_slope_error"] = -_TWO_PI * di, _TWO_PI * dei
    return rows


def maxwell_check(data, *, margin=0.1, floor=0.2, dna=None) -> MaxwellCheck:
    """How consistent the extension and torque channels of rotation curves are (data alone).

    Per force and side: the plateau torque ``tau_b`` and the post-buckling
    slope ``dz/dN``; the Maxwell relation in coexistence, ``dz/dN = -2 pi
    dtau_b/dF`` (docs/theory/fitting.md#maxwell-check), compared as the ratio
    of the rise of ``tau_b`` over the force range to the rise the slopes allow.

    Parameters
    ----------
    data : pandas.DataFrame
        Rotation-curve table with a ``torque`` column (:func:`read_tweezers_csv`
        convention), at least two forces; with a ``molecule`` column each
        molecule is checked alone.
    margin : float
        The slope window starts this fraction of the post-buckling turns range
        (at least 1 turn) past the buckling turns, to skip the transition.
    floor : float
        The window ends where the extension falls below this fraction of the
        extension at buckling.
    dna : DNA, optional
        The molecule's parameter set: its contour length and temperature turn
        the pre-buckling torque slope into the twist stiffness ``C_eff`` (nm;
        without it the ``twist_stiffness`` column is NaN and only the slope is
        given).

    Returns
    -------
    MaxwellCheck
        ``ratio`` and ``ratio_error`` (+ side), ``summary`` per side,
        :meth:`~MaxwellCheck.to_table` with the per-force numbers.

    Raises
    ------
    DataError
        The table is malformed or has no ``torque`` column.
    """
    rot = RotationData.from_frame(data, source="maxwell_check data")
    if not rot.has_torque:
        raise DataError("maxwell_check needs a 'torque' column (pN nm) besides the extension")
    if not (0 <= float(margin) < 1 and 0 <= float(floor) < 1):
        raise DataError(f"margin and floor must lie in [0, 1), got {margin!r}, {floor!r}")
    per_slope = np.nan  # C_eff / (dtau/dN) = L / (2 pi kT), nm per (pN nm/turn)
    if dna is not None:
        si = dna.si
        per_slope = display.to_display(si.length, "extension") / (
            _TWO_PI * display.to_display(si.kT, "torque"))
    rows, summary = [], {}
    for i, idx in enumerate(rot.groups()):
        label = rot.labels[i] if rot.has_molecule else None
        part = _curves(rot, idx, float(margin), float(floor), label)
        for r in part:
            r["twist_stiffness"] = per_slope * r["twist_slope"]
            r["twist_stiffness_error"] = per_slope * r["twist_slope_error"]
        rows += part
        for side in ("+", "-"):
            key = side if label is None else f"{label} {side}"
            summary[key] = _summary([r for r in part if r["side"] == side])
    return MaxwellCheck(rows, summary)


def report_lines(result) -> list[str]:
    """The Maxwell-check lines of a fit report (none without torque data)."""
    if not result.spec.data.has_torque:
        return []
    scale = result.solution.calibration.get("torque_scale", 1.0)
    try:
        return maxwell_check(result.data, dna=result.dna).lines(torque_scale=scale)
    except DataError as exc:
        return [f"    Maxwell check      : not measurable ({exc})"]
