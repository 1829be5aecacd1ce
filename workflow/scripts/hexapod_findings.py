"""Chapter 6.3's findings (robomill.hexapod.findings), with the scorecard rows of the stage
for its "Against the source" section."""

import pandas as pd

from robomill.findings import write_findings
from robomill.hexapod.findings import hexapod_findings
from robomill.io import open_artefact
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import stage_comparisons

log = setup(snakemake.log[0], "hexapod_findings")
inp, p = snakemake.input, snakemake.params
found = hexapod_findings(open_artefact(inp.trajectory), open_artefact(inp.forces),
                         open_artefact(inp.sensitivity), pd.read_csv(inp.force_accuracy),
                         hexapod=p.hexapod)
# a reference study: its rows hold for any study (scorecard.yaml `any_study`)
found.comparisons = stage_comparisons("hexapod")
write_findings(found, snakemake.output.findings)
log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
