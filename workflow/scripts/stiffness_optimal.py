"""Stiffness-optimal pose per milling height and its deformation under the end load."""

import numpy as np
import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.io.robots import read_robot_file
from robomill.pipeline.runlog import setup
from robomill.stiffness.model import compliance_from_table
from robomill.stiffness.poses import optimal_poses

log = setup(snakemake.log[0], "stiffness")
robot, _ = read_robot_file(snakemake.input.robot)
c = compliance_from_table(pd.read_csv(snakemake.input.joints))
m = snakemake.params.map
table = optimal_poses(robot, c, open_artefact(snakemake.input.maps), load_kg=m["load_kg"],
                      random_poses=int(m["random_poses"]),
                      rng=np.random.default_rng(snakemake.params.seed))
table.insert(0, "robot", robot.name)
write_table(table, snakemake.output.poses)
for _, r in table[table["pose"] == "optimal"].iterrows():
    log.info("H = %.0f mm: optimum at (%.0f, %.0f) mm, %.0f deg, deformation %.1f um",
             r["height_mm"], r["x_mm"], r["y_mm"], r["redundancy_deg"], r["deformation_um"])
