"""Tracker runs: validate, re-order in space, spectrum, gear frequencies, gear-matched peaks
(robomill.pipeline.jobs.straightness_run). One run, or every run of the virtual cell in one job:
``params.runs`` and the outputs in the same order."""

from robomill.pipeline.jobs.straightness_run import analyse_tracker_files
from robomill.pipeline.runlog import setup

analyse_tracker_files(snakemake.input.study, snakemake.input.cell, snakemake.params.runs,
                      snakemake.input.raw, snakemake.output.nc, snakemake.output.peaks,
                      snakemake.output.gears, settings=snakemake.params.settings,
                      cell_relpath=snakemake.params.cell_relpath,
                      log=setup(snakemake.log[0], "straightness_run"))
