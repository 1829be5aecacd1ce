"""Chapter 3.3's findings: every number, flag and verdict it states, from the modal stage's
artefacts (robomill.modal.findings), with the scorecard rows of the stage for its
"Against the thesis" section.
The job: robomill.pipeline.jobs.modal_findings."""

from robomill.pipeline.jobs import modal_findings
from robomill.pipeline.runlog import setup

modal_findings.run(snakemake.input, snakemake.output, snakemake.params,
                   log=setup(snakemake.log[0], "modal_findings"))
