"""Lazy public names of a package (PEP 562): the package's ``__init__`` imports nothing, and
each public name is loaded from its submodule on first use.

A science package (``robomill.calibration``, ``robomill.hexapod``, ``robomill.stiffness``)
states one table ``submodule → names``; ``from robomill.calibration import identify`` keeps
working while a rule script imports the submodule it uses and, through
:mod:`robomill.pipeline.codedeps`, depends on that file alone.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping, Sequence


def lazy_exports(package: str, table: Mapping[str, Sequence[str]]
                 ) -> tuple[Callable[[str], object], Callable[[], list[str]], list[str]]:
    """``(__getattr__, __dir__, __all__)`` for ``package`` from ``table`` (submodule → the
    public names it defines). A name is imported from ``package.submodule`` on first access
    and then kept in the package's namespace."""
    where = {name: module for module, names in table.items() for name in names}

    def __getattr__(name: str) -> object:
        module = where.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{module}"), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(where))

    return __getattr__, __dir__, sorted(where)
