"""Synthetic raw file stiffness/load_tests_<robot>.csv (kind stiffness): simulated load tests.
The job: robomill.synth.jobs.synth_loadtests."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_loadtests

synth_loadtests.run(snakemake.input, snakemake.output, snakemake.params,
                    log=setup(snakemake.log[0], "stiffness"))
