"""One shard of the sensitivity study: one actuator in error, every error size.
The job: robomill.pipeline.jobs.hexapod_sensitivity_shard."""

from robomill.pipeline.jobs import hexapod_sensitivity_shard
from robomill.pipeline.runlog import setup

hexapod_sensitivity_shard.run(snakemake.input, snakemake.output, snakemake.params,
                              log=setup(snakemake.log[0], "hexapod"), rule=snakemake.rule)
