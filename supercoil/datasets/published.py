"""Published rotation curves read from the user's copy of the source data (never shipped).

The averaged extension and torque of naked DNA against added turns (about 6.48 kb,
angular optical trap, room temperature) at 0.3, 0.5, 0.75, 1, 1.5 and 2 pN of Qian
et al., "Chromatin buffers torsional stress during transcription", bioRxiv
2024.10.15.618270 (2024), doi:10.1101/2024.10.15.618270, source data in the public
repository WangLabCornell/Qian_et_al, file ``Source Data/Figure S5.xlsx``. That file
is GPL-licensed: the package does not ship it. :func:`read_published_curves` reads
it from a path the user gives (or the environment variable :data:`ENV_VAR`) into
the rotation-curve table of :func:`~supercoil.fit_hat_curves`; the small per-force
summary numbers of its sheets S5C and S5D are shipped, cited, in ``published.csv``
(:func:`load_published_summary`).

Layout of the workbook (sheets S5A, S5B): one pair of columns per force, in the
order 2.00, 1.50, 1.00, 0.75, 0.50, 0.30 pN; row 1 the force (``"2.00 pN
(Magenta)"``), row 2 the column names (``Turns added``, ``Extension (nm)`` or
``Torque (pN∙nm)``), then the values. The forces are read from row 1, not
assumed from the column order. The two sheets have different turns grids.
"""

from __future__ import annotations

import os
import re
from pathlib import Path

import numpy as np

from supercoil import display
from supercoil.exceptions import DataError
from supercoil.tables import make_table, provenance, read_csv

__all__ = ["CITATION", "ENV_VAR", "FILE", "REPOSITORY", "SYNTHETIC_LENGTH_NM",
           "SYNTHETIC_TORQUE_SCALE", "load_published_summary",
           "published_curves_path", "read_published_curves", "write_published_workbook",
           "write_synthetic_workbook"]

#: environment variable holding the path of the user's copy of ``Figure S5.xlsx``
ENV_VAR = "SUPERCOIL_QIAN_S5"
CITATION = ("Qian et al., 'Chromatin buffers torsional stress during transcription', "
            "bioRxiv 2024.10.15.618270 (2024), doi:10.1101/2024.10.15.618270")
REPOSITORY = "github.com/WangLabCornell/Qian_et_al"
FILE = "Source Data/Figure S5.xlsx"
LICENSE_NOTE = ("the source file is GPL-licensed and not shipped; give its path or set "
                f"{ENV_VAR}")
_SHEETS = {"extension": ("S5A", "extension (nm)"), "torque": ("S5B", "torque (pn")}
_FORCE = re.compile(r"^\s*([0-9]*\.?[0-9]+)\s*pN", re.IGNORECASE)


def published_curves_path(path=None):
    """The path of the workbook: ``path``, else the environment variable :data:`ENV_VAR`.

    Returns None when neither is given (callers skip with a message). A given
    path that is not a file raises :class:`~supercoil.exceptions.DataError`.
    """
    if path is None:
        path = os.environ.get(ENV_VAR) or None
        if path is None:
            return None
    p = Path(path)
    if not p.is_file():
        raise DataError(f"{p}: no such file (the Figure S5 workbook of {CITATION}, "
                        f"{REPOSITORY}, {FILE!r}; {LICENSE_NOTE})")
    return p


def _require_openpyxl():
    try:
        import openpyxl
    except ImportError:  # pragma: no cover - openpyxl is in the test extra
        raise ImportError("reading .xlsx files needs openpyxl: pip install 'supercoil[xlsx]'"
                          ) from None
    return openpyxl


