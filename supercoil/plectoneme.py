"""Deprecated alias of :mod:`supercoil.dna.plectoneme` (moved in 0.2; removed in 0.3)."""

from supercoil._moved import alias as _alias

__getattr__, __dir__ = _alias("plectoneme")
