"""Synthetic raw file stiffness/load_tests_<robot>.csv (kind stiffness): simulated load tests."""

from robomill.pipeline.runlog import setup
from robomill.synth.loadtests import write_load_tests

log = setup(snakemake.log[0], "stiffness")
write_load_tests(dict(snakemake.params.cfg), snakemake.params.robot,
                 snakemake.output.tests)
log.info("wrote %s", snakemake.output.tests)
