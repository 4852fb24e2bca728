"""Reader of MultiMT ``.mtdat`` recordings (Dunlap lab, Emory; github.com/ddunlap91/MagTweezer).

What was verified, and where (repository ``ddunlap91/MagTweezer``, commit c9e026e, read
2026-12-01; re-implemented from the layout, no code taken):
``multiMTgui_PylonMEX/Functions/mtdat_fileio/mtdatwriteheader.m`` (the header writer),
``mtdat_writerecord.m`` (the record writer), ``mtdatread.m`` (MultiMT's own reader),
``fio_size.m`` (bytes per type), ``YAML.m`` (SnakeYAML 1.9 ``Yaml().dump`` of the MATLAB
structure); the record layouts of the experiments in
``multiMTgui_PylonMEX/MultiMTgui_Functions/ChapeauCurve/MultiMTgui_startChapeauCurve.m``
and ``MultiMTgui_CC_ProcessFrame.m``; the units from
``multiMTgui_PylonMEX/MultiMT_Plotting/LoadExperimentData.m`` (``Date`` is a MATLAB
datenum: ``(Date - Date(1)) * 86400`` s), ``PlotForceExtension.m`` (``X``, ``Y`` in
pixels times ``PxScale`` in um), ``PlotChapeauCurve.m`` and ``FindChapeauPeak.m`` (heights
in um; drift is the mean ``Z_ABS`` of the tracks whose ``TrackingInfo.Type`` is
``Reference``).

Layout: a line ``#!!#YAML_START``, the YAML text of the configuration (with a ``Record``
list: ``parameter``, ``format`` (an ``fwrite`` precision such as ``double``, ``uint32``,
``int8``), ``size`` (MATLAB size, e.g. ``[3.0, 1.0]``), ``machinefmt`` (``ieee-le``...)
and ``encoding``), a line ``#!!#YAML_END``, then binary records back to back: each
record holds every ``Record`` entry in order, ``prod(size)`` values of its format in
column-major order, without padding. A last incomplete record (a run stopped while
writing) is dropped, as ``mtdatread`` does, with a DataWarning.

The YAML is the subset SnakeYAML writes for MATLAB structures (block mappings and
sequences, flow ``[...]``/``{...}`` collections that may wrap over lines, plain, single-
and double-quoted scalars, numbers, ``.NaN``/``.inf``); it is parsed here
(:func:`parse_yaml_subset`), PyYAML is not needed.
"""

from __future__ import annotations

import re
import warnings

import numpy as np

from .._csvfile import check_path, open_input
from ..exceptions import DataError, DataWarning
from ..units import ureg
from .trace import build_trace

__all__ = ["parse_yaml_subset", "read_mtdat", "read_mtdat_records"]

_START = re.compile(rb"^#!!#YAML_START[ \t]*\r?$", re.I | re.M)
_END = re.compile(rb"^#!!#YAML_END", re.I | re.M)

#: MATLAB fread/fwrite precisions -> numpy type codes (fio_size.m)
_TYPES = {
    "double": "f8", "float64": "f8", "real*8": "f8", "single": "f4", "float32": "f4",
    "float": "f4", "real*4": "f4", "int8": "i1", "schar": "i1", "signed char": "i1",
    "integer*1": "i1", "uint8": "u1", "uchar": "u1", "unsigned char": "u1", "char*1": "u1",
    "char": "u1", "int16": "i2", "short": "i2", "integer*2": "i2", "uint16": "u2",
    "ushort": "u2", "int32": "i4", "int": "i4", "long": "i4", "integer*4": "i4",
    "uint32": "u4", "uint": "u4", "ulong": "u4", "int64": "i8", "integer*8": "i8",
    "uint64": "u8",
}


# ---- the YAML subset ---------------------------------------------------------------------

def _scalar(text):
    t = text.strip()
    if not t:
        return None
    if t[0] == "'":
        return t[1:-1].replace("''", "'")
    if t[0] == '"':
        body = t[1:-1]
        return re.sub(r'\\(["\\/nt0abefrv ]|x[0-9a-fA-F]{2}|u[0-9a-fA-F]{4})', _unescape, body)
    low = t.lower()
    if low in ("null", "~"):
        return None
    if low in ("true", "false"):
        return low == "true"
    if low in (".nan",):
        return float("nan")
    if low in (".inf", "+.inf", "-.inf"):
        return float("-inf") if low[0] == "-" else float("inf")
    if re.fullmatch(r"[-+]?[0-9]+", t):
        return int(t)
    if re.fullmatch(r"[-+]?(\.[0-9]+|[0-9]+(\.[0-9]*)?)([eE][-+]?[0-9]+)?", t):
        return float(t)
    return t


