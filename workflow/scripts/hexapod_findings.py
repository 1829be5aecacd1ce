"""Chapter 6.3's findings (robomill.hexapod.findings), with the scorecard rows of the stage
for its "Against the source" section.
The job: robomill.pipeline.jobs.hexapod_findings."""

from robomill.pipeline.jobs import hexapod_findings
from robomill.pipeline.runlog import setup

hexapod_findings.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "hexapod_findings"))
