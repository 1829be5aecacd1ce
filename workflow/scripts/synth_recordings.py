"""Simulate the microphone's and the spindle accelerometer's recordings of the planned cuts
(robomill.synth.recordings), one after the other in this process (one output per entry of
``params.files``, in order); the cut of consecutive entries is integrated once."""

from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "synth_recordings")

from robomill.experiment import Cut  # noqa: E402
from robomill.synth.cell import cell_from_config  # noqa: E402
from robomill.synth.recordings import simulate_file  # noqa: E402

config = dict(snakemake.params.cfg)
cell = cell_from_config(config)
for spec, path in zip(snakemake.params.files, snakemake.output, strict=True):
    cut = Cut(**spec["cut"])
    simulate_file(config, cut, path, spec["kind"], cell=cell)
    log.info("simulated the %s recording of %s -> %s", spec["kind"], cut.id, path)
