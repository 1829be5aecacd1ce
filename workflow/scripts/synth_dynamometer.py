"""Simulate the dynamometer records of the planned cuts (robomill.synth.dynamometer) from
their stored simulated state (``input.states``, rule synth_cuts), each written block by block,
one after the other in this process (one output per cut, in the order of ``params.cuts``).
The job: robomill.synth.jobs.synth_dynamometer."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_dynamometer

synth_dynamometer.run(snakemake.input, snakemake.output, snakemake.params,
                      log=setup(snakemake.log[0], "forces_synth"))