def _sheet_columns(wb, path, channel):
    """``{force (pN): (turns, values)}`` of one sheet, each sorted by turns."""
    name, want = _SHEETS[channel]
    if name not in wb.sheetnames:
        raise DataError(f"{path}: no sheet {name!r} (have {wb.sheetnames}); expected the "
                        f"Figure S5 workbook of {CITATION}")
    rows = wb[name].iter_rows(values_only=True)
    try:
        title, header = next(rows), next(rows)
    except StopIteration:
        raise DataError(f"{path}, sheet {name}: fewer than 2 header rows") from None
    pairs = []
    for c in range(0, len(header) - 1, 2):
        m = _FORCE.match(str(title[c] or ""))
        head = str(header[c + 1] or "").lower()
        if m is None or "turns" not in str(header[c] or "").lower() or want not in head:
            raise DataError(f"{path}, sheet {name}, columns {c + 1}-{c + 2}: expected a force "
                            f"('2.00 pN') above 'Turns added' and {want!r}, got "
                            f"{title[c]!r} / {header[c]!r}, {header[c + 1]!r}")
        pairs.append((float(m.group(1)), c))
    data = {f: ([], []) for f, _ in pairs}
    for i, row in enumerate(rows, start=3):
        for f, c in pairs:
            a, b = (row[c], row[c + 1]) if len(row) > c + 1 else (None, None)
            if a is None and b is None:
                continue
            if not all(isinstance(v, int | float) for v in (a, b)):
                raise DataError(f"{path}, sheet {name}, row {i}, columns {c + 1}-{c + 2} "
                                f"({f:g} pN): not a number pair: {a!r}, {b!r}")
            data[f][0].append(float(a))
            data[f][1].append(float(b))
    out = {}
    for f, (t, v) in data.items():
        t, v = np.asarray(t), np.asarray(v)
        if len(t) < 2:
            raise DataError(f"{path}, sheet {name}: fewer than 2 points at {f:g} pN")
        order = np.argsort(t, kind="stable")
        out[f] = (t[order], v[order])
    return out


