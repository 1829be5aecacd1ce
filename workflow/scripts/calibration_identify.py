"""Identify the calibrated model from the C-Track tables (thesis ch. 1).
The job: robomill.pipeline.jobs.calibration_identify."""

from robomill.pipeline.jobs import calibration_identify
from robomill.pipeline.runlog import setup

calibration_identify.run(snakemake.input, snakemake.output, snakemake.params,
                         log=setup(snakemake.log[0], "calibration_identify"))
