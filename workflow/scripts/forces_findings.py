"""Chapter 3.1's findings on the dominant low-frequency peak (robomill.forces.findings), with
the scorecard rows of the stage for its "Against the thesis" section."""

import pandas as pd

from robomill.findings import write_findings
from robomill.forces.findings import forces_findings
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import stage_comparisons

log = setup(snakemake.log[0], "forces_findings")
inp, p = snakemake.input, snakemake.params
modes = pd.read_csv(inp.modes) if "modes" in inp.keys() else None
found = forces_findings(pd.read_csv(inp.peaks), modes, mode_match_hz=p.mode_match_hz,
                        band_hz=p.band_hz, prominence_db=p.prominence_db)
found.comparisons = stage_comparisons("forces", thesis_study=bool(p.thesis_study))
write_findings(found, snakemake.output.findings)
log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
