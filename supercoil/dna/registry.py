"""Name registries for DNA models and interactions (one mechanism for both).

A registry made for a package (``Registry(kind, base, package)``) registers the package's
own classes itself: each module of the package (``base`` and private modules apart) is
imported once, and every non-abstract subclass of the base defined there is registered
under its ``name``. Adding a model or an interaction to the package is adding its module;
user code registers its own with :meth:`Registry.register`.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil

from supercoil._checks import check_flag
from supercoil.exceptions import ModelError

__all__ = ["Registry"]


class Registry:
    """Maps registry names to classes; resolves a name or an instance to an instance."""

    def __init__(self, kind, base, package=None):
        self.kind = kind
        self.base = base
        self._classes = {}
        self._own = {}
        if package is not None:
            self._discover(package)

    def _discover(self, package):
        """Import each public module of ``package`` and register the classes defined there."""
        pkg = importlib.import_module(package)
        for info in sorted(pkgutil.iter_modules(pkg.__path__), key=lambda i: i.name):
            if info.name == "base" or info.name.startswith("_"):
                continue
            module = importlib.import_module(f"{package}.{info.name}")
            for cls in vars(module).values():
                if (isinstance(cls, type) and issubclass(cls, self.base)
                        and cls.__module__ == module.__name__ and not inspect.isabstract(cls)
                        and cls.name):
                    self.register(cls)
                    self._own[cls.__name__] = cls

    def package_classes(self):
        """``{class name: class}`` of the package's own classes (found in its modules)."""
        return dict(self._own)

    def register(self, cls, replace=False):
        """Register a subclass of the base (or an instance's class) under ``cls.name``."""
        replace = check_flag(replace, "replace")
        if isinstance(cls, self.base):
            cls = type(cls)
        if not (isinstance(cls, type) and issubclass(cls, self.base)):
            raise TypeError(f"a {self.kind} must subclass {self.base.__module__}."
                            f"{self.base.__name__}, got {cls!r}")
        name = getattr(cls, "name", "")
        if not isinstance(name, str) or not name:
            raise ValueError(f"{cls.__name__} needs a non-empty class attribute 'name'")
        if name in self._classes and self._classes[name] is not cls and not replace:
            raise ValueError(f"a {self.kind} named {name!r} is already registered "
                             "(pass replace=True to override it)")
        self._classes[name] = cls
        return cls

    def unregister(self, name):
        """Remove the class registered under ``name`` (returns it; for tests and plug-ins).

        Raises
        ------
        ModelError
            If nothing is registered under ``name``.
        """
        try:
            return self._classes.pop(name)
        except KeyError:
            raise ModelError(f"no {self.kind} named {name!r} is registered; registered: "
                             f"{', '.join(self.names())}") from None

    def get(self, spec, argname, **values):
        """An instance from a registered name or an instance (``values`` override parameters)."""
        if isinstance(spec, self.base):
            return spec.replace(**values) if values else spec
        if isinstance(spec, type) and issubclass(spec, self.base):
            return spec(**values)
        if not isinstance(spec, str):
            raise TypeError(f"{argname} must be a {self.kind} name ({', '.join(self.names())}) "
                            f"or a {self.base.__name__} instance, got {type(spec).__name__}")
        cls = self._classes.get(spec)
        if cls is None:
            raise ModelError(f"unknown {self.kind} {spec!r} for {argname}; available: "
                             f"{', '.join(self.names())}")
        return cls(**values)

    def names(self):
        return sorted(self._classes)
