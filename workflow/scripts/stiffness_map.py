"""Directional-stiffness map over the working plane for one height and redundancy angle.
The job: robomill.pipeline.jobs.stiffness_map."""

from robomill.pipeline.jobs import stiffness_map
from robomill.pipeline.runlog import setup

stiffness_map.run(snakemake.input, snakemake.output, snakemake.params,
                  log=setup(snakemake.log[0], "stiffness"))
