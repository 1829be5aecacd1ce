"""One configured lobe case -> results/chatter/cases/<name>.nc (ZOA and converged SEM).
The job: robomill.pipeline.jobs.chatter_case."""

from robomill.pipeline.jobs import chatter_case
from robomill.pipeline.runlog import setup

chatter_case.run(snakemake.input, snakemake.output, snakemake.params,
                 log=setup(snakemake.log[0], "chatter"))
