"""Positioning accuracy before and after calibration on the accuracy points (thesis ch. 1)."""

from robomill.calibration.accuracy import (
    accuracy_by_region,
    accuracy_points,
    accuracy_table,
    workspace_regions,
)
from robomill.calibration.dataset import model_from_dataset
from robomill.io import open_artefact, write_table
from robomill.io.ctrack import read_accuracy
from robomill.pipeline.runlog import setup
from robomill.study import load_study

log = setup(snakemake.log[0], "calibration_accuracy")
inp, p = snakemake.input, snakemake.params
load_study(inp.study).verify_file(p.relpath)
model = model_from_dataset(open_artefact(inp.model))
points = accuracy_points(read_accuracy(inp.accuracy), model)
points["region"] = workspace_regions(points, p.regions["reach_edges_mm"],
                                         p.regions["height_edges_mm"])
table = accuracy_table(points)
write_table(table, snakemake.output.accuracy)
write_table(accuracy_by_region(points, points["region"]), snakemake.output.regions)
write_table(points, snakemake.output.points)
log.info("accuracy:\n%s", table.to_string())
