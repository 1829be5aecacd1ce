"""Chapter 3.3's findings: every number, flag and verdict it states, from the modal stage's
artefacts (robomill.modal.findings), with the scorecard rows of the stage for its
"Against the thesis" section."""

from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.io.impact import read_frf
from robomill.modal.findings import modal_findings, read_tables
from robomill.modal.ncio import join_complex
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import stage_comparisons

log = setup(snakemake.log[0], "modal_findings")
found = modal_findings(read_frf(snakemake.input.frf),
                       join_complex(open_artefact(snakemake.input.synth)),
                       read_tables(snakemake.input),
                       coherence_min=snakemake.params.coherence_min,
                       coupling_tolerance=snakemake.params.coupling_tolerance,
                       stability=snakemake.params.stability)
found.comparisons = stage_comparisons("modal", thesis_study=bool(snakemake.params.thesis_study))
write_findings(found, snakemake.output.findings)
log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
