"""Directional-stiffness map over the working plane for one height and redundancy angle.

The job of the rule script ``workflow/scripts/stiffness_map.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.io import write_artefact
from robomill.io.robots import read_robot_file
from robomill.stiffness.maps import map_dataset
from robomill.stiffness.model import compliance_from_table
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    load_study(inputs.study).verify_file(params.robot_rel)
    robot, _ = read_robot_file(inputs.robot)
    c = compliance_from_table(pd.read_csv(inputs.joints))
    m = params.map
    ds = map_dataset(robot, c, height_mm=params.height_mm,
                     redundancy_deg=params.redundancy_deg,
                     half_width_mm=m["half_width_mm"], step_mm=m["step_mm"],
                     q_seed_deg=m["q_seed_deg"], limits_deg=m["limits_deg"])
    log.info("%d of %d grid points reachable", int(ds["reachable"].sum()), ds["reachable"].size)
    write_artefact(ds, outputs.map, rule="stiffness_map",
                   inputs=[inputs.robot, inputs.joints], config_section=m)
