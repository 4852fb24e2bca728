"""Deprecated alias of :mod:`supercoil.dna.fitting` (moved in 0.2; removed in 0.3)."""

import importlib as _importlib
import warnings as _warnings

_warnings.warn("supercoil.fitting is deprecated: it moved to supercoil.dna.fitting "
               "(the old path is kept for one release)", DeprecationWarning,
               stacklevel=2)
_new = _importlib.import_module("supercoil.dna.fitting")


def __getattr__(name):
    return getattr(_new, name)


def __dir__():
    return dir(_new)
