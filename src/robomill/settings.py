"""Settings dataclasses from configuration mappings: the one constructor that takes a config
section's keys that a dataclass has as fields (the rest left at the dataclass' defaults).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from typing import Any, TypeVar

T = TypeVar("T")


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


class FromMapping:
    """Mixin of a settings dataclass read from a config section whose other keys it ignores:
    ``Settings.from_mapping(config["section"])`` (:func:`dataclass_from_mapping`)."""

    @classmethod
    def from_mapping(cls, section: Mapping[str, Any]):
        """From a config section (keys that are not fields ignored)."""
        return dataclass_from_mapping(cls, section)
