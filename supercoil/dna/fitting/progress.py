"""Progress of many fits: a tqdm bar on a terminal, one line per event in a log.

Used by :func:`~supercoil.fit_many` and ``supercoil fit``. A bar's carriage
returns pile up into one unreadable line in a log file, so off a terminal
each finished molecule is one line (``molecule m3 done (3/20)``).
"""

from __future__ import annotations

import sys

__all__ = ["Progress", "is_terminal"]


def is_terminal(stream) -> bool:
    """True when ``stream`` is an interactive terminal (False for files, pipes, captures)."""
    isatty = getattr(stream, "isatty", None)
    try:
        return bool(isatty()) if isatty is not None else False
    except (ValueError, OSError):  # a closed stream
        return False


class Progress:
    """Progress reporting of ``total`` molecules.

    Parameters
    ----------
    progress : None, bool or callable
        None: a tqdm bar if ``stream`` is a terminal, else one line per
        molecule; True: the bar (ImportError without tqdm); False: silent; a
        callable: ``progress(done, total, molecule)`` after each molecule.
    total : int
        Number of molecules.
    stream : file, optional
        Where bar and lines go (default ``sys.stderr``, looked up at creation).
    prefix : str
        Put before each line (e.g. ``"supercoil fit: "``).
    """

    def __init__(self, progress, total, stream=None, prefix=""):
        self.total, self.done, self.prefix = int(total), 0, prefix
        self.stream = sys.stderr if stream is None else stream
        self.callback = self.bar = None
        self.lines = False
        if progress is False:
            return
        if progress is not None and progress is not True:
            if not callable(progress):
                raise TypeError("progress must be None, True, False or a callable "
                                f"progress(done, total, molecule), got {progress!r}")
            self.callback = progress
            return
        if progress is True or is_terminal(self.stream):
            try:
                from tqdm import tqdm
            except ImportError as exc:
                if progress is True:
                    raise ImportError("progress=True needs tqdm (pip install "
                                      "'supercoil[distributed]')") from exc
                self.lines = True  # a terminal without tqdm: plain lines
                return
            self.bar = tqdm(total=self.total, file=self.stream, unit="molecule",
                            desc=prefix.rstrip(": ") or "fit_many", leave=True)
            return
        self.lines = True

    def update(self, molecule):
        """One more molecule finished."""
        self.done += 1
        if self.callback is not None:
            self.callback(self.done, self.total, molecule)
        elif self.bar is not None:
            self.bar.set_postfix_str(f"last {molecule}", refresh=False)
            self.bar.update(1)
        elif self.lines:
            print(f"{self.prefix}molecule {molecule} done ({self.done}/{self.total})",
                  file=self.stream, flush=True)

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None
