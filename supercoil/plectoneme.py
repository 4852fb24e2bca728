"""Deprecated alias of :mod:`supercoil.dna.plectoneme` (moved in 0.2; removed in 0.3)."""

import importlib as _importlib
import warnings as _warnings

_warnings.warn("supercoil.plectoneme is deprecated: it moved to supercoil.dna.plectoneme "
               "(the old path is kept for one release)", DeprecationWarning,
               stacklevel=2)
_new = _importlib.import_module("supercoil.dna.plectoneme")


def __getattr__(name):
    return getattr(_new, name)


def __dir__():
    return dir(_new)
