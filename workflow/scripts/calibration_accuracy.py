"""Positioning accuracy before and after calibration on the accuracy points (thesis ch. 1).
The job: robomill.pipeline.jobs.calibration_accuracy."""

from robomill.pipeline.jobs import calibration_accuracy
from robomill.pipeline.runlog import setup

calibration_accuracy.run(snakemake.input, snakemake.output, snakemake.params,
                         log=setup(snakemake.log[0], "calibration_accuracy"))
