"""The sources' reference numbers: one file, one citation per value.

Every number the thesis and the seed papers print that this study is compared with lives once
in ``robomill/data/references.yaml``: key → ``value`` (a number, ``[low, high]``, or a text
for a part of the source's setup: ``thesis.cell.robot``), ``unit``,
``source`` (the document), ``where`` (table, figure, section or equation in it) and
``quantity``. The scorecard (:mod:`robomill.pipeline.scorecard`), the findings of the chapters
and module constants such as :data:`robomill.modal.peaks.THESIS_NATURAL_HZ` read them here, so
a source number is typed in one place only.
"""

from __future__ import annotations

from functools import cache
from importlib import resources
from typing import Any

import yaml

REFERENCE_FIELDS = ("value", "unit", "source", "where", "quantity")


@cache
def _load() -> dict[str, dict[str, Any]]:
    text = resources.files("robomill.data").joinpath("references.yaml").read_text()
    refs = yaml.safe_load(text)["references"]
    for key, ref in refs.items():
        missing = [f for f in REFERENCE_FIELDS if f not in ref]
        if missing:
            raise ValueError(f"references.yaml: entry {key!r} lacks {', '.join(missing)}; "
                             f"expected the fields {', '.join(REFERENCE_FIELDS)}")
    return refs


def load_references() -> dict[str, dict[str, Any]]:
    """Every reference entry by key (a copy: callers may change it)."""
    return {k: dict(v) for k, v in _load().items()}


def reference(key: str) -> dict[str, Any]:
    """One entry: ``value``, ``unit``, ``source``, ``where``, ``quantity``."""
    refs = _load()
    if key not in refs:
        raise KeyError(f"references.yaml: no entry {key!r}")
    return dict(refs[key])


def value(key: str) -> Any:
    """The value of one entry (a float, or a ``[low, high]`` list)."""
    return reference(key)["value"]


def values(prefix: str) -> dict[str, Any]:
    """The values of every entry whose key starts with ``prefix`` (file order)."""
    return {k: v["value"] for k, v in _load().items() if k.startswith(prefix)}


def citation(key: str) -> str:
    """``source, where`` of one entry, for a table column or a sentence."""
    ref = reference(key)
    return f"{ref['source']}, {ref['where']}"
