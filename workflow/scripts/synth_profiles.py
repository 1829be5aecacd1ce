"""Simulate the stylus profiles (profiles/<cut>.csv) of the planned cuts from the virtual cell
and the cuts' stored simulated state (``input.states``, rule synth_cuts), one after the other
in this process (one output per cut, in the order of ``params.cuts``)."""

from robomill.experiment import Cut
from robomill.pipeline.runlog import setup
from robomill.synth.cell import cell_from_config
from robomill.synth.cutstate import read_cut_state
from robomill.synth.profilometer import simulate_profile, trace_end_mm

log = setup(snakemake.log[0], "synth_profiles")
p = snakemake.params
cfg = dict(p.cfg)
cell = cell_from_config(cfg)
for spec, state, path in zip(p.cuts, snakemake.input.states, snakemake.output, strict=True):
    cut = Cut(**spec)
    sim = read_cut_state(state, length_mm=trace_end_mm(cfg), variables=["deflection_m"])
    simulate_profile(cfg, cut, path, sim, cell=cell)
    log.info("profile of %s (feed %g mm/s) written to %s", cut.id, cut.feed_mm_s, path)
