"""Gather the working-plane maps into maps.nc, with the Monte-Carlo workspace [Yi 2025, §2].
The job: robomill.pipeline.jobs.stiffness_maps."""

from robomill.pipeline.jobs import stiffness_maps
from robomill.pipeline.runlog import setup

stiffness_maps.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "stiffness"))