def _unescape(m):
    c = m.group(1)
    simple = {"n": "\n", "t": "\t", "0": "\0", "a": "\a", "b": "\b", "e": "\x1b", "f": "\f",
              "r": "\r", "v": "\v", " ": " ", '"': '"', "\\": "\\", "/": "/"}
    return simple[c] if c in simple else chr(int(c[1:], 16))


def _flow(text, i, where):
    """A flow value starting at ``text[i]``: (value, index after it)."""
    while i < len(text) and text[i] in " \t\n":
        i += 1
    if i >= len(text):
        raise DataError(f"{where}: unexpected end of a flow collection")
    if text[i] in "[{":
        close = "]" if text[i] == "[" else "}"
        items, pairs = [], {}
        i += 1
        while True:
            while i < len(text) and text[i] in " \t\n,":
                i += 1
            if i >= len(text):
                raise DataError(f"{where}: unclosed {text[i - 1]!r} in a flow collection")
            if text[i] == close:
                return (items if close == "]" else pairs), i + 1
            if close == "}":
                key, i = _flow_scalar(text, i, ":", where)
                value, i = _flow(text, i + 1, where)
                pairs[str(key)] = value
            else:
                value, i = _flow(text, i, where)
                items.append(value)
    return _flow_scalar(text, i, ",]}", where)


def _flow_scalar(text, i, stops, where):
    """A scalar in a flow collection from ``text[i]``; a plain one ends at a stop
    character (``:`` only when followed by a space, a line end or the end)."""
    if text[i] in "'\"":
        q, j = text[i], i + 1
        while j < len(text):
            if q == "'" and text.startswith("''", j):
                j += 2
            elif q == '"' and text[j] == "\\":
                j += 2
            elif text[j] == q:
                break
            else:
                j += 1
        if j >= len(text):
            raise DataError(f"{where}: unclosed quote in a flow collection")
        return _scalar(" ".join(text[i:j + 1].split("\n"))), j + 1
    j = i
    while j < len(text):
        c = text[j]
        if c in stops and (c != ":" or text[j + 1:j + 2] in (" ", "\n", "")):
            break
        j += 1
    return _scalar(" ".join(text[i:j].split())), j


def _balanced(text):
    depth, q = 0, None
    for c in text:
        if q:
            q = None if c == q else q
        elif c in "'\"":
            q = c
        elif c in "[{":
            depth += 1
        elif c in "]}":
            depth -= 1
    return depth <= 0 and q is None


def parse_yaml_subset(text, where="YAML header"):
    """Parse the YAML that SnakeYAML's default ``dump`` writes (see the module docstring).

    Returns nested dicts, lists, str, int, float, bool and None. DataError
    naming the line for anything outside the subset (anchors, tags, ...).
    """
    lines = [(n, ln.rstrip()) for n, ln in enumerate(text.replace("\r\n", "\n").split("\n"), 1)
             if ln.strip() and not ln.lstrip().startswith("#") and ln.strip() != "---"]
    if not lines:
        return {}
    value, k = _block(lines, 0, _indent(lines[0][1]), where)
    if k < len(lines):
        raise DataError(f"{where}, line {lines[k][0]}: unexpected indentation")
    return value


def _indent(line):
    return len(line) - len(line.lstrip(" "))


def _value(lines, k, rest, indent, where):
    """The value written after ``key:`` or ``-`` on line k (``rest``): (value, next line)."""
    n = lines[k][0]
    if rest.startswith(("&", "*", "!", "|", ">")):
        raise DataError(f"{where}, line {n}: YAML feature {rest[:1]!r} is not supported "
                        "(the MultiMT header writer does not use it)")
    if rest[:1] in "[{":
        text, k = rest, k + 1
        while not _balanced(text) and k < len(lines):
            text += "\n" + lines[k][1].strip()
            k += 1
        value, end = _flow(text, 0, f"{where}, line {n}")
        if text[end:].strip():
            raise DataError(f"{where}, line {n}: text after a flow collection")
        return value, k
    k += 1
    while k < len(lines) and _indent(lines[k][1]) > indent:  # a folded plain scalar
        rest += " " + lines[k][1].strip()
        k += 1
    return _scalar(rest), k


