"""Simulate one C-Track table of the virtual robot (results/synthetic/raw/ctrack/<table>.csv).
The job: robomill.synth.jobs.synth_ctrack."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_ctrack

synth_ctrack.run(snakemake.input, snakemake.output, snakemake.params,
                 log=setup(snakemake.log[0], "synth_ctrack"))
