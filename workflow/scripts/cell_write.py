"""Write a configuration's cell: section as cell.yaml (robomill.io.cell): synthetic mode's raw
folder, or results/ingest/cell.yaml for a raw folder without a cell file.
The job: robomill.pipeline.jobs.cell_write."""

from robomill.pipeline.jobs import cell_write
from robomill.pipeline.runlog import setup

cell_write.run(snakemake.input, snakemake.output, snakemake.params,
               log=setup(snakemake.log[0], "cell_write"))
