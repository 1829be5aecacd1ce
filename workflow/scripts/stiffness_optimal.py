"""Stiffness-optimal pose per milling height and its deformation under the end load.
The job: robomill.pipeline.jobs.stiffness_optimal."""

from robomill.pipeline.jobs import stiffness_optimal
from robomill.pipeline.runlog import setup

stiffness_optimal.run(snakemake.input, snakemake.output, snakemake.params,
                      log=setup(snakemake.log[0], "stiffness"))
