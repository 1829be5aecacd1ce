"""Chapter 1's findings (robomill.calibration.findings), with the scorecard rows of the
stage for its "Against the thesis" section."""

import pandas as pd

from robomill.calibration.findings import calibration_findings
from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import stage_comparisons

log = setup(snakemake.log[0], "calibration_findings")
inp = snakemake.input
found = calibration_findings(open_artefact(inp.model),
                             pd.read_csv(inp.accuracy).set_index("model"),
                             holdout_every=snakemake.params.holdout_every)
found.comparisons = stage_comparisons("calibration",
                                      thesis_study=bool(snakemake.params.thesis_study))
write_findings(found, snakemake.output.findings)
log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
