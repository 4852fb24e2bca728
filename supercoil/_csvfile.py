"""Reading a CSV file in bounded memory: comment lines, header, body handle, file lines.

Private helper of :func:`supercoil.tables.read_csv` and
:func:`supercoil.read_tweezers_csv`. The file is never held whole in memory on
the normal path: the ``#`` lines and the header are read line by line, pandas
streams the body from the open file, and the file line of every data row is
found by scanning the bytes in blocks (:meth:`CsvFile.data_lines`). Only the
error paths (a bad record, a quoted field that spans lines, a bare carriage
return, bytes that are not UTF-8) decode the body as one text.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from supercoil.exceptions import DataError

__all__ = ["BLOCK_BYTES", "CsvFile", "check_path", "decode_utf8", "open_input", "read_text"]

#: bytes scanned at a time for the file lines of the rows
BLOCK_BYTES = 1 << 20
_BOM = b"\xef\xbb\xbf"
_WHITE = np.zeros(256, dtype=bool)
_WHITE[[9, 10, 13, 32]] = True


def check_path(path, name="path"):
    """``path`` as a :class:`~pathlib.Path`; TypeError naming ``name`` if it is not a path.

    The one path check of every reader (CSV, CALISTO, MagScope, MultiMT).
    """
    if isinstance(path, bytes) or not (isinstance(path, str | Path)
                                        or hasattr(path, "__fspath__")):
        raise TypeError(f"{name} must be a str or a path, got {type(path).__name__}")
    return Path(path)


def open_input(path, kind="file", name="path"):
    """``(Path, binary handle)`` of an input file; DataError naming the file otherwise.

    DataError for a missing file, a directory, a file that cannot be read
    (permissions, ...); TypeError (naming ``name``) for a non-path.
    """
    path = check_path(path, name)
    if path.is_dir():
        raise DataError(f"cannot read {path}: it is a directory, not a {kind}; give the "
                        "file's path")
    try:
        return path, open(path, "rb")  # the caller closes it
    except FileNotFoundError:
        raise DataError(f"no such {kind}: {path}") from None
    except OSError as exc:  # permissions, a device, ...
        raise DataError(f"cannot read the {kind} {path}: {exc.strerror or exc}") from None


def decode_utf8(raw, path, first_line=1, offset=0):
    """``raw`` bytes as UTF-8 text; DataError naming the file line of a bad byte.

    ``first_line``: file line of ``raw[0]``; ``offset``: its byte offset in the file.
    """
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = first_line + raw[: exc.start].count(b"\n")
        raise DataError(
            f"{path}, line {line}: not UTF-8 text ({exc.reason} at byte "
            f"{offset + exc.start}); save the file as UTF-8") from None


def read_text(path, kind="file", name="path"):
    """``(Path, text)`` of a whole UTF-8 text file (a byte-order mark is skipped).

    The shared checks of :func:`open_input` and :func:`decode_utf8`.
    """
    path, fh = open_input(path, kind, name)
    with fh:
        raw = fh.read()
    start = 3 if raw.startswith(_BOM) else 0
    return path, decode_utf8(raw[start:], path, offset=start)


def _mac_line_ends(fh):
    """``fh``, or an in-memory copy with LF line ends if the file ends lines with CR only.

    Classic Mac OS (and Excel's "CSV (Macintosh)") ends lines with a bare
    carriage return; pandas and :mod:`csv` would read such a file as one line.
    A file with a carriage return and no line feed in its whole text is read
    into memory once with every CR turned into LF (same lines, same line numbers).
    """
    import io

    head = fh.read(BLOCK_BYTES)
    if b"\r" not in head or b"\n" in head:
        fh.seek(0)
        return fh
    raw = head + fh.read()
    if b"\n" in raw:
        fh.seek(0)
        return fh
    fh.close()
    return io.BytesIO(raw.replace(b"\r", b"\n"))


class CsvFile:
    """The parts of a CSV file before its data: provenance, header, byte offset of the body.

    Attributes
    ----------
    path : Path
    provenance : dict
        The ``# key: json`` lines (others under ``"comments"``).
    n_comment : int
        Number of ``#`` lines above the body.
    offset : int
        Byte offset of the body (the first line after the ``#`` lines).
    header_line : int
        File line (1-based) of the header.
    header_text : str
        The header line, stripped.
    """

    def __init__(self, path):
        self.path, fh = open_input(path, "file")  # closed below on error, else by close()
        try:
            fh = _mac_line_ends(fh)
            self.handle = fh
            self._read_head(fh)
        except BaseException:
            fh.close()
            raise

    def _decode(self, raw, line_no, start):
        return decode_utf8(raw, self.path, line_no, start)

    def _read_head(self, fh):
        prov, comments, n = {}, [], 0
        pos = 3 if fh.read(3) == _BOM else 0
        fh.seek(pos)
        while True:
            line = fh.readline()
            if not line.startswith(b"#"):
                break
            text = self._decode(line, n + 1, pos)
            pos += len(line)
            n += 1
            body = text[1:].strip()
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
        self.provenance, self.n_comment, self.offset = prov, n, pos
        blank = 0
        while line and not line.strip():
            blank += 1
            line = fh.readline()
        if not line:
            raise DataError(f"{self.path}: no header line (the file is empty after its "
                            "comments)")
        self.header_line = n + blank + 1
        self.header_text = self._decode(line, self.header_line, pos).strip()

    def body(self):
        """A binary handle positioned at the body (for pandas, which streams it)."""
        self.handle.seek(self.offset)
        return self.handle

    def body_text(self):
        """The whole body as text (error paths only); DataError naming a non-UTF-8 line."""
        self.handle.seek(self.offset)
        return decode_utf8(self.handle.read(), self.path, self.n_comment + 1, self.offset)

    def close(self):
        self.handle.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def data_lines(self, n_rows):
        """File line (1-based) of every data row as pandas reads the body, or None if unsure.

        pandas skips blank (or whitespace-only) lines; the ``#`` lines above the
        header count. Without quotes one record is one line: the lines are found
        in blocks of :data:`BLOCK_BYTES` with numpy (temporaries bounded by the
        block). A quote or a bare carriage return sends the body to the
        record-by-record reading of :mod:`csv`.
        """
        if self._one_line_per_row(n_rows):  # the common case: no blank line, no quote
            return np.arange(self.header_line + 1, self.header_line + 1 + n_rows)
        filled = self._filled_lines()
        if filled is None:
            return self._data_lines_csv(n_rows)
        if filled.size - 1 != n_rows:
            return None
        return filled[1:] + (self.n_comment + 1)

    def _one_line_per_row(self, n_rows):
        """True if every line after the header is one data row (counted at C speed)."""
        fh = self.body()
        n_lines, last = 0, b""
        while chunk := fh.read(BLOCK_BYTES):
            if b'"' in chunk or b"\r" in chunk:
                return False
            n_lines += chunk.count(b"\n")
            last = chunk
        if last and not last.endswith(b"\n"):
            n_lines += 1  # a last line without its newline
        # pandas made n_rows rows of the lines after the header; with one line per
        # record and as many lines as rows, none of them was skipped as blank
        return n_lines == (self.header_line - self.n_comment) + n_rows

    def _filled_lines(self):
        """0-based indices (from the body start) of non-blank lines; None: use :mod:`csv`."""
        fh = self.body()
        carry, first, parts = b"", 0, []
        while True:
            chunk = fh.read(BLOCK_BYTES)
            data = carry + chunk
            if not chunk:  # the end: a last line without its newline
                if data.strip():
                    if b'"' in data or b"\r" in data.rstrip(b"\r"):
                        return None
                    parts.append(np.array([first]))
                break
            cut = data.rfind(b"\n")
            if cut < 0:
                carry = data
                continue
            block, carry = data[: cut + 1], data[cut + 1:]
            b = np.frombuffer(block, dtype=np.uint8)
            newline = np.flatnonzero(b == 10)
            n_cr = np.count_nonzero(b == 13)
            if (n_cr and n_cr != np.count_nonzero(b[newline[newline > 0] - 1] == 13)) \
                    or np.any(b == 34):  # a bare carriage return, or a quote
                return None
            starts = np.concatenate(([0], newline[:-1] + 1))
            # non-whitespace bytes per line (int32: a block is < 2^31 bytes)
            solid = np.concatenate(([0], np.cumsum(~_WHITE[b], dtype=np.int32)))
            parts.append(np.flatnonzero(solid[newline + 1] - solid[starts] > 0) + first)
            first += newline.size
            del b, newline, starts, solid
        return np.concatenate(parts) if parts else np.zeros(0, dtype=np.int64)

    def _data_lines_csv(self, n_rows):
        import csv
        import io

        reader = csv.reader(io.StringIO(self.body_text()), skipinitialspace=True)
        rows, prev, header = [], 0, False
        for record in reader:
            start = prev + 1
            prev = reader.line_num
            if not record or (all(not c.strip() for c in record) and len(record) <= 1):
                continue
            if not header:
                header = True
                continue
            rows.append(self.n_comment + start)
        if len(rows) != n_rows:
            return None
        return np.asarray(rows, dtype=np.int64)
