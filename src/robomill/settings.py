"""A stage's settings, read one way: from the configuration as its schema fills it.

Every default of a configuration key is written once, in the schemas, package data
(``robomill/data/schemas/config.schema.yaml`` and
``robomill/data/schemas/config/<section>.schema.yaml``).
The workflow validates the configuration, which fills them; a stage reads its section with
:func:`config_section` (a mapping: the simulators, the surface analysis, the plan) or
:func:`settings_from` (its settings dataclass), which fill from the same schema whatever a
configuration given by hand leaves out (a test's, a notebook's). A settings dataclass whose
fields have defaults takes them from the schema (:func:`schema_default`), never a literal of
its own.
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Mapping
from functools import cache
from pathlib import Path
from typing import Any, TypeVar

T = TypeVar("T")

#: the package's configuration schemas (the top-level one and a folder of sections)
SCHEMAS = Path(__file__).resolve().parent / "data" / "schemas"


@cache
def _schema_file(path: str) -> dict[str, Any]:
    import yaml

    with open(path) as fh:
        return yaml.load(fh, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))


SECTIONS: tuple[tuple[tuple[str, ...], str], ...] = (
    (("data",), "data"),
    (("cell",), "cell"),
    (("experiment",), "experiment"),
    (("synth",), "synth"),
    (("synth", "profilometer"), "synth_profilometer"),
    (("synth", "dynamometer"), "synth_dynamometer"),
    (("synth", "tracker"), "synth_tracker"),
    (("synth", "impact"), "synth_impact"),
    (("synth", "ctrack"), "synth_ctrack"),
    (("synth", "loadtests"), "synth_loadtests"),
    (("synth", "recordings"), "synth_recordings"),
    (("chapters",), "chapters"),
    (("book",), "book"),
    (("calibration",), "calibration"),
    (("surface",), "surface"),
    (("forces",), "forces"),
    (("straightness",), "straightness"),
    (("modal",), "modal"),
    (("chatter",), "chatter"),
    (("stiffness",), "stiffness"),
    (("hexapod",), "hexapod"),
)
"""Config sections and their schema files ``src/robomill/data/schemas/config/<name>.schema.yaml``,
validated in this order after the top-level ``config.schema.yaml``
(:func:`robomill.pipeline.config.validate_config`, which the Snakefile calls)."""


@cache
def _section_schema(section: str) -> dict[str, Any]:
    """The schema of config section ``section`` (``"synth.tracker"``, ``"plan.simulate"``):
    the section's own schema file where it has one, else the part of the schema of the
    nearest section above it (the top-level schema for ``plan``)."""
    files = {".".join(keys): name for keys, name in SECTIONS}
    keys = section.split(".") if section else []
    for n in range(len(keys), -1, -1):
        head = ".".join(keys[:n])
        if n == 0 or head in files:
            path = SCHEMAS / ("config.schema.yaml" if n == 0
                              else f"config/{files[head]}.schema.yaml")
            node = _schema_file(str(path))
            for k in keys[n:]:
                try:
                    node = node["properties"][k]
                except (KeyError, TypeError):
                    raise KeyError(f"no config section {section!r} in the schemas") from None
            return node
    raise KeyError(section)  # unreachable: n == 0 always matches


def _fill(value: Any, schema: Mapping[str, Any]) -> Any:
    """``value`` with every key its ``schema`` states a default for and it lacks, filled
    (in nested mappings too, as the workflow's validation fills them)."""
    props = schema.get("properties") if isinstance(schema, Mapping) else None
    if not isinstance(value, dict) or not isinstance(props, Mapping):
        return value
    for key, sub in props.items():
        if key not in value and isinstance(sub, Mapping) and "default" in sub:
            value[key] = copy.deepcopy(sub["default"])
        if key in value:
            value[key] = _fill(value[key], sub)
    return value


def schema_defaults(section: str) -> dict[str, Any]:
    """The defaults the schema states for the keys of config section ``section``."""
    return _fill({}, _section_schema(section))


def schema_default(section: str, key: str) -> Any:
    """The default the schema states for ``<section>.<key>`` (a settings dataclass' field
    default: ``welch_nperseg: int = schema_default("forces", "welch_nperseg")``)."""
    defaults = schema_defaults(section)
    if key not in defaults:
        raise KeyError(f"the schema states no default for config key {section}.{key}")
    return defaults[key]


def section_settings(values: Mapping[str, Any] | None, section: str) -> dict[str, Any]:
    """The ``values`` of config section ``section`` (``"surface"``), every key its schema
    gives a default for filled where ``values`` lacks it; a copy."""
    return _fill(copy.deepcopy(dict(values or {})), _section_schema(section))


def config_section(config: Mapping[str, Any], section: str) -> dict[str, Any]:
    """Config section ``section`` (``"synth.tracker"``) of ``config``, every key its schema
    gives a default for filled where ``config`` lacks it (a validated configuration lacks
    none); a copy."""
    node: Any = config
    for k in section.split("."):
        node = node.get(k) if isinstance(node, Mapping) else None
    return section_settings(node, section)


def dataclass_from_mapping(cls: type[T], section: Mapping[str, Any], *,
                           strict: str | None = None) -> T:
    """An instance of the dataclass ``cls`` from the keys of ``section`` that are its fields.

    Keys that are not fields are ignored (a config section that also holds other settings),
    unless ``strict`` names the section (e.g. ``"chatter.seed.params"``): then an unknown key
    (a misspelt one) is a :class:`robomill.errors.ConfigError` naming the section, the
    keys and the fields expected.
    """
    names = {f.name for f in dataclasses.fields(cls)}
    if strict is not None:
        unknown = sorted(set(section) - names)
        if unknown:
            from robomill.errors import ConfigError

            raise ConfigError(f"{strict}: unknown key(s) {unknown}; expected some of "
                              f"{sorted(names)}")
    return cls(**{k: section[k] for k in names if k in section})


def settings_from(cls: type[T], config: Mapping[str, Any], section: str) -> T:
    """The settings dataclass ``cls`` of config section ``section`` (:func:`config_section`:
    the schema's defaults where ``config`` lacks a key)."""
    return dataclass_from_mapping(cls, config_section(config, section))


class FromMapping:
    """Mixin of a settings dataclass read from a config section whose other keys it ignores:
    ``Settings.from_mapping(config["section"])`` (:func:`dataclass_from_mapping`)."""

    @classmethod
    def from_mapping(cls, section: Mapping[str, Any]):
        """From a config section (keys that are not fields ignored)."""
        return dataclass_from_mapping(cls, section)
