"""The next cuts from what was measured: candidates, the chosen cuts, the Pareto
front, the study's own cuts beside the plan, and the next experiment's manifest and config.
The job: robomill.pipeline.jobs.plan_make."""

from robomill.pipeline.jobs import plan_make
from robomill.pipeline.runlog import setup

plan_make.run(snakemake.input, snakemake.output, snakemake.params,
              log=setup(snakemake.log[0], "plan"))
