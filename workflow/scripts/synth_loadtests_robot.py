"""Synthetic raw file stiffness/<robot>.yaml (kind robot) from the virtual cell's config."""

from robomill.pipeline.runlog import setup
from robomill.synth.loadtests import write_robot_file

log = setup(snakemake.log[0], "stiffness")
write_robot_file(dict(snakemake.params.cfg), snakemake.params.robot,
                 snakemake.output.robot)
log.info("wrote %s", snakemake.output.robot)
