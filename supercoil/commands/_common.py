"""Helpers shared by the ``supercoil`` subcommands.

* :func:`allow_negative_values`: argparse reads ``--turns -20:20:0.1`` as two
  options (``-20:20:0.1`` looks like a flag); :func:`supercoil.cli.build_parser`
  applies this so that ``--turns -20:20:0.1`` and ``--turns=-20:20:0.1`` mean the same.
* :func:`parse_range`: ``start:stop:step`` (both ends included), ``start:stop``
  (a default step) or ``a,b,c``, with an error message that names the flag.
* :func:`plain_warnings`: run a computation, collect its warnings and return them
  once each, as plain text (no Python warning text on the terminal).
"""

from __future__ import annotations

import argparse
import re
import warnings

import numpy as np

#: a word that starts with a minus and then a digit or a point is a value, never an option:
#: -20, -0.5, -.5, -20:20:0.1, -3e2, -40turn, "-10 cm" (argparse's own pattern accepts plain
#: negative numbers only; written to work whether argparse calls match or fullmatch)
NEGATIVE_VALUE = re.compile(r"-\.?\d.*", re.S)


def allow_negative_values(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Let every option of ``parser`` and its subparsers take values that start with ``-``.

    argparse reads ``--turns -20:20:0.1`` as two options, because ``-20:20:0.1`` is not a
    plain negative number; after this call it reads it as ``--turns=-20:20:0.1`` does,
    also for options with several values (``--slack -1cm 2cm``). No option of the
    package's parsers starts with ``-`` and a digit, so nothing else changes.
    """
    stack = [parser]
    while stack:
        p = stack.pop()
        # argparse has no public hook: its parsers decide "option or value" with this
        # pattern (argparse.ArgumentParser._parse_optional)
        p._negative_number_matcher = NEGATIVE_VALUE
        for action in p._actions:
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())
    return parser


def parse_range(text: str, flag: str, default_step: float = 0.1) -> np.ndarray:
    """Values of a range option: ``start:stop:step``, ``start:stop`` or ``a,b,c``.

    ``start:stop:step`` includes both ends (``stop`` when it is on the grid, to 1e-9 of
    a step); ``step`` must be positive and ``stop >= start``. Raises
    ``argparse.ArgumentTypeError`` naming ``flag`` and the text for anything else (argparse
    then exits with status 2 and the usage line).
    """
    try:
        if ":" in text:
            parts = [float(p) for p in text.split(":")]
            if len(parts) == 2:
                parts.append(default_step)
            if len(parts) != 3:
                raise ValueError
            start, stop, step = parts
            if not (np.isfinite(parts).all() and step > 0 and stop >= start):
                raise ValueError
            n = int(np.floor((stop - start) / step + 1e-9)) + 1
            if n > 10_000_000:
                raise ValueError
            return start + step * np.arange(n)
        values = np.array([float(p) for p in text.split(",")])
        if not np.isfinite(values).all():
            raise ValueError
        return values
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{flag} {text!r}: expected start:stop:step (step > 0, stop >= start, at most "
            f"1e7 values), start:stop (step {default_step:g}) or a comma-separated list of "
            "finite numbers"
        ) from None


def plain_warnings(func, *args, **kwargs):
    """``(result, messages)``: ``func(*args, **kwargs)`` and its warnings, each text once.

    The messages keep their order of first appearance; the command prints them in its
    own words instead of Python's ``file:line: Category: text`` lines.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = func(*args, **kwargs)
    messages = list(dict.fromkeys(str(w.message) for w in caught))
    return result, messages
