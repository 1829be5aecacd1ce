"""Cai 2015 beam-frame model: precessing pneumatic wheel, δ_sum(t) and σ(t).
The job: robomill.pipeline.jobs.stiffness_beamframe."""

from robomill.pipeline.jobs import stiffness_beamframe
from robomill.pipeline.runlog import setup

stiffness_beamframe.run(snakemake.input, snakemake.output, snakemake.params,
                        log=setup(snakemake.log[0], "stiffness"))
