"""The ``supercoil`` command line.

Each subcommand lives in its own module under :mod:`supercoil.commands` and
exposes ``register(subparsers)``, which adds its parser and sets
``func(args) -> int`` as the handler.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from supercoil import __version__

#: subcommand modules, in the order ``--help`` lists them
COMMANDS = ("params", "rod", "hat", "fit", "curves", "validate", "docs", "bench")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="supercoil",
        description="Double helices of twisted filaments: rubber rods and DNA plectonemes "
        "(Li, Zhao et al.; the physics is in the documentation's Theory pages).",
    )
    parser.add_argument("--version", action="version", version=f"supercoil {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        try:
            module = importlib.import_module(f"supercoil.commands.{name}")
        except ModuleNotFoundError as exc:
            if exc.name == f"supercoil.commands.{name}":
                continue  # subcommand not built yet
            raise
        module.register(sub)
    from supercoil.commands._common import allow_negative_values

    # "--turns -20:20:0.1" and "--turns=-20:20:0.1" mean the same (argparse alone would
    # take "-20:20:0.1" for an option)
    return allow_negative_values(parser)


def main(argv=None) -> int:
    """Run the command line; the exit status.

    0: done; 1: a fit failed (``supercoil fit``, documented there); 2: the command
    cannot run as given (no command, a bad argument or ``--out``, unreadable data; the
    message names the flag or the file, never a traceback).
    """
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        # a missing subcommand is a usage error (argparse's convention: status 2)
        parser.print_help(sys.stderr)
        print("supercoil: error: a COMMAND is required", file=sys.stderr)
        return 2
    from supercoil.commands._common import argument_flags, check_out_folder, error_text
    from supercoil.exceptions import SupercoilError

    out = getattr(args, "out", None)
    problem = check_out_folder(out) if out is not None else None
    if problem:  # before any computation: a bad folder costs no work
        print(f"supercoil {args.command}: error: {problem}", file=sys.stderr)
        return 2
    try:
        return int(args.func(args) or 0)
    except SupercoilError as exc:
        print(error_text(args.command, exc), file=sys.stderr)
        return 2
    except (TypeError, ValueError) as exc:
        if not argument_flags(exc):  # not about a flag's value: a bug, keep the traceback
            raise
        print(error_text(args.command, exc), file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
