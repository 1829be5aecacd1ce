"""Rybak n.d.: the programme's inverse dynamics and replay, and the vertical move with a force
error → trajectory.nc and forces.nc.
The job: robomill.pipeline.jobs.hexapod_dynamics."""

from robomill.pipeline.jobs import hexapod_dynamics
from robomill.pipeline.runlog import setup

hexapod_dynamics.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "hexapod"), rule=snakemake.rule)
