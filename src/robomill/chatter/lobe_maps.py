"""Lobe diagrams as datasets: the zero-order lobes beside the semi-discretization (the
Shagniev 2019 diagram) or beside the converged spectral element (the lobe cases and the thesis
robot's slots), on one speed grid."""

from __future__ import annotations

import numpy as np
import xarray as xr

from robomill.chatter.lobes_sdm import sdm_lobes
from robomill.chatter.lobes_sem import sem_lobes
from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel
from robomill.xrvars import coord

SOLVERS = ("zoa", "sem")


def speed_grid(spec: dict) -> np.ndarray:
    """The speed grid of a ``spindle_rpm: {start, stop, num}`` setting [rpm]."""
    return np.linspace(float(spec["start"]), float(spec["stop"]), int(spec["num"]))


def sdm_lobes_dataset(tool, cut: CuttingModel, rpm: np.ndarray, *, depth_max_m: float, m: int,
                      rtol: float, progress=None) -> xr.Dataset:
    """ZOA and first-order SDM lobes on one speed grid (the Shagniev 2019 diagram): a_crit_mm,
    chatter_hz over (solver = zoa, sdm; spindle_rpm), and the SDM bifurcation kind."""
    a_z, f_z = zoa_lobes(tool, cut, rpm)
    a_s, f_s, kind = sdm_lobes(tool, cut, rpm, depth_max_m=depth_max_m, m=m, rtol=rtol,
                               f_ref_hz=f_z, progress=progress)
    return xr.Dataset(
        {
            "a_crit_mm": (("solver", "spindle_rpm"), np.stack([a_z, a_s]) * 1e3,
                          {"units": "mm", "long_name": "critical axial depth of cut"}),
            "chatter_hz": (("solver", "spindle_rpm"), np.stack([f_z, f_s]),
                           {"units": "Hz", "long_name": "chatter frequency at the boundary"}),
            "sdm_bifurcation": ("spindle_rpm", kind.astype(str),
                                {"units": "1", "long_name": "SDM critical multiplier: hopf, "
                                 "flip (period doubling), fold; empty if stable to depth_max"}),
        },
        coords={"solver": ("solver", ["zoa", "sdm"], {"units": "1", "long_name":
                                                      "zoa: zero-order analytical; sdm: "
                                                      "semi-discretization"}),
                "spindle_rpm": coord("spindle_rpm", rpm, "rpm", "spindle speed")},
        attrs={"sdm_steps_per_period": int(m), "sdm_rtol": float(rtol),
               "depth_max_mm": depth_max_m * 1e3})


def lobes_dataset(tool, cut: CuttingModel, rpm: np.ndarray, *, depth_max_m: float,
                  accuracy: float, progress=None) -> xr.Dataset:
    """ZOA and converged spectral-element lobes on one speed grid: ``a_crit_mm``,
    ``chatter_hz`` over (solver = zoa, sem; spindle_rpm); beside them the SEM's estimated
    discretization error ``a_crit_error_mm`` (refined per speed to ``accuracy``), its
    ``bifurcation`` kind and the ``collocation_order`` used
    (:func:`robomill.chatter.lobes_sem.sem_lobes`)."""
    a_z, f_z = zoa_lobes(tool, cut, rpm)
    r = sem_lobes(tool, cut, rpm, depth_max_m=depth_max_m, accuracy=accuracy, f_ref_hz=f_z,
                  progress=progress)
    return xr.Dataset(
        {
            "a_crit_mm": (("solver", "spindle_rpm"), np.stack([a_z, r["a_crit_m"]]) * 1e3,
                          {"units": "mm", "long_name": "critical axial depth of cut"}),
            "a_crit_error_mm": ("spindle_rpm", r["error_m"] * 1e3,
                                {"units": "mm", "long_name": "estimated discretization error "
                                 "of the sem critical depth: |a(p) - a(p-2)| + root tolerance"}),
            "chatter_hz": (("solver", "spindle_rpm"), np.stack([f_z, r["chatter_hz"]]),
                           {"units": "Hz", "long_name": "chatter frequency at the boundary"}),
            "bifurcation": ("spindle_rpm", r["kind"].astype(str),
                            {"units": "1", "long_name": "sem critical multiplier: hopf, "
                             "flip (period doubling), fold; empty if stable to depth_max"}),
            "collocation_order": ("spindle_rpm", r["p"].astype(np.int64),
                                  {"units": "1", "long_name": "sem polynomial order p per "
                                   "element at which the accuracy was met"}),
        },
        coords={"solver": ("solver", list(SOLVERS), {"units": "1", "long_name":
                                                     "zoa: zero-order analytical; sem: "
                                                     "spectral element (Chebyshev "
                                                     "collocation)"}),
                "spindle_rpm": coord("spindle_rpm", rpm, "rpm", "spindle speed")},
        attrs={"accuracy": float(accuracy), "depth_max_mm": depth_max_m * 1e3,
               "worst_relative_error": float(np.nanmax(r["error_m"] / r["a_crit_m"]))
               if np.isfinite(r["a_crit_m"]).any() else float("nan")})
