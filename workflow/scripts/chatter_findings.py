"""Chapters 4 and 6.1's findings: every number, flag and verdict they state, from the chatter
stage's artefacts (robomill.chatter.findings), with the scorecard rows of the stage (the
reference studies' checks: chapter 6.1's "Against the sources").
The job: robomill.pipeline.jobs.chatter_findings."""

from robomill.pipeline.jobs import chatter_findings
from robomill.pipeline.runlog import setup

chatter_findings.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "chatter_findings"))
