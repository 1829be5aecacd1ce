"""Each prediction of the plan (and of the study's own cuts) beside the outcome its run's files
recorded under the same cut id (robomill.pipeline.jobs.plan_check)."""

from robomill.pipeline.jobs.plan_check import check_plan_files
from robomill.pipeline.runlog import setup

inp, out, p = snakemake.input, snakemake.output, snakemake.params
check_plan_files({k: inp[k] for k in inp.keys()}, {k: out[k] for k in out.keys()},
                 next_run=p.next_run, tolerance=p.tolerance,
                 chatter_fraction_of_mean=p.chatter_fraction_of_mean,
                 nominal_coverage=p.nominal_coverage, fmin_cycles=p.fmin_cycles,
                 waviness_noise=p.waviness_noise, log=setup(snakemake.log[0], "plan"))
