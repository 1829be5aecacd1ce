"""Ours beside the parameters a profile file states about itself (one row per parameter; see
robomill.surface.reference.reference_comparison).
The job: robomill.pipeline.jobs.surface_reference."""

from robomill.pipeline.jobs import surface_reference
from robomill.pipeline.runlog import setup

surface_reference.run(snakemake.input, snakemake.output, snakemake.params,
                      log=setup(snakemake.log[0], "surface_reference"))
