"""Gather the working-plane maps into maps.nc, with the Monte-Carlo workspace [Yi 2025, §2].

The job of the rule script ``workflow/scripts/stiffness_maps.py``."""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr

from robomill.io import open_artefact, write_artefact
from robomill.io.robots import read_robot_file
from robomill.stiffness.maps import workspace_dataset


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    parts = [open_artefact(p) for p in inputs.maps]
    by_h = {}
    for ds in parts:
        by_h.setdefault(float(ds["height_mm"]), []).append(ds)
    maps = xr.concat([xr.concat(sorted(v, key=lambda d: float(d["redundancy_deg"])),
                                dim="redundancy_deg") for _, v in sorted(by_h.items())],
                     dim="height_mm")
    maps["height_mm"].attrs.update(units="mm", long_name="milling height H")
    maps["redundancy_deg"].attrs.update(units="deg",
                                        long_name="redundancy angle about the tool axis")
    robot, _ = read_robot_file(inputs.robot)
    m = params.map
    ws = workspace_dataset(robot, m["limits_deg"], int(m["workspace_samples"]),
                           np.random.default_rng(params.seed), maps)
    out = xr.merge([maps, ws], combine_attrs="drop_conflicts")
    out.attrs["robot"] = robot.name
    write_artefact(out, outputs.maps, rule="stiffness_maps",
                   inputs=[*inputs.maps, inputs.robot], config_section=m)
    log.info("maps for heights %s", list(by_h))
