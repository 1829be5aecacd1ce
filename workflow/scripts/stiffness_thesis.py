"""Both stiffness models for the study's robot at the study's cuts (feed, normal, axial).
The job: robomill.pipeline.jobs.stiffness_thesis."""

from robomill.pipeline.jobs import stiffness_thesis
from robomill.pipeline.runlog import setup

stiffness_thesis.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "stiffness"))
