"""Chatter verdicts of every cut's force record and every sound/vibration recording
(robomill.chatter.recordings), their chatter lines tested on the cuts' air passes:
results/chatter/verdicts.csv and the pooled spectrograms.
The job: robomill.pipeline.jobs.chatter_verdicts."""

from robomill.pipeline.jobs import chatter_verdicts
from robomill.pipeline.runlog import setup

chatter_verdicts.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "chatter_verdicts"))