def _block(lines, k, indent, where):
    """A block mapping or sequence whose lines start at ``indent``: (value, next line)."""
    first = lines[k][1].strip()
    if first == "-" or first.startswith("- "):
        out = []
        while k < len(lines) and _indent(lines[k][1]) == indent and (
                lines[k][1].strip() == "-" or lines[k][1].strip().startswith("- ")):
            rest = lines[k][1].strip()[2:].strip()
            if not rest:
                k += 1
                if k < len(lines) and _indent(lines[k][1]) > indent:
                    value, k = _block(lines, k, _indent(lines[k][1]), where)
                else:
                    value = None
            elif re.match(r"^[^'\"\[{][^:]*:( |$)", rest):  # "- key: value": a mapping
                sub = [(lines[k][0], " " * (indent + 2) + rest)]
                value, used = _block(sub + lines[k + 1:], 0, indent + 2, where)
                k += used
            else:
                value, k = _value(lines, k, rest, indent, where)
            out.append(value)
        return out, k
    out = {}
    while k < len(lines) and _indent(lines[k][1]) == indent:
        n, line = lines[k]
        m = re.match(r"^\s*('(?:[^']|'')*'|\"[^\"]*\"|[^:]+?)\s*:(?:\s+(.*))?$", line)
        if not m:
            raise DataError(f"{where}, line {n}: expected 'key: value', got {line.strip()!r}")
        key, rest = str(_scalar(m.group(1))), (m.group(2) or "").strip()
        if rest:
            out[key], k = _value(lines, k, rest, indent, where)
            continue
        k += 1
        if k < len(lines) and (_indent(lines[k][1]) > indent or (
                _indent(lines[k][1]) == indent and lines[k][1].strip().startswith("-"))):
            out[key], k = _block(lines, k, _indent(lines[k][1]), where)
        else:
            out[key] = None
    return out, k


# ---- the file ---------------------------------------------------------------------------

def _split(raw, path):
    """(YAML text, byte offset of the records, file lines above the YAML) of a file's bytes."""
    start = _START.search(raw)
    if start is None:
        raise DataError(f"{path}: no line '#!!#YAML_START'; not a MultiMT .mtdat file")
    end = _END.search(raw, start.end())
    if end is None:
        raise DataError(f"{path}: no line '#!!#YAML_END' after '#!!#YAML_START' (the header "
                        "is not closed: the file holds no records)")
    nl = raw.find(b"\n", end.end())
    body = len(raw) if nl < 0 else nl + 1
    first = raw.find(b"\n", start.end()) + 1  # the YAML starts on the next line
    text = raw[first:end.start()]
    try:
        yaml = text.decode("utf-8")
    except UnicodeDecodeError:
        yaml = text.decode("latin-1")  # MATLAB's default encoding (windows-1252) on Windows
    return yaml, body, raw[:first].count(b"\n")


def _record_dtype(record, path):
    if isinstance(record, dict):
        record = [record]  # a struct array of one element is written as one mapping
    if not isinstance(record, list) or not record:
        raise DataError(f"{path}: the header has no 'Record' list (parameter, format, size "
                        "of every field of a binary record)")
    fields = []
    for j, rec in enumerate(record):
        if not isinstance(rec, dict) or not {"parameter", "format", "size"} <= set(rec):
            raise DataError(f"{path}: Record entry {j + 1} lacks parameter, format or size: "
                            f"{rec!r}")
        fmt = str(rec["format"]).strip().lower()
        code = _TYPES.get(fmt)
        if code is None:
            raise DataError(f"{path}: Record {rec['parameter']!r}: format {rec['format']!r} is "
                            f"not supported (known: {', '.join(sorted(_TYPES))})")
        order = str(rec.get("machinefmt") or "ieee-le").strip().lower()
        endian = ">" if order in ("b", "ieee-be", "ieee-be.l64", "s") else "<"
        size = rec["size"] if isinstance(rec["size"], list) else [rec["size"]]
        try:
            shape = tuple(round(float(s)) for s in size)
        except (TypeError, ValueError):
            raise DataError(f"{path}: Record {rec['parameter']!r}: size {rec['size']!r} is "
                            "not a list of numbers") from None
        count = int(np.prod(shape)) if shape else 1
        fields.append((str(rec["parameter"]), np.dtype(endian + code), count, shape))
    names = [f[0] for f in fields]
    if len(set(names)) != len(names):
        raise DataError(f"{path}: Record names a parameter twice: {names}")
    dtype = np.dtype([(nm, dt, (c,)) if c != 1 else (nm, dt) for nm, dt, c, _ in fields])
    return dtype, {nm: shape for nm, _, _, shape in fields}


