"""Reading magnetic-tweezers rotation curves (extension versus turns at fixed forces).

The data are a long-format table, one row per measured point::

    # instrument: "MT-2"
    molecule, force [pN], turns, extension [um]
    m1, 0.5, -10, 0.41
    m1, 0.5, -9.5, 0.44
    ...

with the columns

* ``force`` (a force unit), ``turns`` (no unit or ``dimensionless``: turns; or an
  angle unit such as ``turn``, ``rad``, ``deg``), ``extension`` (a length unit):
  required;
* ``molecule`` (any label): optional, one label per tethered molecule, read as
  text exactly as written (``01``, ``1`` and ``1.0`` are three molecules);
* ``sigma`` (a length unit): optional, the standard error of each extension;
* ``torque`` (a torque unit, e.g. ``pN nm``): optional, the measured torque of
  each point (sign of the turns), fitted jointly with the extension by
  :func:`~supercoil.fit_hat_curves` (docs/theory/fitting.md#joint-torque-fit);
  ``torque_sigma`` (a torque unit): optional with it, its standard error;
* any other column is kept as it is.

:func:`read_tweezers_csv` reads it with :func:`supercoil.tables.read_csv` (units
in the headers, ``# key: json`` provenance lines) and checks every cell. Every
error is a :class:`~supercoil.exceptions.DataError` that names the problem, the
file line and the column. No row is ever dropped silently: with
``drop_incomplete=True`` rows with a missing value are removed and a
:class:`~supercoil.exceptions.DataWarning` lists them by file line.

The result is a DataFrame in the package's table convention: plain float
magnitudes in the units of the file, ``attrs["units"]`` and
``attrs["provenance"]`` (which also records the source file and the file line
of every row, ``attrs["lines"]``, as runs of consecutive lines).
"""

from __future__ import annotations

import warnings

import numpy as np
import pandas as pd
import pint

from supercoil._checks import check_flag
from supercoil.exceptions import DataError, DataWarning
from supercoil.tables import expand_line_runs, header_hint, is_line_runs, line_runs, read_csv_source
from supercoil.units import U, ureg

__all__ = [
    "COLUMN_DIMENSIONS",
    "OPTIONAL_COLUMNS",
    "REQUIRED_COLUMNS",
    "check_tweezers_frame",
    "read_tweezers_csv",
]

#: Columns every rotation-curve table must have.
REQUIRED_COLUMNS = ("force", "turns", "extension")

#: The dimension each numeric column must have, with the unit used to check it
#: and a description for error messages.
COLUMN_DIMENSIONS = {
    "force": (U.N, "a force (e.g. pN)"),
    "turns": (U.turn, "turns: no unit, or an angle unit (turn, rad, deg)"),
    "extension": (U.m, "a length (e.g. nm, um)"),
    "sigma": (U.m, "a length (e.g. nm), the extension's standard error"),
    "torque": (U.pN * U.nm, "a torque (e.g. pN nm)"),
    "torque_sigma": (U.pN * U.nm, "a torque (e.g. pN nm), the torque's standard error"),
}

#: Optional numeric columns (checked like the required ones when present).
OPTIONAL_COLUMNS = ("sigma", "torque", "torque_sigma")

#: Columns that must be positive.
_POSITIVE = ("force", "sigma", "torque_sigma")


def _unit_for(column, unit_str, where):
    """Parse and check the unit of a numeric column; raise DataError naming it."""
    target, expected = COLUMN_DIMENSIONS[column]
    try:
        unit = ureg.Unit(unit_str) if unit_str else U.dimensionless
    except (pint.UndefinedUnitError, pint.errors.DefinitionSyntaxError, ValueError,
            AttributeError, TypeError) as exc:
        raise DataError(
            f"{where}, column {column!r}: unknown unit {unit_str!r} ({exc}); "
            f"expected {expected}"
        ) from None
    if unit.dimensionality != target.dimensionality:
        shown = f"{unit_str!r}" if unit_str else "no unit"
        raise DataError(
            f"{where}, column {column!r}: {shown} has dimension {unit.dimensionality}, "
            f"expected {expected}"
        )
    return unit


