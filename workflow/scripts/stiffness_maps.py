"""Gather the working-plane maps into maps.nc, with the Monte-Carlo workspace [Yi 2025, §2]."""

import numpy as np
import xarray as xr

from robomill.io import open_artefact, write_artefact
from robomill.io.robots import read_robot_file
from robomill.pipeline.runlog import setup
from robomill.stiffness.maps import workspace_dataset

log = setup(snakemake.log[0], "stiffness")
parts = [open_artefact(p) for p in snakemake.input.maps]
by_h = {}
for ds in parts:
    by_h.setdefault(float(ds["height_mm"]), []).append(ds)
maps = xr.concat([xr.concat(sorted(v, key=lambda d: float(d["redundancy_deg"])),
                            dim="redundancy_deg") for _, v in sorted(by_h.items())],
                 dim="height_mm")
maps["height_mm"].attrs.update(units="mm", long_name="milling height H")
maps["redundancy_deg"].attrs.update(units="deg", long_name="redundancy angle about the tool axis")
robot, _ = read_robot_file(snakemake.input.robot)
m = snakemake.params.map
ws = workspace_dataset(robot, m["limits_deg"], int(m["workspace_samples"]),
                       np.random.default_rng(snakemake.params.seed), maps)
out = xr.merge([maps, ws], combine_attrs="drop_conflicts")
out.attrs["robot"] = robot.name
write_artefact(out, snakemake.output.maps, rule="stiffness_maps",
               inputs=[*snakemake.input.maps, snakemake.input.robot], config_section=m)
log.info("maps for heights %s", list(by_h))