def read_mtdat_records(path):
    """The header and the records of a MultiMT ``.mtdat`` file.

    Returns
    -------
    header : dict
        The YAML configuration (``Record`` included).
    records : dict of str -> ndarray
        Every ``Record`` parameter: shape ``(n_records,)`` for one value per
        record, else ``(n_records, *size)`` (MATLAB's column-major order
        restored; a ``[n, 1]`` size gives ``(n_records, n, 1)``).

    Raises
    ------
    DataError
        Not a file, not an ``.mtdat`` file (no ``#!!#YAML_START``), no
        ``#!!#YAML_END``, a header outside the YAML subset (names the line), no
        or a malformed ``Record``, an unknown format.

    Warns
    -----
    DataWarning
        Trailing bytes that do not make a whole record (dropped).
    """
    path, fh = open_input(path, "MultiMT .mtdat file")
    with fh:
        raw = fh.read()
    yaml, body, first = _split(raw, path)
    try:
        header = parse_yaml_subset(yaml, f"{path}, YAML header")
    except DataError as exc:  # header line numbers -> file lines
        msg = re.sub(r"line (\d+)", lambda m: f"line {int(m.group(1)) + first}", str(exc))
        raise DataError(msg) from None
    if not isinstance(header, dict):
        raise DataError(f"{path}: the YAML header is not a mapping")
    dtype, shapes = _record_dtype(header.get("Record"), path)
    n_rec, extra = divmod(len(raw) - body, dtype.itemsize)
    if extra:
        warnings.warn(f"{path}: {extra} trailing byte(s) after {n_rec} record(s) of "
                      f"{dtype.itemsize} bytes do not make a whole record (the run stopped "
                      "while writing?); dropped", DataWarning, stacklevel=2)
    arr = np.frombuffer(raw, dtype=dtype, count=n_rec, offset=body)
    records = {}
    for name, shape in shapes.items():
        col = np.asarray(arr[name]).astype(arr.dtype[name].base.newbyteorder("="))
        if int(np.prod(shape)) != 1:
            col = col.reshape((n_rec, *shape[::-1])).transpose(0, *range(len(shape), 0, -1))
        records[name] = col
    return header, records


def _factors(z_unit, magnet_unit):
    try:
        return (float(ureg.Quantity(1.0, z_unit).m_as("nm")),
                float(ureg.Quantity(1.0, magnet_unit).m_as("mm")))
    except Exception as exc:  # pint parse or dimensionality error
        raise ValueError(f"z_unit={z_unit!r} / magnet_unit={magnet_unit!r}: not lengths ({exc})"
                         ) from None


def _pixel_nm(pixel_size, header):
    """nm per camera pixel: the argument, else the header's PxScale (um per pixel), else NaN."""
    from ..units import U, magnitude

    if pixel_size is not None:
        return float(magnitude(pixel_size, U.nm, "pixel_size"))
    scale = header.get("PxScale")
    if isinstance(scale, int | float) and not isinstance(scale, bool):
        return float(scale) * 1e3
    return float("nan")


def _references(header, beads, reference_beads, path):
    """The reference tracks: given, or TrackingInfo entries of Type 'Reference'."""
    if reference_beads is None:
        info = header.get("TrackingInfo")
        info = [info] if isinstance(info, dict) else (info if isinstance(info, list) else [])
        refs = [str(i + 1) for i, ti in enumerate(info) if isinstance(ti, dict)
                and str(ti.get("Type", "")).lower() == "reference"]
    else:
        refs = [str(r) for r in reference_beads]
    missing = [r for r in refs if r not in beads]
    if missing:
        raise DataError(f"{path}: reference bead(s) {missing} not in the recording "
                        f"(tracks: {beads})")
    return refs


