"""Joint-stiffness identification of one robot from its load tests [Yi 2025, §3].
The job: robomill.pipeline.jobs.stiffness_identify."""

from robomill.pipeline.jobs import stiffness_identify
from robomill.pipeline.runlog import setup

stiffness_identify.run(snakemake.input, snakemake.output, snakemake.params,
                       log=setup(snakemake.log[0], "stiffness"))
