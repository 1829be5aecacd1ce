"""Gather the sensitivity shards into results/hexapod/sensitivity.nc.
The job: robomill.pipeline.jobs.hexapod_sensitivity."""

from robomill.pipeline.jobs import hexapod_sensitivity
from robomill.pipeline.runlog import setup

hexapod_sensitivity.run(snakemake.input, snakemake.output, snakemake.params,
                        log=setup(snakemake.log[0], "hexapod"), rule=snakemake.rule)
