"""Lazy public names of a package (PEP 562): the package's ``__init__`` imports nothing, and
each public name is loaded from its module on first use.

A package states one table ``module → the public names it defines`` and binds::

    __getattr__, __dir__, __all__ = lazy_exports(__name__, _EXPORTS)

A module without a dot is a submodule of the package (``"model"``); one with a dot is a full
module name (``"robomill.spectra"``). ``from robomill.calibration import identify`` keeps
working while a rule script imports the submodule it uses and, through
:mod:`robomill.pipeline.codedeps` (which reads this table without running it), depends on
that file alone.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping, Sequence


def module_name(package: str, module: str) -> str:
    """The full name of a table's ``module`` (a submodule of ``package`` unless dotted)."""
    return module if "." in module else f"{package}.{module}"


def lazy_exports(package: str, table: Mapping[str, Sequence[str]]
                 ) -> tuple[Callable[[str], object], Callable[[], list[str]], list[str]]:
    """``(__getattr__, __dir__, __all__)`` for ``package`` from ``table`` (module → the
    public names it defines). A name is imported from its module on first access.

    Raises
    ------
    TypeError
        A table entry whose names are one string (``{"model": "fit"}`` would otherwise
        export the letters ``f``, ``i``, ``t``).
    ValueError
        A name listed under two modules.
    """
    where: dict[str, str] = {}
    for module, names in table.items():
        if isinstance(names, str) or not all(isinstance(n, str) for n in names):
            raise TypeError(f"{package}: the lazy-export table maps a module to a list of "
                            f"names; {module!r} maps to {names!r}")
        for name in names:
            if name in where:
                raise ValueError(f"{package}: {name!r} is exported from both "
                                 f"{where[name]!r} and {module!r}")
            where[name] = module_name(package, module)

    def __getattr__(name: str) -> object:
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        return getattr(importlib.import_module(module), name)

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(where))

    return __getattr__, __dir__, sorted(where)
