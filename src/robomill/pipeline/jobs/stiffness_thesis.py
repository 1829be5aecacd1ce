"""Both stiffness models for the study's robot at the study's cuts (feed, normal, axial).

The job of the rule script ``workflow/scripts/stiffness_thesis.py``."""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd

from robomill.beamframe import sections_from_config, slot_stiffness_table
from robomill.experiment import cut_joint_path_rad
from robomill.io import write_table
from robomill.io.cell import read_cell
from robomill.io.robots import read_robot_file
from robomill.stiffness.model import compliance_from_table
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    manifest = load_study(inputs.study)
    manifest.verify_file(params.robot_rel)
    if params.cell_relpath:
        manifest.verify_file(params.cell_relpath)
    robot, _ = read_robot_file(inputs.robot)
    cell = read_cell(inputs.cell)  # posture and tool orientation of the cell
    c = compliance_from_table(pd.read_csv(inputs.joints))
    cuts = list(manifest.cuts)  # the study's cuts and experiment (its block layout resolved)
    experiment = manifest.experiment
    L = float(experiment["cut_length_mm"])
    q = np.array([cut_joint_path_rad(robot, cut, experiment, np.array([L / 2]),
                                     tool_rotation=cell.tool_rotation, q0_rad=cell.q_home_rad)[0]
                  for cut in cuts])
    bf = params.beamframe
    sections = sections_from_config(bf["thesis_sections"], bf["E_Pa"], bf["G_Pa"])
    table = slot_stiffness_table(robot, c, sections, cuts, q)
    write_table(table, outputs.slots)
    log.info("%s", table.groupby(["model", "direction"])[["k_feed_N_m", "k_normal_N_m",
                                                           "k_axial_N_m"]].mean().to_string())
