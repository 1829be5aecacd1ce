"""The configured lobe cases (``chatter.cases``): each case's zero-order and converged
spectral-element lobes as one dataset."""

from __future__ import annotations

import xarray as xr

from robomill.chatter.lobe_maps import lobes_dataset, speed_grid
from robomill.chatter.model import CuttingModel, modes_from_xy_lists, tool_from_modes


def run_case(case: dict, *, accuracy: float, depth_max_m: float,
             progress=None) -> xr.Dataset:
    """One configured lobe case (schema ``chatter.cases[]``); ``progress(fraction)`` is called
    as the semi-discretization works through the speed grid."""
    modes = modes_from_xy_lists(case["modes"].get("x", []), case["modes"].get("y", []))
    tool = tool_from_modes(modes)
    cut = CuttingModel.from_immersion(case["teeth"], case["Kt_N_m2"], case["Kr"],
                                      case["radial_immersion"], case["milling"])
    ds = lobes_dataset(tool, cut, speed_grid(case["spindle_rpm"]), depth_max_m=depth_max_m,
                       accuracy=accuracy, progress=progress)
    ds.attrs.update({"case_" + k: v for k, v in case.items() if k != "modes"})
    ds.attrs["case_modes"] = case["modes"]
    ds.attrs["phi_st_rad"], ds.attrs["phi_ex_rad"] = cut.phi_st, cut.phi_ex
    return ds
