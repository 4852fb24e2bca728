"""Deprecated alias of :mod:`supercoil.rod.spinning` (moved in 0.2; removed in 0.3)."""

import importlib as _importlib
import warnings as _warnings

_warnings.warn("supercoil.spinning is deprecated: it moved to supercoil.rod.spinning "
               "(the old path is kept for one release)", DeprecationWarning,
               stacklevel=2)
_new = _importlib.import_module("supercoil.rod.spinning")


def __getattr__(name):
    return getattr(_new, name)


def __dir__():
    return dir(_new)
