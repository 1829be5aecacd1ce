"""Write the reproduction scorecard: source numbers beside ours, read from the artefacts.
The job: robomill.pipeline.jobs.scorecard."""

from robomill.pipeline.jobs import scorecard
from robomill.pipeline.runlog import setup

scorecard.run(snakemake.input, snakemake.output, snakemake.params,
              log=setup(snakemake.log[0], "scorecard"))
