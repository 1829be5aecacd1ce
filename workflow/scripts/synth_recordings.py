"""Simulate the microphone's and the spindle accelerometer's recordings of the planned cuts
(robomill.synth.recordings), and each one's air pass (``pass: air``: the same path without
material), from the cuts' stored simulated state (rule synth_cuts: the ``air`` pass of the same
file), one after the other in this process (one output per entry of ``params.files``, in
order; consecutive entries of one cut and pass read its state once).
The job: robomill.synth.jobs.synth_recordings."""

from robomill.pipeline.runlog import setup
from robomill.synth.jobs import synth_recordings

synth_recordings.run(snakemake.input, snakemake.output, snakemake.params,
                     log=setup(snakemake.log[0], "synth_recordings"))
