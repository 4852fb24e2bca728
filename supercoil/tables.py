"""The package's one table convention, and CSV input/output for it.

Every tabular output of supercoil is a :class:`pandas.DataFrame` of plain
float magnitudes (or strings and booleans for labels and flags) with

* ``df.attrs["units"]``: ``{column: unit string}`` for every column (``""`` for
  dimensionless numbers and for non-numeric columns);
* ``df.attrs["provenance"]``: ``{"supercoil_version": ..., "parameters": {...},
  ...}``, the package version and the parameters that made the table.

On disk (:func:`write_csv`) the units go into the headers (``pitch [mm]``) and
the provenance into ``#`` comment lines above them, one ``# key: <json>`` line
per entry. :func:`read_csv` reads both back into the same convention.
"""

from __future__ import annotations

import io
import json
import re
from pathlib import Path

import numpy as np
import pandas as pd

from supercoil._csvfile import CsvFile
from supercoil.exceptions import DataError

__all__ = ["column_quantity", "line_runs", "make_table", "provenance", "read_csv", "row_lines",
           "write_csv"]

_HEADER = re.compile(r"^\s*(?P<name>.*?)\s*(?:\[(?P<unit>[^\]]*)\])?\s*$")


def provenance(parameters=None, **extra):
    """Provenance dict: package version, the parameters, and any ``extra`` entries.

    ``parameters`` may be a material (anything with ``as_dict()``), a dict, or
    None. Values in ``extra`` must be JSON-serialisable (quantities are
    written as strings).
    """
    from supercoil import __version__

    if parameters is not None and hasattr(parameters, "as_dict"):
        parameters = parameters.as_dict()
    out = {"supercoil_version": __version__, "parameters": _jsonable(parameters or {})}
    out.update({k: _jsonable(v) for k, v in extra.items()})
    return out


def _jsonable(v):
    if isinstance(v, dict):
        return {str(k): _jsonable(x) for k, x in v.items()}
    if isinstance(v, list | tuple):
        return [_jsonable(x) for x in v]
    if hasattr(v, "units") and hasattr(v, "magnitude"):
        mag = v.magnitude
        if np.ndim(mag):
            return [f"{m:.12g} {v.units:~}" for m in np.ravel(mag)]
        return f"{mag:.12g} {v.units:~}"
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, str | int | float | bool) or v is None:
        return v
    return str(v)


def make_table(columns, units, provenance_dict=None) -> pd.DataFrame:
    """Build a DataFrame in the package's convention.

    Parameters
    ----------
    columns : dict of str -> array-like
        Column data (plain magnitudes), in order.
    units : dict of str -> str
        Unit string of every column (``""`` for dimensionless or labels).
    provenance_dict : dict, optional
        From :func:`provenance`.
    """
    missing = [c for c in columns if c not in units]
    if missing:
        raise ValueError(f"make_table: no unit given for columns {missing}")
    df = pd.DataFrame(dict(columns), copy=False)  # fresh arrays: no copy, no consolidation
    df.attrs["units"] = {c: units[c] for c in columns}
    df.attrs["provenance"] = provenance_dict if provenance_dict is not None else provenance()
    return df


def line_runs(lines):
    """File lines of the rows as runs ``[[first, last], ...]`` of consecutive lines (plain ints).

    The form of ``attrs["lines"]``: plain Python values only (pandas compares
    and deep-copies attrs; an array breaks ``pd.concat`` and a list of one int
    per row costs a deep copy per row on every pandas operation). A file
    without blank lines is one run.
    """
    v = np.asarray(lines, dtype=np.int64).ravel()
    if v.size == 0:
        return []
    cut = np.flatnonzero(np.diff(v) != 1) + 1
    first = np.concatenate(([0], cut))
    last = np.concatenate((cut - 1, [v.size - 1]))
    return [[int(a), int(b)] for a, b in zip(v[first], v[last], strict=True)]


def expand_line_runs(runs):
    """The file line of every row (int64 array) from :func:`line_runs`; None if malformed."""
    try:
        parts = [np.arange(int(a), int(b) + 1, dtype=np.int64) for a, b in runs]
    except (TypeError, ValueError):
        return None
    return np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)


