"""Simulate the laser-tracker runs (tracker/<dir>_f<feed>.csv) of the virtual cell, a loaded
run from its cut's stored simulated state (rule synth_cuts), one after the other in this
process (one output per run, in the order of ``params.runs``).
The job: robomill.synth.jobs.synth_tracker."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_tracker

synth_tracker.run(snakemake.input, snakemake.output, snakemake.params,
                  log=setup(snakemake.log[0], "synth_tracker"))