def _per_track(records, name, n_tracks, path):
    if name not in records:
        raise DataError(f"{path}: no record parameter {name!r} (parameters: "
                        f"{sorted(records)})")
    v = records[name].reshape(records[name].shape[0], -1).astype(float)
    if v.shape[1] != n_tracks:
        raise DataError(f"{path}: record parameter {name!r} has {v.shape[1]} values per record, "
                        f"expected one per track ({n_tracks})")
    return v


def read_mtdat(path, *, z="Z_ABS", pixel_size=None, z_unit="um", magnet_unit="mm",
               reference_beads=None):
    """Read a MultiMT ``.mtdat`` recording into the trace table of :mod:`supercoil.traces.trace`.

    Parameters
    ----------
    path : str or Path
        The ``.mtdat`` file (e.g. a ``<date>_ChapeauCurve_001.mtdat``).
    z : {"Z_ABS", "Z_REL", "dZ"}
        The record parameter taken as the bead height: ``Z_ABS`` (default; the
        absolute height, drift removed with the reference tracks as MultiMT's
        ``FindChapeauPeak.m`` does), ``Z_REL`` or ``dZ`` (already against each
        track's ``ZRef``; then pass ``reference_beads=[]``).
    pixel_size : Quantity [length], optional
        Size of a camera pixel in the sample (``X``, ``Y`` are in pixels).
        Default: the header's ``PxScale`` in um (MultiMT's own convention);
        without both, x and y are NaN.
    z_unit, magnet_unit : str
        Units of the heights (MultiMT: um) and of ``MagnetHeight`` (mm).
    reference_beads : sequence of str, optional
        Default: the tracks whose ``TrackingInfo`` ``Type`` is ``Reference``.
        Tracks are labelled ``"1"``, ``"2"``, ... as MultiMT numbers them.

    Returns
    -------
    pandas.DataFrame
        The trace table (time [s] from ``Date``, a MATLAB datenum; bead; x, y,
        z [nm]; turns from ``MagnetRotation``; height [mm] from ``MagnetHeight``).

    Raises
    ------
    DataError
        As :func:`read_mtdat_records`; a missing record parameter (``Date``,
        ``MagnetRotation``, ``MagnetHeight``, ``X``, ``Y``, ``z``) or one with
        a number of values other than the number of tracks; times not
        increasing.
    """
    from .trace import check_increasing

    path = check_path(path, "path")
    if z not in ("Z_ABS", "Z_REL", "dZ"):
        raise ValueError(f"z must be 'Z_ABS', 'Z_REL' or 'dZ', got {z!r}")
    f_z, f_mag = _factors(z_unit, magnet_unit)
    header, rec = read_mtdat_records(path)
    if not rec or next(iter(rec.values())).shape[0] == 0:
        raise DataError(f"{path}: the file holds no records")
    for name in ("Date", "MagnetRotation", "MagnetHeight", z):
        if name not in rec:
            raise DataError(f"{path}: no record parameter {name!r}; a rotation recording "
                            f"has Date, MagnetRotation, MagnetHeight, {z} (found {sorted(rec)})")
    n_tracks = int(np.prod(rec[z].shape[1:])) if rec[z].ndim > 1 else 1
    t = (rec["Date"].astype(float) - float(rec["Date"][0])) * 86400.0
    check_increasing(t, f"{path}, record parameter 'Date'", "frame time")
    px_nm = _pixel_nm(pixel_size, header)
    xyz = np.empty((t.size, n_tracks, 3))
    xyz[:, :, 0] = _per_track(rec, "X", n_tracks, path) * px_nm
    xyz[:, :, 1] = _per_track(rec, "Y", n_tracks, path) * px_nm
    xyz[:, :, 2] = _per_track(rec, z, n_tracks, path) * f_z
    beads = [str(i + 1) for i in range(n_tracks)]
    refs = _references(header, beads, reference_beads, path)
    return build_trace(t, beads, xyz, rec["MagnetRotation"].astype(float),
                       rec["MagnetHeight"].astype(float) * f_mag, source=path,
                       fmt="multimt-mtdat", reference_beads=refs,
                       extra={"file_type": str(header.get("FileType", "")), "z": z})
