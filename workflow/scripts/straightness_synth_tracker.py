"""Simulate one laser-tracker run (tracker/<dir>_f<feed>.csv) from the virtual cell."""

from robomill.pipeline.runlog import setup
from robomill.synth.cell import cell_from_config
from robomill.synth.plan import synthetic_cuts
from robomill.synth.tracker import simulate_run, write_run

log = setup(snakemake.log[0], "straightness_synth_tracker")
p = snakemake.params
cfg = dict(p.cfg)
cell = cell_from_config(cfg)
cut = next(c for c in synthetic_cuts(cfg) if c.id == p.cut)
df = simulate_run(cfg, cell, p.direction, float(p.feed_mm_s), cut)
write_run(df, snakemake.output[0])
log.info("tracker run %s_f%g along %s: %d samples, %.2f s", p.direction, p.feed_mm_s, cut.id,
         len(df), df["t_s"].iloc[-1])
