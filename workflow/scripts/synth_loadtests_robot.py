"""Synthetic raw file stiffness/<robot>.yaml (kind robot) from the virtual cell's config.
The job: robomill.synth.jobs.synth_loadtests_robot."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_loadtests_robot

synth_loadtests_robot.run(snakemake.input, snakemake.output, snakemake.params,
                          log=setup(snakemake.log[0], "stiffness"))
