"""Subcommands of the ``supercoil`` command line, one module each (see :mod:`supercoil.cli`)."""
