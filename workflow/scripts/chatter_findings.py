"""Chapters 4 and 6.1's findings: every number, flag and verdict they state, from the chatter
stage's artefacts (robomill.chatter.findings), with the scorecard rows of the stage (the
reference studies' checks: chapter 6.1's "Against the sources")."""

import pandas as pd

from robomill.chatter.findings import chatter_findings, load_cases
from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import stage_comparisons

log = setup(snakemake.log[0], "chatter_findings")
inp = snakemake.input
found = chatter_findings(load_cases(inp.cases, open_artefact),
                         open_artefact(inp.simulation),
                         open_artefact(inp.lobes) if "lobes" in inp.keys() else None,
                         pd.read_csv(inp.recommendations)
                         if "recommendations" in inp.keys() else None,
                         safety_fraction=snakemake.params.safety_fraction,
                         thesis_study=bool(snakemake.params.thesis_study))
found.comparisons = stage_comparisons("chatter",
                                      thesis_study=bool(snakemake.params.thesis_study))
write_findings(found, snakemake.output.findings)
log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
