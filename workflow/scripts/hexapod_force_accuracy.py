"""The force accuracy each position tolerance needs: results/hexapod/force_accuracy.csv
(see robomill.hexapod.sensitivity.force_accuracy_requirement).
The job: robomill.pipeline.jobs.hexapod_force_accuracy."""

from robomill.pipeline.jobs import hexapod_force_accuracy
from robomill.pipeline.runlog import setup

hexapod_force_accuracy.run(snakemake.input, snakemake.output, snakemake.params,
                           log=setup(snakemake.log[0], "hexapod"))
