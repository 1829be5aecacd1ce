"""Simulate one impact-test hit (hammer force + tool-tip accelerations) of the virtual cell."""

from robomill.pipeline.runlog import setup
from robomill.synth.cell import cell_from_config
from robomill.synth.impact import planted_defect, write_hit

log = setup(snakemake.log[0], "synth_impact")
p = snakemake.params
cfg = dict(p.cfg)
write_hit(cfg, cell_from_config(cfg), p.direction, p.hit, snakemake.output[0])
log.info("hit %s_%d written (planted defect: %s)", p.direction, p.hit,
         planted_defect(cfg, p.direction, p.hit))
