"""Simulate one stylus profile (profiles/<cut>.csv) from the virtual cell."""

from robomill.experiment import Cut
from robomill.runlog import setup
from robomill.synth.cell import cell_from_config
from robomill.synth.profilometer import simulate_profile

log = setup(snakemake.log[0], "surface_synth_profile")
p = snakemake.params
cfg = {"synth": p.synth, "experiment": p.experiment}
cut = Cut(**p.cut)
simulate_profile(cfg, cut, snakemake.output[0], cell=cell_from_config(cfg))
log.info("profile of %s (feed %g mm/s) written to %s", cut.id, cut.feed_mm_s, snakemake.output[0])