def check_tweezers_frame(df, lines=None, source="data", *, _copy=True) -> pd.DataFrame:
    """Check a rotation-curve table; return it with its numeric columns as floats.

    Used by :func:`read_tweezers_csv` and by the fitting functions for tables
    built in memory.

    Parameters
    ----------
    df : pandas.DataFrame
        Columns ``force``, ``turns``, ``extension`` (optional ``molecule``,
        ``sigma``, ``torque``, ``torque_sigma``) and ``df.attrs["units"]``.
    lines : sequence of int, or runs ``[[first, last], ...]``, optional
        The file line of every row (for error messages), as a sequence or as
        ``attrs["lines"]`` holds it (:func:`supercoil.tables.line_runs`);
        without it rows are named by their DataFrame index.
    source : str
        What to call the table in messages (a file name).

    Raises
    ------
    DataError
        Missing column or units, unknown or wrong-dimension unit, non-numeric
        or missing (NaN) cell, non-positive force, sigma or torque_sigma, a
        ``torque_sigma`` column without ``torque``; the message names the row
        and the column.
    """
    if not isinstance(df, pd.DataFrame):
        raise DataError(f"{source}: expected a pandas DataFrame, got {type(df).__name__}")
    units = df.attrs.get("units")
    hline = df.attrs.get("header_line")
    header = f"{source}, line {hline} (header)" if hline else f"{source}, header"
    if lines is not None and is_line_runs(lines):
        lines = expand_line_runs(lines)
    if lines is not None and len(lines) != len(df):
        lines = None
    if units is None:
        raise DataError(f"{source}: the table has no attrs['units'] (the unit of every column)")
    for col in REQUIRED_COLUMNS:
        if col not in df.columns:
            raise DataError(
                f"{header}: missing column {col!r}; columns found: {list(map(str, df.columns))}"
                + header_hint(",".join(map(str, df.columns)))
            )
    if len(df) == 0:
        raise DataError(f"{source}: the table has no data rows")

    def row_name(i):
        label = df.index[i]
        label = label.item() if hasattr(label, "item") else label
        return f"line {lines[i]}" if lines is not None else f"row {label!r}"

    if "torque_sigma" in df.columns and "torque" not in df.columns:
        raise DataError(f"{header}, column 'torque_sigma': no 'torque' column to go with it")
    out = df.copy() if _copy else df  # read_tweezers_csv owns its frame: checked in place
    for col in (*REQUIRED_COLUMNS, *OPTIONAL_COLUMNS):
        if col not in df.columns:
            continue
        if col not in units:
            raise DataError(f"{header}, column {col!r}: no unit in attrs['units']")
        _unit_for(col, units[col], header)
        raw = df[col]
        is_float = raw.dtype == np.float64  # already numbers: checked without a copy
        values = _checked_values(raw, col, is_float, lambda i: f"{source}, {row_name(i)}")
        if not is_float or _copy:
            out[col] = values
    if "molecule" in df.columns:
        if "molecule" not in units:
            raise DataError(f"{header}, column 'molecule': no entry in attrs['units']")
        miss = np.flatnonzero(_missing_mask(df["molecule"]))
        if miss.size:
            i = int(miss[0])
            raise DataError(f"{source}, {row_name(i)}, column 'molecule': missing label")
    out.attrs = dict(df.attrs)
    return out


def _checked_values(raw, col, is_float, where):
    """Column ``raw`` as floats; DataError naming ``where(row)`` for a bad cell."""
    values = raw.to_numpy() if is_float else pd.to_numeric(
        raw, errors="coerce").to_numpy(dtype=float)
    bad = np.flatnonzero(~np.isfinite(values))
    if bad.size:
        i = int(bad[0])
        cell = raw.iloc[i]
        if _is_missing(cell):
            what = "missing value (empty cell or NaN)"
        elif isinstance(cell, str) and _is_number(cell):
            what = f"non-finite value {cell!r}"
        elif isinstance(cell, float | np.floating):
            what = f"non-finite value {float(cell)!r}"
        else:
            what = f"non-numeric value {cell!r}"
        more = f" ({bad.size - 1} more rows in this column)" if bad.size > 1 else ""
        raise DataError(f"{where(i)}, column {col!r}: {what}{more}")
    if col in _POSITIVE:
        nonpos = np.flatnonzero(values <= 0)
        if nonpos.size:
            i = int(nonpos[0])
            raise DataError(f"{where(i)}, column {col!r}: {col} must be positive, "
                            f"got {float(values[i]):g}")
    return values


def _missing_mask(column):
    """Boolean array: True where a cell is missing (NaN/None, or an NA string), vectorised."""
    mask = column.isna().to_numpy(dtype=bool, copy=True)
    if column.dtype == object or pd.api.types.is_string_dtype(column.dtype):
        # the NA test on the distinct labels only (few: one per molecule), found in
        # blocks (pandas' unique of a whole text column costs ~60 bytes per row)
        labels = set()
        for start in range(0, len(column), 65536):
            labels.update(column.iloc[start:start + 65536].dropna().unique())
        na = [v for v in labels if isinstance(v, str) and v.strip().lower() in _NA_STRINGS]
        if na:
            mask |= column.isin(na).to_numpy(dtype=bool)
    return mask


def _is_missing(cell):
    if cell is None:
        return True
    if isinstance(cell, str):
        return cell.strip().lower() in _NA_STRINGS
    try:
        return bool(pd.isna(cell))
    except (TypeError, ValueError):
        return False


def _is_number(s):
    try:
        float(s)
    except ValueError:
        return False
    return True


# pandas' default NA strings (read_csv's na_values)
_NA_STRINGS = {
    "", "#n/a", "#n/a n/a", "#na", "-1.#ind", "-1.#qnan", "-nan", "1.#ind", "1.#qnan",
    "<na>", "n/a", "na", "null", "nan", "none",
}