def row_lines(df):
    """File line of every row of a table read from a file (``attrs["lines"]``), or None.

    Returns an int64 array of ``len(df)`` lines, or None when the table has no
    line record or it no longer matches the rows (e.g. after filtering).
    """
    runs = getattr(df, "attrs", {}).get("lines")
    if runs is None:
        return None
    lines = expand_line_runs(runs) if is_line_runs(runs) else np.asarray(runs, dtype=np.int64)
    return lines if lines is not None and lines.size == len(df) else None


def is_line_runs(lines):
    return isinstance(lines, list) and all(isinstance(r, list | tuple) and len(r) == 2
                                           for r in lines)


def column_quantity(df, column):
    """Column ``column`` of a convention table as a pint quantity of :data:`supercoil.ureg`."""
    from supercoil.units import ureg

    unit = df.attrs.get("units", {}).get(column)
    if unit is None:
        raise KeyError(f"column {column!r} has no unit in df.attrs['units']")
    return ureg.Quantity(df[column].to_numpy(dtype=float), unit or "dimensionless")


def write_csv(df, path) -> Path:
    """Write a convention table to ``path``: units in headers, provenance as ``#`` lines.

    Returns the path written.

    Raises
    ------
    TypeError
        ``df`` is not a DataFrame (e.g. a dict: build the table with
        :func:`make_table`), or ``path`` is not a path.
    ValueError
        The table has no unit for a column; ``path`` is a directory, or the
        file cannot be written (names the path and the reason).
    """
    from supercoil._csvfile import check_path

    if not isinstance(df, pd.DataFrame):
        raise TypeError(f"write_csv: df must be a pandas DataFrame with attrs['units'] (build "
                        f"one with supercoil.tables.make_table), got {type(df).__name__}")
    path = check_path(path, "path")
    if path.is_dir():
        raise ValueError(f"write_csv: {path} is a directory; give a file name, e.g. "
                         f"{path / 'table.csv'}")
    units = df.attrs.get("units")
    if units is None:
        raise ValueError("write_csv: the table has no df.attrs['units']")
    missing = [c for c in df.columns if c not in units]
    if missing:
        raise ValueError(f"write_csv: no unit for columns {missing} in df.attrs['units']")
    header = {c: (f"{c} [{units[c]}]" if units[c] else str(c)) for c in df.columns}
    prov = df.attrs.get("provenance", {})
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "w", newline="") as fh:
            for key, value in prov.items():
                fh.write(f"# {key}: {json.dumps(_jsonable(value), sort_keys=True)}\n")
            df.rename(columns=header).to_csv(fh, index=False, float_format="%.12g")
    except OSError as exc:  # a parent that is a file, no permission, disk full
        raise ValueError(f"write_csv: cannot write {path}: {exc.strerror or exc}") from None
    return path


def header_hint(header):
    """A hint for a header line that does not follow the ``name [unit]``, comma convention."""
    hints = []
    if ";" in header or "\t" in header:
        sep = "';'" if ";" in header else "a tab"
        hints.append(f"the header uses {sep} as delimiter; supercoil reads comma-separated "
                     "files with '.' as decimal point")
    if re.search(r"\(\s*[^()\s]+\s*\)", header):
        hints.append("units go in square brackets: 'force [pN]', not 'force (pN)'")
    if not hints:
        return ""
    return " (hint: " + "; ".join(hints) + "; expected e.g. 'force [pN],turns,extension [um]')"


def _bad_record(body, n_fields):
    """(line in ``body``, number of fields) of the first record with more fields than the header.

    pandas would silently turn an extra leading field into the index (when
    every row has one) or fail with a line count that ignores the comment lines.
    """
    import csv

    reader = csv.reader(io.StringIO(body), skipinitialspace=True)
    prev = 0
    for record in reader:
        start, prev = prev + 1, reader.line_num
        if not record or (len(record) <= 1 and not "".join(record).strip()):
            continue  # blank line (pandas skips it)
        if len(record) > n_fields:
            return start, len(record)
    return None, None


