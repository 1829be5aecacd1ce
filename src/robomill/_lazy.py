"""Lazy package exports (PEP 562): a package's public names loaded from their submodule on
first use, so that importing the package itself imports nothing.

A science subpackage's ``__init__.py`` keeps a table ``name → submodule`` and binds
``__getattr__, __dir__, __all__ = lazy_exports(__name__, TABLE)``. Rule scripts and
notebooks import from the submodules directly, so the workflow's code-dependency tracking
(:mod:`robomill.pipeline.codedeps`, which reads imports without running them) ties each
rule to the submodules it uses and not to the whole package.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any


def lazy_exports(package: str, table: Mapping[str, str]
                 ) -> tuple[Callable[[str], Any], Callable[[], list[str]], list[str]]:
    """``(__getattr__, __dir__, __all__)`` for ``package`` whose public name ``n`` lives in
    ``package + "." + table[n]`` (imported on first access, then cached in the package)."""
    names = sorted(table)

    def __getattr__(name: str) -> Any:
        sub = table.get(name)
        if sub is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{sub}"), name)
        setattr(importlib.import_module(package), name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(names) | set(table.values()))

    return __getattr__, __dir__, names
