"""Gather the areal scans: ISO 25178-2 parameters per scan with its instrument's statements,
the spectra, and stylus against scan for cuts measured both ways
(robomill.surface.areal_study.gather_areal).
The job: robomill.pipeline.jobs.surface_areal_gather."""

from robomill.pipeline.jobs import surface_areal_gather
from robomill.pipeline.runlog import setup

surface_areal_gather.run(snakemake.input, snakemake.output, snakemake.params,
                         log=setup(snakemake.log[0], "surface_areal_gather"))
