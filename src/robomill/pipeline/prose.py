"""Sentences from findings: the chapters' prose as templates filled from a findings artefact.

A chapter keeps its sentences as data (``src/robomill/data/templates/<chapter>.yaml``): one template
per statement, Markdown with named fields (``{n_modes}``, ``{f_hz:.2f}``, ``{band_hz[0]:.4g}``),
so the notebook holds templates and calls, no computation, no threshold and no typed number
(docs/design.md, principle 10; the habit of Quarto's inline expressions and myst-nb's ``glue``). A
template is a string, or a mapping with

* ``text``: the sentence;
* ``absent``: what to say when a field it needs is missing (or ``None``) or the finding is
  absent (default: nothing) — never a Python error;
* ``when`` / ``unless``: a finding (or a list of them) whose values must all be truthy /
  all falsy for ``text`` (``absent`` otherwise);
* ``cases``: ``{<text id>: sentence}`` chosen by the value of the finding named ``by``
  (``absent`` for an id not listed).

A list value formats element-wise and joins with ", " (``{modes_hz:.2f}`` → "20.01, 35.20"), or
with the separator after a ``|`` (``{flagged:|; }``); a
``[low, high]`` range is indexed (``{band_hz[0]}``). Fields may also come from ``extra`` (a
figure or table reference of the notebook's numbering).
"""

from __future__ import annotations

import string
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from robomill.findings import Findings

TEMPLATES_DIR = Path(__file__).resolve().parents[1] / "data" / "templates"


class _Missing(LookupError):
    """A field the template needs is missing or null."""


class _Formatter(string.Formatter):
    def get_value(self, key, args, kwargs):
        if key not in kwargs or kwargs[key] is None:
            raise _Missing(key)
        return kwargs[key]

    def get_field(self, field_name, args, kwargs):
        try:
            obj, first = super().get_field(field_name, args, kwargs)
        except (IndexError, KeyError, TypeError, AttributeError) as err:
            raise _Missing(field_name) from err
        if obj is None:
            raise _Missing(field_name)
        return obj, first

    def format_field(self, value, format_spec):
        if isinstance(value, list | tuple):
            spec, _, sep = format_spec.partition("|")
            return (sep or ", ").join(self.format_field(v, spec) for v in value)
        if isinstance(value, bool) and format_spec:
            value = int(value)
        try:
            return super().format_field(value, format_spec)
        except (ValueError, TypeError) as err:
            raise _Missing(f"{value!r}:{format_spec}") from err


_FORMATTER = _Formatter()


def fill(text: str, fields: Mapping[str, Any]) -> str | None:
    """``text`` with its fields filled, or ``None`` when one is missing or cannot be
    formatted."""
    try:
        return _FORMATTER.vformat(text, (), dict(fields))
    except _Missing:
        return None


def _fields(findings: Findings | Mapping[str, Any], extra: Mapping[str, Any] | None):
    values = findings.values() if isinstance(findings, Findings) else dict(findings)
    return {**values, **(extra or {})}


def render(template: str | Mapping[str, Any], findings: Findings | Mapping[str, Any],
           extra: Mapping[str, Any] | None = None) -> str:
    """One template filled from ``findings`` (a :class:`Findings` or a key → value mapping)."""
    fields = _fields(findings, extra)
    if isinstance(template, str):
        template = {"text": template}
    absent = template.get("absent", "")
    absent_text = fill(absent, fields) if absent else ""
    absent_text = absent_text if absent_text is not None else ""
    when, unless = template.get("when", []), template.get("unless", [])
    if (not all(fields.get(k) for k in ([when] if isinstance(when, str) else when))
            or any(fields.get(k) for k in ([unless] if isinstance(unless, str) else unless))):
        return absent_text
    if "cases" in template:
        chosen = template["cases"].get(str(fields.get(template.get("by", ""), "")))
        text = chosen if chosen is not None else None
    else:
        text = template.get("text")
    if text is None:
        return absent_text
    filled = fill(text, fields)
    return filled if filled is not None else absent_text


def load_templates(chapter: str, directory: str | Path | None = None) -> dict[str, Any]:
    """The templates of one chapter: ``<directory>/<chapter>.yaml`` (default
    ``src/robomill/data/templates``), or ``directory`` itself when it names a ``.yaml`` file (the
    chapter rule's ``templates`` input), a mapping name → template."""
    if directory is not None and str(directory).endswith(".yaml"):
        path = Path(directory)
    else:
        path = Path(directory or TEMPLATES_DIR) / f"{chapter}.yaml"
    data = yaml.safe_load(path.read_text())
    if not isinstance(data, Mapping):
        raise ValueError(f"{path}: expected a mapping of template name → template")
    return dict(data)


COMPARISON_COLUMNS = ["quantity", "ours", "source_value", "unit", "tolerance", "verdict",
                      "reason", "citation"]


def comparison_table(findings: Findings):
    """The comparison rows of a findings artefact as a table (the "Against the thesis"
    section of a chapter): ours, the source's value, the verdict, the reason of any miss."""
    import pandas as pd

    return pd.DataFrame(findings.comparisons, columns=COMPARISON_COLUMNS)


class Prose:
    """A chapter's templates bound to its findings: ``prose("n_modes")`` is the sentence."""

    def __init__(self, templates: Mapping[str, Any], findings: Findings | Mapping[str, Any]):
        self.templates = dict(templates)
        self.findings = findings

    def __call__(self, *names: str, sep: str = " ", **extra: Any) -> str:
        missing = [n for n in names if n not in self.templates]
        if missing:
            raise KeyError(f"no template {', '.join(missing)}")
        parts = (render(self.templates[n], self.findings, extra) for n in names)
        return sep.join(p for p in parts if p)
