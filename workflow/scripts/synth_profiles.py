"""Simulate the stylus profiles (profiles/<cut>.csv) of the planned cuts from the virtual cell
and the cuts' stored simulated state (``input.states``, rule synth_cuts), one after the other
in this process (one output per cut, in the order of ``params.cuts``).
The job: robomill.synth.jobs.synth_profiles."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_profiles

synth_profiles.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "synth_profiles"))
