"""Simulate the dynamometer records of the planned cuts (robomill.synth.dynamometer) from
their stored simulated state (``input.states``, rule synth_cuts), each written block by block,
one after the other in this process (one output per cut, in the order of ``params.cuts``)."""

from robomill.pipeline.runlog import Progress, setup

log = setup(snakemake.log[0], "forces_synth")

from robomill.experiment import Cut  # noqa: E402
from robomill.synth.cell import cell_from_config  # noqa: E402
from robomill.synth.cutstate import read_cut_state  # noqa: E402
from robomill.synth.dynamometer import record_length_mm, simulate_file  # noqa: E402

p = snakemake.params
config = dict(p.cfg)
cell = cell_from_config(config)
for spec, state, path in zip(p.cuts, snakemake.input.states, snakemake.output, strict=True):
    cut = Cut(**spec)
    progress = Progress(log, 1.0, f"dynamometer record of {cut.id}")
    sim = read_cut_state(state, length_mm=record_length_mm(config), variables=["force_N"])
    simulate_file(config, cut, path, sim, cell=cell, progress=progress.update)
    progress.finish(f"simulated {cut.id} -> {path}")
