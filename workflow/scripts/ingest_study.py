"""Read and validate the manifest once; write the study every analysis reads.
The job: robomill.pipeline.jobs.ingest_study."""

from robomill.pipeline.jobs import ingest_study
from robomill.pipeline.runlog import setup

ingest_study.run(snakemake.input, snakemake.output, snakemake.params,
                 log=setup(snakemake.log[0], "ingest_study"))
