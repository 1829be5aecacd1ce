"""Simulate one cut's dynamometer record (robomill.synth.dynamometer), written block by block."""

from robomill.runlog import setup

log = setup(snakemake.log[0], "forces_synth")

from robomill.experiment import Cut  # noqa: E402
from robomill.synth.dynamometer import simulate_file  # noqa: E402

p = snakemake.params
config = {"synth": p.synth, "experiment": p.experiment}
cut = Cut(**p.cut)
simulate_file(config, cut, snakemake.output[0])
log.info("simulated %s -> %s", cut.id, snakemake.output[0])
