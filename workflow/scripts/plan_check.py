"""Each prediction of the plan (and of the study's own cuts) beside the outcome its run's files
recorded under the same cut id (robomill.pipeline.jobs.plan_check)."""

from robomill.pipeline.jobs.plan_check import check_plan_files
from robomill.pipeline.runlog import setup

check_plan_files(snakemake.input, snakemake.output, next_run=snakemake.params.next_run,
                 tolerance=snakemake.params.tolerance,
                 chatter_fraction_of_mean=snakemake.params.chatter_fraction_of_mean,
                 nominal_coverage=snakemake.params.nominal_coverage,
                 fmin_cycles=snakemake.params.fmin_cycles,
                 waviness_noise=snakemake.params.waviness_noise,
                 log=setup(snakemake.log[0], "plan"))