def _drop_incomplete(df, lines, source):
    """``df`` (and ``lines``) without the rows that have a missing cell; DataWarning lists them."""
    checked = [c for c in (*REQUIRED_COLUMNS, *OPTIONAL_COLUMNS, "molecule")
               if c in df.columns]
    missing = np.zeros(len(df), dtype=bool)
    for col in checked:
        missing |= _missing_mask(df[col])
    if not missing.any():
        return df, lines
    idx = np.flatnonzero(missing)
    names = [str(lines[i]) if lines is not None else f"data row {i + 1}" for i in idx[:21]]
    shown = ", ".join(names[:20]) + (", ..." if len(names) > 20 else "")
    warnings.warn(
        f"{source}: dropped {idx.size} incomplete row(s) (empty or NaN cell in "
        f"{', '.join(checked)}) at file line(s) {shown}",
        DataWarning,
        stacklevel=3,
    )
    attrs = dict(df.attrs)
    df = df.loc[~missing].reset_index(drop=True)
    df.attrs = attrs
    if lines is not None:
        lines = lines[~missing]
    if len(df) == 0:
        raise DataError(f"{source}: no complete data rows left after dropping")
    return df, lines


def read_tweezers_csv(path, drop_incomplete=False) -> pd.DataFrame:
    """Read a magnetic-tweezers rotation-curve CSV (long format, units in headers).

    Parameters
    ----------
    path : str or Path
        CSV with columns ``force [force unit]``, ``turns`` (no unit = turns, or
        an angle unit), ``extension [length unit]``, optionally ``molecule``
        and ``sigma [length unit]``, ``torque [torque unit]`` (e.g. ``torque
        [pN nm]``) and ``torque_sigma [torque unit]``; ``# key: json`` lines above the header are
        kept as provenance.
    drop_incomplete : bool
        If True, rows with a missing value (empty cell or NaN) in ``force``,
        ``turns``, ``extension``, ``sigma``, ``torque``, ``torque_sigma`` or
        ``molecule`` are removed, and a
        :class:`~supercoil.exceptions.DataWarning` says how many and lists
        their file lines. If False (default) such a row is an error.

    Returns
    -------
    pandas.DataFrame
        The table convention: float magnitudes in the file's units,
        ``attrs["units"]``, ``attrs["provenance"]`` (plus ``"source"``, the
        path) and ``attrs["lines"]``, the file lines of the rows kept as runs
        ``[[first, last], ...]`` of consecutive lines (plain ints, so that
        ``pd.concat`` and copies work; :func:`supercoil.tables.row_lines`
        gives one line per row).

    Raises
    ------
    DataError
        No such file; missing column; unknown unit or unit of the wrong
        dimension; non-numeric, missing or non-finite cell; non-positive force
        sigma or torque_sigma; ``torque_sigma`` without ``torque``; a column
        named twice. The message names the file line and
        the column.
    TypeError
        ``drop_incomplete`` not True/False (e.g. the string ``"False"``), or
        ``path`` not a path.

    Notes
    -----
    The checks are vectorised and the file is streamed (pandas reads the
    body from the open file; the file lines are counted in blocks): measured
    1.2-2x plain ``pandas.read_csv`` for 1e6 rows, and a few bytes per row of
    peak memory beyond the table (benchmark: :mod:`supercoil.benchmark.memory`).

    Examples
    --------
    >>> data = read_tweezers_csv("rotation_curves.csv")  # doctest: +SKIP
    >>> data.attrs["units"]["extension"]  # doctest: +SKIP
    'um'
    """
    drop_incomplete = check_flag(drop_incomplete, "drop_incomplete")
    df, src = read_csv_source(path)
    path = src.path
    with src:
        lines = src.data_lines(len(df))
        header_line = src.header_line
    source = str(path)
    if header_line is not None:
        df.attrs["header_line"] = header_line
    units = df.attrs["units"]
    # header-level checks first (missing columns, units), named by the header line
    hdr = f"{source}, line {header_line} (header)" if header_line else f"{source}, header"
    for col in REQUIRED_COLUMNS:
        if col not in df.columns:
            raise DataError(
                f"{hdr}: missing column {col!r}; columns found: {list(map(str, df.columns))}"
                + header_hint(",".join(map(str, df.columns)))
            )
    for col in (*REQUIRED_COLUMNS, *OPTIONAL_COLUMNS):
        if col in df.columns:
            _unit_for(col, units[col], hdr)
    if drop_incomplete:
        df, lines = _drop_incomplete(df, lines, source)
    out = check_tweezers_frame(df, lines=lines, source=source, _copy=False)
    out.attrs["provenance"] = dict(out.attrs.get("provenance", {}), source=source)
    out.attrs.pop("header_line", None)
    if lines is not None:
        # runs of plain ints: pandas deep-copies and compares attrs (concat), so no array and
        # no per-row list (one deep copy per row on every column access)
        out.attrs["lines"] = line_runs(lines)
    return out
