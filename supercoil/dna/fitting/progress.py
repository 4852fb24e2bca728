"""Progress of many fits: a tqdm bar on a terminal or in a notebook, silent elsewhere.

Used by :func:`~supercoil.fit_many` and ``supercoil fit``. The bar is
:mod:`tqdm.auto`'s (a widget in a Jupyter notebook, text on a terminal). Off
a terminal (a log file, a pipe, a captured stream) nothing is written unless
asked: ``progress="log"`` writes one line per finished molecule there
(``molecule m3 done (3/20)``; a bar's carriage returns would pile up into one
unreadable line), which is what ``supercoil fit`` asks for.
"""

from __future__ import annotations

import sys

__all__ = ["Progress", "in_notebook", "is_terminal"]


def is_terminal(stream) -> bool:
    """True when ``stream`` is an interactive terminal (False for files, pipes, captures)."""
    isatty = getattr(stream, "isatty", None)
    try:
        return bool(isatty()) if isatty is not None else False
    except (ValueError, OSError):  # a closed stream
        return False


def in_notebook(stream) -> bool:
    """True when ``stream`` is the standard output or error of a Jupyter (IPython) kernel."""
    if "ipykernel" not in sys.modules or stream not in (sys.stderr, sys.stdout):
        return False
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - ipykernel needs IPython
        return False
    shell = get_ipython()
    return shell is not None and type(shell).__name__ == "ZMQInteractiveShell"


class Progress:
    """Progress reporting of ``total`` molecules.

    Parameters
    ----------
    progress : None, bool, "log" or callable
        None: a :mod:`tqdm.auto` bar if ``stream`` is a terminal or a
        notebook's output, else silent; ``"log"``: the same bar, and one line
        per molecule off a terminal; True: the bar (ImportError without
        tqdm); False: silent; a callable: ``progress(done, total, molecule)``
        after each molecule.
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
        log = isinstance(progress, str) and progress == "log"
        if progress is not None and progress is not True and not log:
            if isinstance(progress, str) or not callable(progress):
                raise TypeError("progress must be None, True, False, 'log' or a callable "
                                f"progress(done, total, molecule), got {progress!r}")
            self.callback = progress
            return
        if progress is True or is_terminal(self.stream) or in_notebook(self.stream):
            try:
                from tqdm.auto import tqdm
            except ImportError as exc:
                if progress is True:
                    raise ImportError("progress=True needs tqdm (pip install "
                                      "'supercoil[distributed]')") from exc
                self.lines = True  # a terminal without tqdm: plain lines
                return
            self.bar = tqdm(total=self.total, file=self.stream, unit="molecule",
                            desc=prefix.rstrip(": ") or "fit_many", leave=True)
            return
        self.lines = log

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
