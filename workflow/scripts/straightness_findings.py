"""Chapter 3.2's findings (robomill.straightness.findings), with the scorecard rows of the
stage for its "Against the thesis" section.
The job: robomill.pipeline.jobs.straightness_findings."""

from robomill.pipeline.jobs import straightness_findings
from robomill.pipeline.runlog import setup

straightness_findings.run(snakemake.input, snakemake.output, snakemake.params,
                          log=setup(snakemake.log[0], "straightness_findings"))
