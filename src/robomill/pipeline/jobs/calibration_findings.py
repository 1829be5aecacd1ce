"""Chapter 1's findings (robomill.calibration.findings), with the scorecard rows of the
stage for its "Against the thesis" section.

The job of the rule script ``workflow/scripts/calibration_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.calibration.findings import calibration_findings
from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.scorecard import stage_comparisons


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    found = calibration_findings(open_artefact(inputs.model),
                                 pd.read_csv(inputs.accuracy).set_index("model"),
                                 holdout_every=params.holdout_every)
    found.comparisons = stage_comparisons("calibration",
                                          thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
