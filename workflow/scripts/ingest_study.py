"""Read and validate the manifest once; write the study every analysis reads."""

from robomill.io.rawdirs import load_study_manifest
from robomill.pipeline.runlog import setup
from robomill.study import write_study

log = setup(snakemake.log[0], "ingest_study")
m = load_study_manifest(list(snakemake.input.manifest))
write_study(m, snakemake.output[0], layout=snakemake.params.layout)
log.info("study of %d cuts and %d files from %s", len(m.cuts), len(m.files), m.path)
