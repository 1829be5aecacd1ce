"""Validate the manifest, check every listed file's sha256, tabulate cuts and files.

The job of the rule script ``workflow/scripts/ingest_manifest.py``."""

from __future__ import annotations

import logging
import sys

import pandas as pd

from robomill.experiment import cuts_table
from robomill.io import write_table
from robomill.io.rawdirs import load_study_manifest


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    m = load_study_manifest(list(inputs.manifest))
    for line in m.verify_all():  # unlisted files outside the data folders: one line
        log.warning(line)
        print(f"warning: {line}", file=sys.__stderr__)
    exp = m.experiment
    # a folder without cuts (modal-only, tracker-only) need not give a spindle speed or flutes
    write_table(cuts_table(m.cuts, exp.get("spindle_rpm"), exp.get("flutes")),
                outputs.cuts)
    write_table(pd.DataFrame(m.files), outputs.files)
    log.info("verified %d files of %d cuts in %s", len(m.files), len(m.cuts), m.raw_dir)
