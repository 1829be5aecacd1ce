"""Gather the per-cut force analyses: spectra.nc, peaks.csv, mean forces, harmonics and the
identified cutting coefficients (robomill.forces.study.gather_force_study).
The job: robomill.pipeline.jobs.forces_gather."""

from robomill.pipeline.jobs import forces_gather
from robomill.pipeline.runlog import setup

forces_gather.run(snakemake.input, snakemake.output, snakemake.params,
                  log=setup(snakemake.log[0], "forces_gather"))
