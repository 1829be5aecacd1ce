"""Chapter 0's findings (robomill.experiment_findings): the cuts, their process and design,
with the scorecard rows of results/ingest/cuts.csv for its "Against the thesis" section.
The job: robomill.pipeline.jobs.ingest_findings."""

from robomill.pipeline.jobs import ingest_findings
from robomill.pipeline.runlog import setup

ingest_findings.run(snakemake.input, snakemake.output, snakemake.params,
                    log=setup(snakemake.log[0], "ingest_findings"))