def _check_unique_names(path, header_line, header_text):
    """DataError if two header fields share a name (with or without their units).

    pandas renames a repeated header ``force [pN]`` to ``force [pN].1``, so the
    check reads the raw header fields, before pandas sees them.
    """
    import csv

    fields = next(csv.reader([header_text], skipinitialspace=True), [])
    seen = {}
    for i, field in enumerate(fields):
        name = _HEADER.match(field.strip()).group("name")
        if name in seen:
            raise DataError(f"{path}, line {header_line}: column {name!r} appears twice in "
                            f"the header (fields {seen[name] + 1} and {i + 1})")
        seen[name] = i


def read_csv(path, text_columns=("molecule",)) -> pd.DataFrame:
    """Read a table written by :func:`write_csv` (or any CSV with ``name [unit]`` headers).

    Lines starting with ``#`` before the header are provenance, ``# key: json``;
    a comment line that is not of that form is kept under ``"comments"``.
    Headers without ``[unit]`` get the unit ``""``. The file is UTF-8 (a
    byte-order mark is skipped).

    Parameters
    ----------
    path : str or Path
        The CSV file.
    text_columns : sequence of str
        Columns (names without unit) read as text exactly as written, never
        as numbers: labels such as ``molecule`` keep ``"01"`` apart from
        ``"1"`` and ``"1.0"``. Empty cells stay missing (NaN).

    Raises
    ------
    DataError
        No such file; not UTF-8 text (names the line); no header; a row with
        more fields than the header (names the file line, counting the
        comment lines, with a hint when the header does not look like
        ``name [unit]`` with commas); a column named twice.
    """
    df, src = read_csv_source(path, text_columns)
    src.close()
    return df


def read_csv_source(path, text_columns=("molecule",)):
    """:func:`read_csv` and the open :class:`~supercoil._csvfile.CsvFile` (the caller closes it).

    For readers that also need the file line of every row
    (:meth:`~supercoil._csvfile.CsvFile.data_lines`), e.g.
    :func:`supercoil.read_tweezers_csv`.
    """
    src = CsvFile(path)
    try:
        df = _parse(src, text_columns)
    except BaseException:
        src.close()
        raise
    names, units = [], {}
    for col in df.columns:
        m = _HEADER.match(str(col))
        name, unit = m.group("name"), (m.group("unit") or "").strip()
        names.append(name)
        units[name] = unit
    df.columns = names
    df.attrs["units"] = units
    df.attrs["provenance"] = src.provenance
    return df, src


def _parse(src, text_columns):
    """pandas' reading of the table body; DataError naming the file line on a bad record."""
    path, header_text, n_comment = src.path, src.header_text, src.n_comment

    def too_many_fields(n_fields):
        where, got = _bad_record(src.body_text(), n_fields)
        if where is None:
            return None
        return DataError(
            f"{path}, line {n_comment + where}: {got} fields, but the header (line "
            f"{src.header_line}) has {n_fields} (a decimal comma, e.g. 1,68 for 1.68, or an "
            f"unquoted comma in a label splits a value){header_hint(header_text)}")

    n_fields = None
    try:
        head = pd.read_csv(io.StringIO(header_text + "\n"), skipinitialspace=True, nrows=0)
        n_fields = len(head.columns)
        _check_unique_names(path, src.header_line, header_text)
        text_set = set(text_columns or ())
        dtype = {c: str for c in head.columns if _HEADER.match(str(c)).group("name") in text_set}
        df = pd.read_csv(src.body(), skipinitialspace=True, dtype=dtype or None,
                         encoding="utf-8")
    except UnicodeDecodeError:
        src.body_text()  # raises the DataError naming the line
        raise
    except pd.errors.EmptyDataError:
        raise DataError(f"{path}: no header line (the file is empty after its comments)"
                        ) from None
    except pd.errors.ParserError as exc:
        err = too_many_fields(n_fields) if n_fields is not None else None
        if err is not None:
            raise err from None
        # pandas counts lines from the header: shift by the comment lines above it
        msg = re.sub(r"line (\d+)", lambda m: f"line {int(m.group(1)) + n_comment}", str(exc))
        raise DataError(f"{path}: cannot parse the table: {msg}{header_hint(header_text)}"
                        ) from None
    if not isinstance(df.index, pd.RangeIndex):
        # every row had more fields than the header: pandas made the first an index.
        # Only then (or on a parser error) is the file scanned record by record.
        err = too_many_fields(n_fields)
        if err is not None:
            raise err
    return df
