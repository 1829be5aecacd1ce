"""Joint-model stiffness of the cell's robot at the middle of every cut (any design).
The job: robomill.pipeline.jobs.stiffness_cuts."""

from robomill.pipeline.jobs import stiffness_cuts
from robomill.pipeline.runlog import setup

stiffness_cuts.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "stiffness"))
