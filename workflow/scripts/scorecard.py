"""Write the reproduction scorecard: source numbers beside ours, read from the artefacts."""

from robomill.io import write_table
from robomill.pipeline.runlog import setup
from robomill.pipeline.scorecard import build_scorecard

log = setup(snakemake.log[0], "scorecard")
thesis = bool(snakemake.params.thesis_study)
table = build_scorecard(snakemake.params.root, thesis_study=thesis)
if not thesis:
    log.info("not the thesis' design (cuts, spindle speed, flutes): no comparison with the "
             "thesis' numbers")
write_table(table, snakemake.output.csv)
counts = table["verdict"].value_counts().to_dict()
log.info("scorecard: %d numbers, %s", len(table), counts)
