"""Synthetic runs: planted (truth.nc) vs recovered waviness and roughness RMS of every cut.
The job: robomill.pipeline.jobs.surface_recovery."""

from robomill.pipeline.jobs import surface_recovery
from robomill.pipeline.runlog import setup

surface_recovery.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "surface_recovery"))
