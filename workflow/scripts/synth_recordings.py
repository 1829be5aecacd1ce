"""Simulate the microphone's and the spindle accelerometer's recordings of the planned cuts
(robomill.synth.recordings), one after the other in this process (one output per entry of
``params.files``, in order), and each one's air pass (``pass: air``: the same path without
material); the cut of consecutive entries is integrated once."""

from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "synth_recordings")

from robomill.experiment import Cut  # noqa: E402
from robomill.synth.cell import cell_from_config  # noqa: E402
from robomill.synth.recordings import simulate_air_pass_file, simulate_file  # noqa: E402

config = dict(snakemake.params.cfg)
cell = cell_from_config(config)
for spec, path in zip(snakemake.params.files, snakemake.output, strict=True):
    cut = Cut(**spec["cut"])
    air = spec.get("pass") == "air"
    (simulate_air_pass_file if air else simulate_file)(config, cut, path, spec["kind"], cell=cell)
    log.info("simulated the %s recording of %s%s -> %s", spec["kind"], cut.id,
             " (air pass)" if air else "", path)
