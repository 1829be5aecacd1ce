"""Chapter 3.1's findings (robomill.forces.findings): the dominant peak and its verdict
against the modes, the records, the kinematic peak and its sanity flag, the force levels and
the cutting coefficients, with the scorecard rows of the stage for its "Against the thesis"
section.
The job: robomill.pipeline.jobs.forces_findings."""

from robomill.pipeline.jobs import forces_findings
from robomill.pipeline.runlog import setup

forces_findings.run(snakemake.input, snakemake.output, snakemake.params,
                    log=setup(snakemake.log[0], "forces_findings"))
