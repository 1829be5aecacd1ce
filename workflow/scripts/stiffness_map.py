"""Directional-stiffness map over the working plane for one height and redundancy angle."""

import pandas as pd

from robomill.io import write_artefact
from robomill.io.robots import read_robot_file
from robomill.pipeline.runlog import setup
from robomill.stiffness.maps import map_dataset
from robomill.stiffness.model import compliance_from_table
from robomill.study import load_study

log = setup(snakemake.log[0], "stiffness")
load_study(snakemake.input.study).verify_file(snakemake.params.robot_rel)
robot, _ = read_robot_file(snakemake.input.robot)
c = compliance_from_table(pd.read_csv(snakemake.input.joints))
m = snakemake.params.map
ds = map_dataset(robot, c, height_mm=snakemake.params.height_mm,
                 redundancy_deg=snakemake.params.redundancy_deg,
                 half_width_mm=m["half_width_mm"], step_mm=m["step_mm"],
                 q_seed_deg=m["q_seed_deg"], limits_deg=m["limits_deg"])
log.info("%d of %d grid points reachable", int(ds["reachable"].sum()), ds["reachable"].size)
write_artefact(ds, snakemake.output.map, rule="stiffness_map",
               inputs=[snakemake.input.robot, snakemake.input.joints], config_section=m)
