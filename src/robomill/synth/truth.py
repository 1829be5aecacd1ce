"""The planted truth of the virtual study: the cell's own plus each instrument's.

The one module that imports every simulator (the simulators import the plan,
:mod:`robomill.io.synthetic_layout`, which imports none of them).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import xarray as xr

from robomill.synth import ctrack, dynamometer, impact, loadtests, profilometer, tracker
from robomill.synth.cell import cell_from_config


def instruments() -> dict[str, Any]:
    """The simulator module of each raw-data kind."""
    return {"profile": profilometer, "force": dynamometer, "tracker": tracker,
            "impact": impact, "ctrack": ctrack, "stiffness": loadtests}


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
