"""Synthetic runs: every planted gear element vs the attributions (results/straightness/;
see robomill.straightness.truth_check).
The job: robomill.pipeline.jobs.straightness_truth_check."""

from robomill.pipeline.jobs import straightness_truth_check
from robomill.pipeline.runlog import setup

straightness_truth_check.run(snakemake.input, snakemake.output, snakemake.params,
                             log=setup(snakemake.log[0], "straightness_truth_check"))
