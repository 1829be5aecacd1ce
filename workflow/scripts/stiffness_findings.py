"""Chapter 5's findings (robomill.stiffness.findings), with the scorecard rows of the stage
for its "Against the source" section.
The job: robomill.pipeline.jobs.stiffness_findings."""

from robomill.pipeline.jobs import stiffness_findings
from robomill.pipeline.runlog import setup

stiffness_findings.run(snakemake.input, snakemake.output, snakemake.params,
                       log=setup(snakemake.log[0], "stiffness_findings"))
