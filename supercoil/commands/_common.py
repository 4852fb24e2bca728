"""Helpers shared by the ``supercoil`` subcommands.

* :func:`allow_negative_values`: argparse reads ``--turns -20:20:0.1`` as two
  options (``-20:20:0.1`` looks like a flag); :func:`supercoil.cli.build_parser`
  applies this so that ``--turns -20:20:0.1`` and ``--turns=-20:20:0.1`` mean the same.
* :func:`parse_range`: ``start:stop:step`` (both ends included), ``start:stop``
  (a default step) or ``a,b,c``, with an error message that names the flag.
* :func:`plain_warnings`: run a computation, collect its warnings and return them
  once each, as plain text (no Python warning text on the terminal).
* :data:`ARGUMENT_FLAGS`, :func:`flag_text`, :func:`error_text`, :func:`warning_text`: the
  one table from a library argument name to the command-line flag that sets it, and
  the messages built from it (an exception's ``argument`` attribute names the
  argument, so that no library message is rewritten into command-line wording).
* :func:`check_out_folder`: ``--out`` checked before any computation.
* :func:`source_checkout`: the source checkout for ``supercoil docs`` (the working
  folder, else the checkout the package is in).
"""

from __future__ import annotations

import argparse
import os
import re
import warnings
from pathlib import Path

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


#: library argument name -> the command-line flag that sets it. The
#: commands name the flag with this table instead of rewriting messages: an exception
#: whose ``argument`` attribute is a key gets the flag in front of its message, and a
#: Python keyword hint in a message (``check_settled=False``, ``calibration=``) becomes
#: the flag (:func:`flag_text`). Flags starting ``--no-`` set the argument to False.
#: tests/cli/test_cli_errors.py checks that every flag is an option of a command.
ARGUMENT_FLAGS = {
    # supercoil hat (hat_curve, buckling_turns, DNA.replace)
    "force": "--force",
    "turns": "--turns",
    "length": "--length",
    "short_tail_length": "--short-tail",
    "thermal": "--athermal",
    "model": "--model",
    "interaction": "--interaction",
    "end_loop": "--end-loop",
    # supercoil fit (fit_hat_curves, fit_many, compare_models, read_tweezers_csv)
    "vary": "--vary",
    "fixed": "--fix",
    "start": "--start",
    "bounds": "--bound",
    "sigma": "--sigma",
    "fit_turns_offset": "--no-turns-offset",
    "fit_extension_offset": "--no-extension-offset",
    "drop_incomplete": "--drop-incomplete",
    "executor": "--jobs",
    # supercoil curves (read_magscope, read_calisto, find_plateaus, rotation_curves)
    "settle": "--settle",
    "calibration": "--calibration",
    "reference_beads": "--reference",
    "reference": "--reference",
    "errors": "--errors",
    "check_settled": "--no-check-settled",
    "rotation_log": "--rotation-log",
    "height_log": "--height-log",
    "motor_path": "--motor",
}

#: a Python keyword hint in a message: ``name=`` and what follows up to a space, comma,
#: parenthesis or the end (``check_settled=False``, ``calibration=``); not a keyword of a
#: call written out in the message (``dna.replace(length=...)`` is Python code to type)
_KEYWORD_HINT = re.compile(
    r"(?<![\w-])(?<!\w\()(?P<name>[a-z_][a-z0-9_]*)=(?P<value>[^\s,;()]*)")


def flag_text(message: str) -> str:
    """``message`` with its Python keyword hints (``name=value``) written as flags.

    Only names in :data:`ARGUMENT_FLAGS` change: ``check_settled=False`` becomes
    ``--no-check-settled``, ``calibration=`` becomes ``--calibration``, ``sigma=5nm``
    becomes ``--sigma 5nm``.
    """

    def replace(m):
        flag = ARGUMENT_FLAGS.get(m["name"])
        if flag is None:
            return m[0]
        if flag.startswith("--no-") or not m["value"]:
            return flag
        return f"{flag} {m['value']}"

    return _KEYWORD_HINT.sub(replace, message)


def argument_flags(exc) -> list[str]:
    """The flags of the argument(s) ``exc`` names (its ``argument`` attribute), in order."""
    names = getattr(exc, "argument", None)
    names = (names,) if isinstance(names, str) else tuple(names or ())
    return list(dict.fromkeys(ARGUMENT_FLAGS[n] for n in names if n in ARGUMENT_FLAGS))


def error_text(command: str, exc) -> str:
    """``supercoil COMMAND: error: FLAG: message``: an exception in the command's terms.

    The flag comes from the exception's ``argument`` (through :data:`ARGUMENT_FLAGS`;
    left out when the message already names it); keyword hints become flags.
    """
    return f"supercoil {command}: error: {_flagged(exc)}"


def warning_text(command: str, warning) -> str:
    """``supercoil COMMAND: warning: FLAG: message``: a warning as :func:`error_text` does it.

    ``warning`` is the warning instance (``w.message`` of a caught warning), a string
    for a warning that names no argument.
    """
    return f"supercoil {command}: warning: {_flagged(warning)}"


def flagged_error(exc) -> str:
    """``Type: FLAG: message``: an exception of a failed comparison row in flag wording."""
    return f"{type(exc).__name__}: {_flagged(exc)}"


def _flagged(exc) -> str:
    """The message of ``exc`` with keyword hints as flags, the flags of its argument first."""
    text = flag_text(str(exc))
    flags = [f for f in argument_flags(exc) if f not in text]
    return f"{'/'.join(flags)}: {text}" if flags else text


def check_out_folder(out, flag: str = "--out"):
    """``None``, or a message saying why ``out`` cannot be the output folder.

    Checked before a command computes anything (a bad folder costs no work): ``out`` must be a
    folder or not exist yet, and the nearest existing folder above it must be writable.
    """
    path = Path(out)
    if path.exists() and not path.is_dir():
        return (f"{flag} {out}: is a file, not a folder (give a folder; it is created "
                "if missing)")
    parent = path
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if parent.exists() and not parent.is_dir():
        return f"{flag} {out}: {parent} is a file, so the folder cannot be created"
    if not path.exists() and not os.access(parent, os.W_OK | os.X_OK):
        return f"{flag} {out}: cannot create a folder in {parent} (no write permission)"
    return None


def is_source_checkout(root: Path, needs=("README.md", "examples", "docs")) -> bool:
    """Whether ``root`` holds ``needs`` (files or folders) of the repository."""
    return all((Path(root) / name).exists() for name in needs)


def source_checkout(given=None, needs=("README.md", "examples", "docs")):
    """The source checkout for ``supercoil docs``: ``given``, else a default, else None.

    The default is the working folder when it is a checkout (a user who installed the
    package with ``pip install .`` and runs the command in the repository), else the
    checkout the package itself is in (an editable install); ``None`` if neither is.
    """
    if given is not None:
        return Path(given)
    for root in (Path.cwd(), Path(__file__).resolve().parents[2]):
        if is_source_checkout(root, needs):
            return root
    return None
