"""Stiffness-optimal pose per milling height and its deformation under the end load.

The job of the rule script ``workflow/scripts/stiffness_optimal.py``."""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd

from robomill.io import open_artefact, write_table
from robomill.io.robots import read_robot_file
from robomill.stiffness.model import compliance_from_table
from robomill.stiffness.poses import optimal_poses


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    robot, _ = read_robot_file(inputs.robot)
    c = compliance_from_table(pd.read_csv(inputs.joints))
    m = params.map
    table = optimal_poses(robot, c, open_artefact(inputs.maps), load_kg=m["load_kg"],
                          random_poses=int(m["random_poses"]),
                          rng=np.random.default_rng(params.seed))
    table.insert(0, "robot", robot.name)
    write_table(table, outputs.poses)
    for _, r in table[table["pose"] == "optimal"].iterrows():
        log.info("H = %.0f mm: optimum at (%.0f, %.0f) mm, %.0f deg, deformation %.1f um",
                 r["height_mm"], r["x_mm"], r["y_mm"], r["redundancy_deg"], r["deformation_um"])
