"""Tracker runs: validate, re-order in space, spectrum, gear frequencies, gear-matched peaks
(robomill.pipeline.jobs.straightness_run). One run, or every run of the virtual cell in one job:
``params.runs`` and the outputs in the same order."""

from robomill.pipeline.jobs.straightness_run import analyse_tracker_files
from robomill.pipeline.runlog import setup


def items(paths):
    """A rule's output or input as a list (one path is a string)."""
    return [paths] if isinstance(paths, str) else list(paths)


out, p = snakemake.output, snakemake.params
analyse_tracker_files(snakemake.input.study, snakemake.input.cell, p.runs,
                      items(snakemake.input.raw), items(out.nc), items(out.peaks),
                      items(out.gears), settings=p.settings, cell_relpath=p.cell_relpath,
                      log=setup(snakemake.log[0], "straightness_run"))
