"""Simulate one cut's dynamometer record (robomill.synth.dynamometer), written block by block."""

from robomill.runlog import Progress, setup

log = setup(snakemake.log[0], "forces_synth")

from robomill.experiment import Cut  # noqa: E402
from robomill.synth.dynamometer import simulate_file  # noqa: E402

p = snakemake.params
config = {"synth": p.synth, "experiment": p.experiment}
cut = Cut(**p.cut)
progress = Progress(log, 1.0, f"dynamometer record of {cut.id}")
simulate_file(config, cut, snakemake.output[0], progress=progress.update)
progress.finish(f"simulated {cut.id} -> {snakemake.output[0]}")
