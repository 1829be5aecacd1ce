"""Both stiffness models for the thesis robot at the thesis cuts (feed, normal, axial)."""

import numpy as np
import pandas as pd

from robomill.beamframe import sections_from_config, slot_stiffness_table
from robomill.experiment import Cut
from robomill.io import write_table
from robomill.io.manifest import load_manifest
from robomill.io.robots import read_robot_file
from robomill.runlog import setup
from robomill.stiffness import compliance_from_table
from robomill.synth.cell import cell_from_config

log = setup(snakemake.log[0], "stiffness")
load_manifest(snakemake.input.manifest).verify_file(snakemake.params.robot_rel)
robot, _ = read_robot_file(snakemake.input.robot)
c = compliance_from_table(pd.read_csv(snakemake.input.joints))
cell = cell_from_config({"synth": snakemake.params.synth,
                         "experiment": snakemake.params.experiment})
cell.robot = robot  # geometry of the cell, robot from the robot file
cuts = [Cut(**d) for d in snakemake.params.cuts]
L = float(snakemake.params.experiment["cut_length_mm"])
q = np.array([cell.joint_path_rad(cut, np.array([L / 2]))[0] for cut in cuts])
bf = snakemake.params.beamframe
sections = sections_from_config(bf["thesis_sections"], bf["E_Pa"], bf["G_Pa"])
table = slot_stiffness_table(robot, c, sections, cuts, q)
write_table(table, snakemake.output.slots)
log.info("%s", table.groupby(["model", "direction"])[["k_feed_N_m", "k_normal_N_m",
                                                       "k_axial_N_m"]].mean().to_string())
