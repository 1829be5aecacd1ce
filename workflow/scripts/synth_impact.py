"""Simulate the impact-test hits (hammer force + tool-tip accelerations) of the virtual cell,
one after the other in this process (one output per hit, in the order of ``params.hits``).
The job: robomill.synth.jobs.synth_impact."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_impact

synth_impact.run(snakemake.input, snakemake.output, snakemake.params,
                 log=setup(snakemake.log[0], "synth_impact"))
