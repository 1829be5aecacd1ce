"""Kistler dynamometer: forces/<cut>.csv|.h5 (t_s, Fx_N, Fy_N, Fz_N).

Simulator of this instrument (issue #4). Until it is implemented it plans no files.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any


def plan(config: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Raw files this instrument writes in the synthetic study (none yet)."""
    return []
