"""The ``supercoil`` command line.

Each subcommand lives in its own module under :mod:`supercoil.commands` and
exposes ``register(subparsers)``, which adds its parser and sets
``func(args) -> int`` as the handler.
"""

from __future__ import annotations

import argparse
import importlib
import sys

from . import __version__

#: subcommand modules, in the order ``--help`` lists them
COMMANDS = ("params", "rod", "hat", "fit", "bench")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="supercoil",
        description="Double helices of twisted filaments: rubber rods and DNA plectonemes "
        "(Li, Zhao et al.; see MODEL.md).",
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
    return parser


def main(argv=None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    if not getattr(args, "func", None):
        parser.print_help()
        return 0
    from .exceptions import SupercoilError

    try:
        return int(args.func(args) or 0)
    except SupercoilError as exc:
        print(f"supercoil {args.command}: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
