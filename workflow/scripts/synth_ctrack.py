"""Simulate one C-Track table of the virtual robot (results/synthetic/raw/ctrack/<table>.csv)."""

from robomill.pipeline.runlog import setup
from robomill.synth.cell import cell_from_config
from robomill.synth.ctrack import write_table

log = setup(snakemake.log[0], "synth_ctrack")
cfg = dict(snakemake.params.cfg)
write_table(cfg, cell_from_config(cfg), snakemake.params.table, snakemake.output[0])
log.info("wrote %s", snakemake.output[0])
