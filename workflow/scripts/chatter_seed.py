"""Shagniev 2019 lobes, time-domain runs, detection and adaptive depth -> simulation.nc.
The job: robomill.pipeline.jobs.chatter_seed."""

from robomill.pipeline.jobs import chatter_seed
from robomill.pipeline.runlog import setup

chatter_seed.run(snakemake.input, snakemake.output, snakemake.params,
                 log=setup(snakemake.log[0], "chatter"))
