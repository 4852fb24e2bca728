"""Deprecated alias of :mod:`supercoil.dna.hat` (moved in 0.2; removed in 0.3)."""

import importlib as _importlib
import warnings as _warnings

_warnings.warn("supercoil.hat is deprecated: it moved to supercoil.dna.hat "
               "(the old path is kept for one release)", DeprecationWarning,
               stacklevel=2)
_new = _importlib.import_module("supercoil.dna.hat")


def __getattr__(name):
    return getattr(_new, name)


def __dir__():
    return dir(_new)
