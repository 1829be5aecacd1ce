"""Simulate the dynamometer records of the planned cuts (robomill.synth.dynamometer), each
written block by block, one after the other in this process (one output per cut, in the
order of ``params.cuts``)."""

from robomill.pipeline.runlog import Progress, setup

log = setup(snakemake.log[0], "forces_synth")

from robomill.experiment import Cut  # noqa: E402
from robomill.synth.dynamometer import simulate_file  # noqa: E402

p = snakemake.params
config = dict(p.cfg)
for spec, path in zip(p.cuts, snakemake.output, strict=True):
    cut = Cut(**spec)
    progress = Progress(log, 1.0, f"dynamometer record of {cut.id}")
    simulate_file(config, cut, path, progress=progress.update)
    progress.finish(f"simulated {cut.id} -> {path}")
