"""All tracker runs: profiles.nc, gears.csv and peaks.csv (temporal vs spatial classification;
see robomill.straightness.gather_profiles, gather_gears, gather_peaks).
The job: robomill.pipeline.jobs.straightness_gather."""

from robomill.pipeline.jobs import straightness_gather
from robomill.pipeline.runlog import setup

straightness_gather.run(snakemake.input, snakemake.output, snakemake.params,
                        log=setup(snakemake.log[0], "straightness_gather"))
