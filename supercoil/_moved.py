"""The 0.1 module paths that moved in 0.2: one table and one warning for the aliases.

``import supercoil.hat`` (a shim module) and ``supercoil.hat`` (attribute access on the
package) both warn with :func:`warn_moved` and hand back the new module; the aliases are
kept for one release (removed in 0.3; CHANGELOG.md).
"""

from __future__ import annotations

import importlib
import warnings

__all__ = ["MOVED", "alias", "warn_moved"]

#: 0.1 name (under ``supercoil.``) -> the module it moved to in 0.2
MOVED = {"fitting": "supercoil.dna.fitting", "hat": "supercoil.dna.hat",
         "plectoneme": "supercoil.dna.plectoneme", "tweezers_data": "supercoil.dna.tweezers",
         "rough": "supercoil.rod.rough", "smooth": "supercoil.rod.smooth",
         "spinning": "supercoil.rod.spinning", "design": "supercoil.rod.design"}


def warn_moved(name, stacklevel):
    """Issue the DeprecationWarning naming the new path of ``supercoil.<name>``; its module."""
    new = MOVED[name]
    warnings.warn(f"supercoil.{name} is deprecated: it moved to {new} (the old path is kept "
                  "for one release)", DeprecationWarning, stacklevel=stacklevel + 1)
    return importlib.import_module(new)


def alias(name):
    """``(__getattr__, __dir__)`` of a shim module standing for ``supercoil.<name>``.

    Warns once, when the shim is imported (``stacklevel`` points at the importer).
    """
    new = warn_moved(name, stacklevel=3)

    def __getattr__(attr):
        return getattr(new, attr)

    def __dir__():
        return dir(new)

    return __getattr__, __dir__
