"""Chapter 2's findings (robomill.surface.findings), with the scorecard rows of the stage for
its "Against the thesis" section.
The job: robomill.pipeline.jobs.surface_findings."""

from robomill.pipeline.jobs import surface_findings
from robomill.pipeline.runlog import setup

surface_findings.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "surface_findings"))
