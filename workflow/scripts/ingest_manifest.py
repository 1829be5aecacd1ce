"""Validate the manifest, check every listed file's sha256, tabulate cuts and files.
The job: robomill.pipeline.jobs.ingest_manifest."""

from robomill.pipeline.jobs import ingest_manifest
from robomill.pipeline.runlog import setup

ingest_manifest.run(snakemake.input, snakemake.output, snakemake.params,
                    log=setup(snakemake.log[0], "ingest_manifest"))
