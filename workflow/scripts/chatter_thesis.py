"""The study's robot: lobes for each slot of the study's cuts, mode coupling, recommendations.
The job: robomill.pipeline.jobs.chatter_thesis."""

from robomill.pipeline.jobs import chatter_thesis
from robomill.pipeline.runlog import setup

chatter_thesis.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "chatter"))
