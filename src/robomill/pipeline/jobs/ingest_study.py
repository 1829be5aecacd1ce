"""Read and validate the manifest once; write the study every analysis reads.

The job of the rule script ``workflow/scripts/ingest_study.py``."""

from __future__ import annotations

import logging

from robomill.io.rawdirs import load_study_manifest
from robomill.study import write_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    m = load_study_manifest(list(inputs.manifest))
    write_study(m, outputs[0], layout=params.layout)
    log.info("study of %d cuts and %d files from %s", len(m.cuts), len(m.files), m.path)
