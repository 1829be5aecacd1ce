"""Write the virtual cell's planted truth (results/synthetic/truth.nc).
The job: robomill.synth.jobs.synth_truth."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_truth

synth_truth.run(snakemake.input, snakemake.output, snakemake.params,
                log=setup(snakemake.log[0], "synth_truth"))
