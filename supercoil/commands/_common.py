"""Helpers shared by the ``supercoil`` subcommands.

* :func:`join_negative_values`: argparse reads ``--turns -20:20:0.1`` as two
  options (``-20:20:0.1`` looks like a flag), so :func:`supercoil.cli.main` rewrites
  ``--flag -VALUE`` into ``--flag=-VALUE`` before parsing, for every option that
  takes exactly one value. Both spellings then mean the same.
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

#: a value that starts with a minus and then a digit or a point: -20, -0.5, -20:20:0.1,
#: -3e2, -40turn (argparse itself only accepts plain negative numbers such as -20)
_NEGATIVE_VALUE = re.compile(r"^-\.?\d")


def _single_value_options(parser: argparse.ArgumentParser) -> set[str]:
    """Option strings (of ``parser`` and all its subparsers) that take exactly one value."""
    found: set[str] = set()
    stack = [parser]
    while stack:
        p = stack.pop()
        for action in p._actions:  # argparse has no public API for its actions
            if isinstance(action, argparse._SubParsersAction):
                stack.extend(action.choices.values())
            elif action.option_strings and action.nargs is None:
                found.update(s for s in action.option_strings if s.startswith("--"))
    return found


def join_negative_values(parser: argparse.ArgumentParser, argv: list[str]) -> list[str]:
    """``[..., "--turns", "-20:20:0.1", ...]`` -> ``[..., "--turns=-20:20:0.1", ...]``.

    Only for options of ``parser`` that take exactly one value, and only when the next
    word starts with ``-`` followed by a digit or a point (a negative number, range or
    quantity); everything else is passed on unchanged. Options that take several values
    (``nargs="+"``) are left alone: ``--flag=VALUE`` would give them one value only.
    """
    options = _single_value_options(parser)
    out: list[str] = []
    i = 0
    while i < len(argv):
        word = argv[i]
        if word == "--":
            out.extend(argv[i:])
            break
        if (word in options and i + 1 < len(argv)
                and _NEGATIVE_VALUE.match(argv[i + 1])):
            out.append(f"{word}={argv[i + 1]}")
            i += 2
            continue
        out.append(word)
        i += 1
    return out


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
