"""Chapter 4's findings: every number, flag and verdict it states, from the chatter stage's
artefacts (robomill.chatter.findings), with the scorecard rows of the stage for its
"Against the thesis" section."""

import pandas as pd

from robomill.chatter.findings import chatter_findings, load_cases
from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import stage_comparisons

log = setup(snakemake.log[0], "chatter_findings")
found = chatter_findings(load_cases(snakemake.input.cases, open_artefact),
                         open_artefact(snakemake.input.simulation),
                         open_artefact(snakemake.input.lobes),
                         pd.read_csv(snakemake.input.recommendations),
                         safety_fraction=snakemake.params.safety_fraction)
found.comparisons = stage_comparisons("chatter",
                                      thesis_study=bool(snakemake.params.thesis_study))
write_findings(found, snakemake.output.findings)
log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
