"""Gather the per-cut analyses: Tables 2.1/2.2, thesis comparison, peaks with mechanism,
metrics, spectra and profiles of every cut (see robomill.surface.gather_surface).
The job: robomill.pipeline.jobs.surface_gather."""

from robomill.pipeline.jobs import surface_gather
from robomill.pipeline.runlog import setup

surface_gather.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "surface_gather"))
