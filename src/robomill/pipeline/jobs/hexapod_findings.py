"""Chapter 6.3's findings (robomill.hexapod.findings), with the scorecard rows of the stage
for its "Against the source" section.

The job of the rule script ``workflow/scripts/hexapod_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.findings import write_findings
from robomill.hexapod.findings import hexapod_findings
from robomill.io import open_artefact
from robomill.pipeline.scorecard import stage_comparisons


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    found = hexapod_findings(open_artefact(inputs.trajectory), open_artefact(inputs.forces),
                             open_artefact(inputs.sensitivity), pd.read_csv(inputs.force_accuracy),
                             hexapod=params.hexapod)
    # a reference study: its rows hold for any study (scorecard.yaml `any_study`)
    found.comparisons = stage_comparisons("hexapod")
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
