"""Integrate every planned cut of the virtual cell once (robomill.synth.cutstate) and store
its simulated state, one file per cut, one cut after the other in this process (the set-up of
the first cut, imports and compiled kernels, is paid once).
The job: robomill.synth.jobs.synth_cuts."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_cuts

synth_cuts.run(snakemake.input, snakemake.output, snakemake.params,
               log=setup(snakemake.log[0], "synth_cuts"))
