"""Chapter 0's findings (robomill.experiment_findings): the cuts, their process and design,
with the scorecard rows of results/ingest/cuts.csv for its "Against the thesis" section."""

import pandas as pd

from robomill.experiment_findings import experiment_findings
from robomill.findings import write_findings
from robomill.pipeline.design_tables import design_summary
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import stage_comparisons

log = setup(snakemake.log[0], "ingest_findings")
p = snakemake.params
cuts = pd.read_csv(snakemake.input.cuts)
found = experiment_findings(cuts, p.experiment,
                            design=design_summary(cuts, p.experiment),
                            thesis_design=p.thesis_design,
                            thesis_study=bool(p.thesis_study))
found.comparisons = stage_comparisons("ingest", thesis_study=bool(p.thesis_study))
write_findings(found, snakemake.output.findings)
log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
