"""Positioning accuracy before and after calibration on the accuracy points (thesis ch. 1).

The job of the rule script ``workflow/scripts/calibration_accuracy.py``."""

from __future__ import annotations

import logging

from robomill.calibration.accuracy import (
    accuracy_by_region,
    accuracy_points,
    accuracy_table,
    workspace_regions,
)
from robomill.calibration.dataset import model_from_dataset
from robomill.io import open_artefact, write_table
from robomill.io.ctrack import read_accuracy
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    load_study(inputs.study).verify_file(params.relpath)
    model = model_from_dataset(open_artefact(inputs.model))
    points = accuracy_points(read_accuracy(inputs.accuracy), model)
    points["region"] = workspace_regions(points, params.regions["reach_edges_mm"],
                                         params.regions["height_edges_mm"])
    table = accuracy_table(points)
    write_table(table, outputs.accuracy)
    write_table(accuracy_by_region(points, points["region"]), outputs.regions)
    write_table(points, outputs.points)
    log.info("accuracy:\n%s", table.to_string())
