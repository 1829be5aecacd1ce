"""Joint-model stiffness of the cell's robot at the middle of every cut (any design).

The job of the rule script ``workflow/scripts/stiffness_cuts.py``."""

from __future__ import annotations

import logging

import numpy as np
import pandas as pd

from robomill.experiment import cut_joint_path_rad
from robomill.io import write_table
from robomill.io.cell import read_cell
from robomill.stiffness.cuts import cut_stiffness_table
from robomill.stiffness.model import compliance_from_table
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    manifest = load_study(inputs.study)
    if params.cell_relpath:
        manifest.verify_file(params.cell_relpath)
    cell = read_cell(inputs.cell)
    c = compliance_from_table(pd.read_csv(inputs.joints))
    cuts = list(manifest.cuts)  # the study's cuts and experiment (its block layout resolved)
    experiment = manifest.experiment
    L = float(experiment["cut_length_mm"])
    q = np.array([cut_joint_path_rad(cell.robot, cut, experiment, np.array([L / 2]),
                                     tool_rotation=cell.tool_rotation, q0_rad=cell.q_home_rad)[0]
                  for cut in cuts])
    table = cut_stiffness_table(cell.robot, c, cuts, q)
    write_table(table, outputs.cuts)
    log.info("%s", table.to_string())
