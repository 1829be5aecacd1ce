"""Modes -> the chapter-3.3 tables: thesis peak groups, the planted-truth check (synthetic
runs) and the ±15 % mode-coupling test against the forces chapter's vibration frequency.
The job: robomill.pipeline.jobs.modal_report."""

from robomill.pipeline.jobs import modal_report
from robomill.pipeline.runlog import setup

modal_report.run(snakemake.input, snakemake.output, snakemake.params,
                 log=setup(snakemake.log[0], "modal_report"))
