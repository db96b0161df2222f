"""Deprecated module paths (the package's flat layout), importable for one release with a DeprecationWarning.

The package's modules live in ``methods/``, ``halfspace/``, ``instationary/`` and ``stepping/``.  A program that
imports one of the deprecated paths below gets a module that forwards every attribute to the new modules (first match in
the listed order) and a DeprecationWarning that names them.  Names that moved out of a module that still exists are
forwarded by that module's ``__getattr__`` (:func:`moved_attribute`).
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import types
import warnings

MODULES = {
    "rollcontact.api": ("rollcontact.dispatch", "rollcontact.method", "rollcontact.methods.polynomial.accuracy",
                        "rollcontact.methods.discretised.accuracy", "rollcontact.methods.closed_form"),
    "rollcontact.model": ("rollcontact.stepping.model", "rollcontact.stepping.parameters",
                          "rollcontact.stepping.state", "rollcontact.stepping.transient"),
    "rollcontact.polynomial": ("rollcontact.methods.polynomial.solver", "rollcontact.methods.polynomial.validity",
                               "rollcontact.methods.polynomial.monomial"),
    "rollcontact.discretised": ("rollcontact.methods.discretised.steady", "rollcontact.methods.discretised.rolling",
                                "rollcontact.halfspace.solver", "rollcontact.halfspace.grid"),
    "rollcontact._bem": ("rollcontact.halfspace.elements",),
    "rollcontact.chebyshev": ("rollcontact.methods.polynomial.chebyshev",),
    "rollcontact.multipatch": ("rollcontact.methods.polynomial.patches",),
    "rollcontact.velocity_friction": ("rollcontact.methods.polynomial.slip",),
    "rollcontact.split_friction": ("rollcontact.methods.polynomial.patches_slip",),
}
"""Deprecated module path -> the modules that hold its names now."""

ATTRIBUTES = {
    "rollcontact.closed_form": {"solve_closed_form": "rollcontact.methods.closed_form",
                                "inapplicable": "rollcontact.methods.closed_form"},
}
"""Module that still exists -> names that moved out of it -> their module now."""


class MovedModule(types.ModuleType):
    """Stands for a deprecated module path: forwards attribute reads to the modules that hold the names now."""

    def __getattr__(self, name: str):
        for target in MODULES[self.__name__]:
            module = importlib.import_module(target)
            if hasattr(module, name):
                return getattr(module, name)
        raise AttributeError(f"module {self.__name__!r} has no attribute {name!r} (it moved to "
                             f"{', '.join(MODULES[self.__name__])})")


class MovedFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds the deprecated module paths of :data:`MODULES` (installed on ``sys.meta_path`` by ``rollcontact``)."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname in MODULES:
            return importlib.util.spec_from_loader(fullname, self)
        return None

    def create_module(self, spec):
        return MovedModule(spec.name)

    def exec_module(self, module):
        warnings.warn(f"{module.__name__} is deprecated: import from {', '.join(MODULES[module.__name__])}",
                      DeprecationWarning, stacklevel=2)


def moved_attribute(module: str, name: str):
    """The value of ``name`` that moved out of ``module`` (with a DeprecationWarning); AttributeError otherwise."""
    target = ATTRIBUTES.get(module, {}).get(name)
    if target is None:
        raise AttributeError(f"module {module!r} has no attribute {name!r}")
    warnings.warn(f"{module}.{name} is deprecated: import it from {target}", DeprecationWarning, stacklevel=3)
    return getattr(importlib.import_module(target), name)


def install() -> None:
    """Put :class:`MovedFinder` on ``sys.meta_path`` (once)."""
    if not any(isinstance(finder, MovedFinder) for finder in sys.meta_path):
        sys.meta_path.append(MovedFinder())
