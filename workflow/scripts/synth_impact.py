"""Simulate the impact-test hits (hammer force + tool-tip accelerations) of the virtual cell,
one after the other in this process (one output per hit, in the order of ``params.hits``)."""

from robomill.pipeline.runlog import setup
from robomill.synth.cell import cell_from_config
from robomill.synth.impact import planted_defect, write_hit

log = setup(snakemake.log[0], "synth_impact")
p = snakemake.params
cfg = dict(p.cfg)
cell = cell_from_config(cfg)
for hit, path in zip(p.hits, snakemake.output, strict=True):
    write_hit(cfg, cell, hit["direction"], hit["hit"], path)
    log.info("hit %s_%d written (planted defect: %s)", hit["direction"], hit["hit"],
             planted_defect(cfg, hit["direction"], hit["hit"]))
