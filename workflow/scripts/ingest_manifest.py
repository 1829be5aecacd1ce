"""Validate the manifest, check every listed file's sha256, tabulate cuts and files."""

import sys

import pandas as pd

from robomill.experiment import cuts_table
from robomill.io import write_table
from robomill.io.rawdirs import load_study_manifest
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "ingest_manifest")
m = load_study_manifest(list(snakemake.input.manifest))
for line in m.verify_all():  # unlisted files outside the data folders: one line
    log.warning(line)
    print(f"warning: {line}", file=sys.__stderr__)
exp = m.experiment
# a folder without cuts (modal-only, tracker-only) need not give a spindle speed or flutes
write_table(cuts_table(m.cuts, exp.get("spindle_rpm"), exp.get("flutes")),
            snakemake.output.cuts)
write_table(pd.DataFrame(m.files), snakemake.output.files)
log.info("verified %d files of %d cuts in %s", len(m.files), len(m.cuts), m.raw_dir)
