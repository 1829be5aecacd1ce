"""The ``config.yaml: surface`` settings of the profile analysis: the schema's
(``src/robomill/data/schemas/config/surface.schema.yaml``) defaults where a section lacks a key."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from robomill.settings import section_settings


def settings(section: Mapping[str, Any] | None) -> dict[str, Any]:
    """``surface`` settings, the schema's defaults filled
    (:func:`robomill.settings.section_settings`)."""
    return section_settings(section, "surface")
