"""Write a configuration's cell: section as cell.yaml (robomill.io.cell): synthetic mode's raw
folder, or results/ingest/cell.yaml for a raw folder without a cell file."""

from robomill.io.cell import write_cell
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "cell_write")
write_cell(snakemake.params.cell, snakemake.output[0])
log.info("wrote %s", snakemake.output[0])
