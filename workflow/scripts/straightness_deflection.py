"""The static deflection of each cut with an air tracker pass: the loaded pass along its path
minus the air pass along the same path (robomill.straightness.deflection) ->
results/straightness/deflection.csv.
The job: robomill.pipeline.jobs.straightness_deflection."""

from robomill.pipeline.jobs import straightness_deflection
from robomill.pipeline.runlog import setup

straightness_deflection.run(snakemake.input, snakemake.output, snakemake.params,
                            log=setup(snakemake.log[0], "straightness_deflection"))
