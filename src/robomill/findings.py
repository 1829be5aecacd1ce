"""Findings: what a stage's artefacts say, as data a chapter renders into sentences.

A *finding* is one thing a chapter states (docs/design.md, principle 10): a ``key``, a ``value`` (a
number, a ``[low, high]`` range, a list of numbers, a flag ``true``/``false`` or a text id such
as ``"flip"``), its ``unit``; when it is a verdict, the ``verdict`` (``"pass"``/``"fail"`` or a
text id) with the ``threshold`` that decided it and the ``config_key`` the threshold comes
from; and the ``evidence``: the ``artefact`` and what in it (``what``: a column, a variable, a
selection). A :class:`Findings` collection is written as ``results/<stage>/findings.yaml``
(plain YAML, numbers as numbers) and read back; the chapter renders it with
:mod:`robomill.pipeline.prose`. This module imports no pipeline code.

The collection also carries ``comparisons``: the rows of the chapter's "Against the thesis"
section (ours, the source's value and citation, the verdict, the reason of a miss), built from
the scorecard's checks of this stage, empty for a study that is not the thesis' design.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

FINDINGS_VERSION = 1


def plain(value: Any) -> Any:
    """``value`` as plain YAML data: numpy scalars and arrays to floats/ints/bools/lists,
    NaN to ``None`` (YAML has no portable NaN), tuples to lists."""
    if isinstance(value, np.ndarray):
        return [plain(v) for v in value.tolist()]
    if isinstance(value, list | tuple):
        return [plain(v) for v in value]
    if isinstance(value, Mapping):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, np.bool_ | bool):
        return bool(value)
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, np.floating | float):
        v = float(value)
        return None if math.isnan(v) else v
    if isinstance(value, np.str_):
        return str(value)
    return value


@dataclass
class Finding:
    """One statement of a chapter, with what decided it and where it comes from."""

    key: str
    value: Any
    unit: str = ""
    verdict: str | None = None
    threshold: Any = None
    config_key: str | None = None
    artefact: str | None = None
    what: str | None = None

    def as_dict(self) -> dict[str, Any]:
        d = {k: plain(v) for k, v in asdict(self).items()}
        return {k: v for k, v in d.items() if v is not None or k == "value"}


@dataclass
class Findings:
    """The findings of one stage, by key, and its comparison rows against the sources."""

    stage: str
    items: dict[str, Finding] = field(default_factory=dict)
    comparisons: list[dict[str, Any]] = field(default_factory=list)

    def add(self, key: str, value: Any, unit: str = "", *, artefact: str | None = None,
            what: str | None = None, verdict: str | None = None, threshold: Any = None,
            config_key: str | None = None) -> Finding:
        """Add (or replace) one finding; a verdict must name its threshold and config key."""
        if verdict is not None and (threshold is None or config_key is None):
            raise ValueError(f"finding {key!r}: a verdict needs the threshold that decided "
                             "it and the config key it comes from")
        f = Finding(key, plain(value), unit, verdict, plain(threshold), config_key, artefact,
                    what)
        self.items[key] = f
        return f

    def __contains__(self, key: str) -> bool:
        return key in self.items

    def __getitem__(self, key: str) -> Finding:
        return self.items[key]

    def values(self) -> dict[str, Any]:
        """The fields a sentence template uses: every finding's value by key, and for a
        verdict ``verdict_<key>`` and ``threshold_<key>``; ``n_comparisons`` and
        ``n_comparisons_pass`` count the comparison rows."""
        out = {k: f.value for k, f in self.items.items()}
        for k, f in self.items.items():
            if f.verdict is not None:
                out[f"verdict_{k}"] = f.verdict
                out[f"threshold_{k}"] = f.threshold
        out["n_comparisons"] = len(self.comparisons)
        out["n_comparisons_pass"] = sum(c.get("verdict") == "pass" for c in self.comparisons)
        return out

    def as_dict(self) -> dict[str, Any]:
        return {"version": FINDINGS_VERSION, "stage": self.stage,
                "findings": [f.as_dict() for f in self.items.values()],
                "comparisons": [plain(c) for c in self.comparisons]}


def write_findings(findings: Findings, path: str | Path) -> None:
    """Write ``findings`` as plain YAML (numbers as numbers, keys in the order added)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(yaml.safe_dump(findings.as_dict(), sort_keys=False, allow_unicode=True,
                                   width=100))


def findings_from_dict(data: Mapping[str, Any], source: str = "findings") -> Findings:
    """A :class:`Findings` from its YAML form; one clear error naming what is wrong."""
    if not isinstance(data, Mapping) or "findings" not in data:
        raise ValueError(f"{source}: expected a mapping with 'stage' and a 'findings' list")
    out = Findings(str(data.get("stage", "")))
    for i, item in enumerate(data["findings"] or []):
        if not isinstance(item, Mapping) or "key" not in item or "value" not in item:
            raise ValueError(f"{source}: findings[{i}]: expected a mapping with 'key' and "
                             "'value'")
        known = {k: item[k] for k in Finding.__dataclass_fields__ if k in item}
        out.items[str(item["key"])] = Finding(**known)
    out.comparisons = list(data.get("comparisons") or [])
    return out


def read_findings(path: str | Path) -> Findings:
    """Read a ``findings.yaml`` written by :func:`write_findings`."""
    return findings_from_dict(yaml.safe_load(Path(path).read_text()), str(path))


def comparison_rows(card_rows: Iterable[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """The "Against the thesis" rows from scorecard rows (``build_scorecard`` records):
    quantity, ours, the source's value, unit, tolerance, verdict, reason and the citation."""
    keep = ("quantity", "ours", "source_value", "unit", "tolerance", "verdict", "reason")
    return [{**{k: plain(r.get(k)) for k in keep},
             "citation": f"{r.get('source', '')}, {r.get('where', '')}"} for r in card_rows]
