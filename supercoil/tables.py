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

from .exceptions import DataError

__all__ = ["column_quantity", "make_table", "provenance", "read_csv", "write_csv"]

_HEADER = re.compile(r"^\s*(?P<name>.*?)\s*(?:\[(?P<unit>[^\]]*)\])?\s*$")


def provenance(parameters=None, **extra):
    """Provenance dict: package version, the parameters, and any ``extra`` entries.

    ``parameters`` may be a material (anything with ``as_dict()``), a dict, or
    None. Values in ``extra`` must be JSON-serialisable (quantities are
    written as strings).
    """
    from . import __version__

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
    df = pd.DataFrame(dict(columns))
    df.attrs["units"] = {c: units[c] for c in columns}
    df.attrs["provenance"] = provenance_dict if provenance_dict is not None else provenance()
    return df


def column_quantity(df, column):
    """Column ``column`` of a convention table as a pint quantity of :data:`supercoil.ureg`."""
    from .units import ureg

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


def read_csv(path) -> pd.DataFrame:
    """Read a table written by :func:`write_csv` (or any CSV with ``name [unit]`` headers).

    Lines starting with ``#`` before the header are provenance, ``# key: json``;
    a comment line that is not of that form is kept under ``"comments"``.
    Headers without ``[unit]`` get the unit ``""``.
    """
    path = Path(path)
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise DataError(f"no such file: {path}") from None
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
    df = pd.read_csv(io.StringIO(body), skipinitialspace=True)
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
