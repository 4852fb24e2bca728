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

from supercoil.exceptions import DataError

__all__ = ["column_quantity", "make_table", "provenance", "read_csv", "write_csv"]

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
    """
    units = df.attrs.get("units")
    if units is None:
        raise ValueError("write_csv: the table has no df.attrs['units']")
    missing = [c for c in df.columns if c not in units]
    if missing:
        raise ValueError(f"write_csv: no unit for columns {missing} in df.attrs['units']")
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    header = {c: (f"{c} [{units[c]}]" if units[c] else str(c)) for c in df.columns}
    prov = df.attrs.get("provenance", {})
    with open(path, "w", newline="") as fh:
        for key, value in prov.items():
            fh.write(f"# {key}: {json.dumps(_jsonable(value), sort_keys=True)}\n")
        df.rename(columns=header).to_csv(fh, index=False, float_format="%.12g")
    return path


def _header_hint(header):
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
    path = Path(path)
    try:
        raw = path.read_bytes()
    except FileNotFoundError:
        raise DataError(f"no such file: {path}") from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise DataError(
            f"{path}, line {line}: not UTF-8 text ({exc.reason} at byte {exc.start}); "
            "save the file as UTF-8 CSV"
        ) from None
    lines = text.splitlines(keepends=True)
    prov, comments, n_comment = {}, [], 0
    for line in lines:
        if not line.startswith("#"):
            break
        n_comment += 1
        body = line[1:].strip()
        key, sep, value = body.partition(":")
        if sep and key.strip() and " " not in key.strip():
            try:
                prov[key.strip()] = json.loads(value.strip())
                continue
            except json.JSONDecodeError:
                pass
        comments.append(body)
    if comments:
        prov["comments"] = comments
    body = "".join(lines[n_comment:])
    if not body.strip():
        raise DataError(f"{path}: no header line (the file is empty after its comments)")
    header_text = next((ln for ln in lines[n_comment:] if ln.strip()), "").strip()
    header_line = n_comment + 1 + next(
        (i for i, ln in enumerate(lines[n_comment:]) if ln.strip()), 0)
    try:
        head = pd.read_csv(io.StringIO(body), skipinitialspace=True, nrows=0)
        n_fields = len(head.columns)
        where, got = _bad_record(body, n_fields)
        if where is not None:
            raise DataError(
                f"{path}, line {n_comment + where}: {got} fields, but the header (line "
                f"{header_line}) has {n_fields} (a decimal comma, e.g. 1,68 for 1.68, or an "
                f"unquoted comma in a label splits a value){_header_hint(header_text)}"
            )
        text_set = set(text_columns or ())
        dtype = {c: str for c in head.columns if _HEADER.match(str(c)).group("name") in text_set}
        df = pd.read_csv(io.StringIO(body), skipinitialspace=True, dtype=dtype or None)
    except pd.errors.EmptyDataError:
        raise DataError(f"{path}: no header line (the file is empty after its comments)"
                        ) from None
    except pd.errors.ParserError as exc:
        # pandas counts lines from the header: shift by the comment lines above it
        msg = re.sub(r"line (\d+)", lambda m: f"line {int(m.group(1)) + n_comment}", str(exc))
        raise DataError(f"{path}: cannot parse the table: {msg}{_header_hint(header_text)}"
                        ) from None
    names, units = [], {}
    for col in df.columns:
        m = _HEADER.match(str(col))
        name, unit = m.group("name"), (m.group("unit") or "").strip()
        if name in units:
            raise DataError(f"{path}: column {name!r} appears twice in the header")
        names.append(name)
        units[name] = unit
    df.columns = names
    df.attrs["units"] = units
    df.attrs["provenance"] = prov
    return df
