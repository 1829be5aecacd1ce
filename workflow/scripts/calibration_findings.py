"""Chapter 1's findings (robomill.calibration.findings), with the scorecard rows of the
stage for its "Against the thesis" section.
The job: robomill.pipeline.jobs.calibration_findings."""

from robomill.pipeline.jobs import calibration_findings
from robomill.pipeline.runlog import setup

calibration_findings.run(snakemake.input, snakemake.output, snakemake.params,
                         log=setup(snakemake.log[0], "calibration_findings"))
