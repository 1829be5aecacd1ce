"""The planted truth of the virtual study: the cell's own plus each instrument's."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import xarray as xr

from robomill.synth.cell import cell_from_config
from robomill.synth.plan import instruments


def cell_truth(config: Mapping[str, Any]) -> xr.Dataset:
    """Truth dataset: the cell (gears, modes, cutting coefficients) merged with whatever each
    instrument module plants (its optional ``truth(config, cell) -> xr.Dataset``)."""
    cell = cell_from_config(config)
    parts = [cell.truth()]
    for module in instruments().values():
        fn = getattr(module, "truth", None)
        if fn is not None:
            parts.append(fn(config, cell))
    return xr.merge(parts, combine_attrs="drop_conflicts", compat="override")