def _bin_means(edges, t, v):
    idx = np.clip(np.searchsorted(edges, t, side="right") - 1, 0, len(edges) - 2)
    inside = (t >= edges[0]) & (t <= edges[-1])
    n = np.bincount(idx[inside], minlength=len(edges) - 1)
    st = np.bincount(idx[inside], weights=t[inside], minlength=len(edges) - 1)
    sv = np.bincount(idx[inside], weights=v[inside], minlength=len(edges) - 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return n, st / n, sv / n


def _one_force(ext, tq, points_per_force, lo, hi):
    """Turns, extension, torque (or None) of one force and the number of points trimmed."""
    te, ze = ext
    if tq is not None:  # the range both channels cover
        lo, hi = max(lo, te[0], tq[0][0]), min(hi, te[-1], tq[0][-1])
    keep = (te >= lo) & (te <= hi)
    trimmed = int((~keep).sum())
    te, ze = te[keep], ze[keep]
    if len(te) < 2:
        return None, trimmed
    if points_per_force is None:
        tau = None if tq is None else np.interp(te, *tq)
        return (te, ze, tau), trimmed
    edges = np.linspace(te[0], te[-1], int(points_per_force) + 1)
    n, t_mean, z_mean = _bin_means(edges, te, ze)
    ok = n > 0
    tau = None
    if tq is not None:
        nt, _, tau = _bin_means(edges, *tq)
        ok &= nt > 0
        tau = tau[ok]
    return (t_mean[ok], z_mean[ok], tau), trimmed


def _options(path, points_per_force, turns_range):
    """The workbook's path and the turns range ``(lo, hi)``; DataError for bad options."""
    p = published_curves_path(path)
    if p is None:
        raise DataError(f"no path given and {ENV_VAR} is not set: give the path of the Figure "
                        f"S5 workbook ({REPOSITORY}, {FILE!r}); {LICENSE_NOTE}")
    if points_per_force is not None and not (isinstance(points_per_force, int | np.integer)
                                             and points_per_force >= 2):
        raise DataError(f"points_per_force must be an integer >= 2 or None, got "
                        f"{points_per_force!r}")
    if turns_range is None:
        return p, -np.inf, np.inf
    lo, hi = turns_range
    return p, -np.inf if lo is None else float(lo), np.inf if hi is None else float(hi)


def _assemble(p, ext, tq, forces, points_per_force, turns_range):
    """The table's columns for ``forces`` and the points trimmed per force."""
    cols = {"force": [], "turns": [], "extension": [], "torque": []}
    trimmed = {}
    for f in forces:
        if f not in ext or (tq is not None and f not in tq):
            raise DataError(f"{p}: no curve at {f:g} pN (have {sorted(ext)} pN)")
        got, trimmed[f"{f:g} pN"] = _one_force(ext[f], None if tq is None else tq[f],
                                               points_per_force, *turns_range)
        if got is None:
            raise DataError(f"{p}: no points at {f:g} pN in the turns range "
                            f"{list(turns_range)}")
        t, z, tau = got
        cols["force"].append(np.full(len(t), f))
        cols["turns"].append(t)
        cols["extension"].append(z)
        if tq is not None:
            cols["torque"].append(tau)
    return {k: np.concatenate(v) for k, v in cols.items() if v}, trimmed


def read_published_curves(path=None, *, points_per_force=200, torque=True, turns_range=None,
                          forces=None):
    """The Figure S5 rotation curves of Qian et al. (2024) as a rotation-curve table.

    Parameters
    ----------
    path : str or Path, optional
        The user's copy of ``Source Data/Figure S5.xlsx`` of the repository
        WangLabCornell/Qian_et_al; default the environment variable
        ``SUPERCOIL_QIAN_S5``.
    points_per_force : int or None
        About this many points per force: the turns range is cut into this
        many equal bins and each channel is averaged in each bin (bins where a
        channel has no point are left out). None: every point of the
        extension sheet, with the torque linearly interpolated onto its turns.
    torque : bool
        Add the ``torque`` column (sheet S5B). The table then covers, per
        force, only the turns range both sheets cover (the extension points
        outside it are trimmed; their number is in
        ``attrs["provenance"]["trimmed_points"]``).
    turns_range : (float, float), optional
        Keep only the turns in ``[low, high]`` (e.g. ``(-3, None)`` for the
        positive side and the start of the negative one, where DNA melts).
    forces : sequence of float, optional
        Keep only these forces (pN).

    Returns
    -------
    pandas.DataFrame
        ``force [pN], turns, extension [nm][, torque [pN nm]]`` sorted by force
        and turns (the table of :func:`~supercoil.read_tweezers_csv`), with
        ``attrs["provenance"]`` citing the paper, the repository and the file.

    Raises
    ------
    DataError
        No path given and no environment variable; no such file; not the
        expected workbook (names the sheet, row and columns); a force or a
        turns range that leaves no points.
    ImportError
        openpyxl is not installed (``pip install 'supercoil[xlsx]'``).
    """
    p, lo, hi = _options(path, points_per_force, turns_range)
    openpyxl = _require_openpyxl()
    try:
        wb = openpyxl.load_workbook(p, read_only=True, data_only=True)
    except Exception as exc:  # openpyxl raises many kinds on a file that is not a workbook
        raise DataError(f"{p}: cannot be read as an .xlsx workbook ({type(exc).__name__}: "
                        f"{exc})") from None
    try:
        ext = _sheet_columns(wb, p, "extension")
        tq = _sheet_columns(wb, p, "torque") if torque else {}
    finally:
        wb.close()
    wanted = sorted(ext) if forces is None else sorted(float(f) for f in forces)
    table, trimmed = _assemble(p, ext, tq if torque else None, wanted, points_per_force,
                               (lo, hi))
    units = {"force": "pN", "turns": "", "extension": "nm", "torque": "pN nm"}
    prov = provenance(
        source=CITATION, repository=REPOSITORY, file=FILE, path_name=p.name,
        sheets="S5A (extension)" + (", S5B (torque)" if torque else ""),
        points_per_force=points_per_force, turns_range=[lo, hi] if turns_range else None,
        torque=("bin means on the extension's bins" if points_per_force else
                "interpolated linearly onto the extension's turns") if torque else None,
        trimmed_points=trimmed, license=LICENSE_NOTE)
    return make_table(table, {k: units[k] for k in table}, prov)


def load_published_summary():
    """The per-force summary numbers of Figure S5C/S5D of Qian et al. (2024), shipped.

    Returns
    -------
    pandas.DataFrame
        One row per force and side (``"+"``, ``"-"`` supercoiling): ``force
        [pN]``, ``side``, ``slope [nm/turn]`` (post-buckling extension slope,
        signed as in the source: negative on the + side), ``slope_error``,
        ``torque [pN nm]`` (buckling torque on the + side, buckling or
        melting torque on the - side), ``torque_error``, ``source``;
        ``attrs["units"]`` and the citation in ``attrs["provenance"]``.
    """
    from importlib import resources

    path = Path(str(resources.files("supercoil.datasets") / "published.csv"))
    return read_csv(path, text_columns=("side", "source"))


def write_published_workbook(table, path):
    """Write rotation curves in the layout of the Figure S5 workbook (tests, examples).

    ``table``: ``force [pN], turns, extension, torque`` (any length and torque
    units; the :func:`~supercoil.read_tweezers_csv` convention). Sheet S5A holds
    the even rows of each curve, S5B the odd rows (two turns grids, as in the
    source), forces in descending order as in the source. Returns the path.
    """
    from supercoil.dna.fitting.data import RotationData

    openpyxl = _require_openpyxl()
    rot = RotationData.from_frame(table, source="write_published_workbook table")
    if not rot.has_torque:
        raise DataError("write_published_workbook needs a 'torque' column")
    wb = openpyxl.Workbook()
    wb.remove(wb.active)
    forces = np.unique(rot.force)[::-1]
    for sheet, values, head, rows in (
            ("S5A", display.to_display(rot.extension, "extension"), "Extension (nm)", 0),
            ("S5B", display.to_display(rot.torque, "torque"), "Torque (pN\u2219nm)", 1)):
        ws = wb.create_sheet(sheet)
        cols = []
        for f in forces:
            sel = np.flatnonzero(rot.force == f)
            sel = sel[np.argsort(rot.turns[sel], kind="stable")][rows::2]
            cols.append((rot.turns[sel], values[sel]))
        ws.append([x for f in forces for x in (display.text(f, "force", ".2f"), None)])
        ws.append(["Turns added", head] * len(forces))
        for i in range(max(len(t) for t, _ in cols)):
            ws.append([float(x) if i < len(t) else None for t, v in cols
                       for x in ((t[i], v[i]) if i < len(t) else (None, None))])
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    wb.save(path)
    return path


#: the construct's contour length the synthetic stand-in is made with: about 6.48 kb x
#: 0.338 nm/bp (the paper's construct size, text)
SYNTHETIC_LENGTH_NM = 2190.0
#: the torque scale of the synthetic stand-in: measured torque = model torque / 0.8
SYNTHETIC_TORQUE_SCALE = 0.8


def write_synthetic_workbook(path, *, points_per_force=60, seed=20261201):
    """A stand-in for the Figure S5 workbook: the same layout, synthetic curves (no GPL data).

    ``marko2007`` curves of the ``dna`` set with the length
    :data:`SYNTHETIC_LENGTH_NM` at the six forces of the source (2 to 0.3 pN),
    ``points_per_force`` points each, 3 nm extension noise and 0.3 pN nm torque
    noise, a turns offset of 0.6 turn, no extension offset (absolute extensions,
    as the averaged published curves), and the measured torque the model torque
    divided by :data:`SYNTHETIC_TORQUE_SCALE` (a torque calibration the fit's
    ``torque_scale`` recovers). Written by :func:`write_published_workbook`;
    returns the path. For tests, examples and the tutorial without the user's copy.
    """
    from supercoil.dna.fitting.simulate import simulate_rotation_curves
    from supercoil.parameters import load_parameters
    from supercoil.units import U

    dna = load_parameters("dna").replace(length=SYNTHETIC_LENGTH_NM * U.nm)
    forces = np.array([2.0, 1.5, 1.0, 0.75, 0.5, 0.3]) * U.pN
    table = simulate_rotation_curves(dna, forces, model="marko2007",
                                     points_per_force=points_per_force, noise=3 * U.nm,
                                     torque_noise=0.3 * U.pN * U.nm, turns_offset=0.6,
                                     extension_offset=0 * U.nm, seed=seed,
                                     extension_unit="nm")
    table["torque"] = table["torque"] / SYNTHETIC_TORQUE_SCALE
    return write_published_workbook(table, path)
