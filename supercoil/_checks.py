"""Argument checks shared by the public functions (one helper per kind of argument)."""

from __future__ import annotations

import numpy as np

__all__ = ["check_flag"]


def check_flag(value, name):
    """``value`` as a bool; TypeError naming ``name`` unless it is True/False (or numpy bool).

    Strings such as ``"no"`` or ``"False"`` are rejected, not read as truthy.
    """
    if isinstance(value, bool | np.bool_):
        return bool(value)
    raise TypeError(f"{name} must be True or False, got {value!r}")
