"""The command-line arguments every example script takes: ``--out DIR`` and ``--quick``.

The scripts in the repository's ``examples/`` folder build their parser with
:func:`example_parser` (adding their own arguments) and parse it with
:func:`example_arguments`, which also creates the output folder.
"""

from __future__ import annotations

import argparse
from pathlib import Path

__all__ = ["example_arguments", "example_parser"]


def example_parser(doc: str, default_out: str = "results") -> argparse.ArgumentParser:
    """The arguments every script in ``examples/`` takes.

    ``--out DIR`` (where PNG and CSV files go; created by :func:`example_arguments`)
    and ``--quick`` (a smaller run, used by the test suite). Scripts add their
    own arguments to the returned parser.
    """
    parser = argparse.ArgumentParser(description=doc.strip().splitlines()[0])
    parser.add_argument("--out", type=Path, default=Path(default_out), help="output folder")
    parser.add_argument("--quick", action="store_true",
                        help="a smaller run (the test suite uses it)")
    return parser


def example_arguments(doc: str, argv=None, default_out: str = "results", parser=None):
    """Parse an example script's arguments and create its output folder."""
    parser = parser or example_parser(doc, default_out)
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    return args
