"""Chapter 0's findings (robomill.experiment_findings): the cuts, their process and design,
with the scorecard rows of results/ingest/cuts.csv for its "Against the thesis" section.

The job of the rule script ``workflow/scripts/ingest_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.experiment_findings import experiment_findings
from robomill.findings import write_findings
from robomill.pipeline.design_tables import design_summary
from robomill.pipeline.scorecard import stage_comparisons


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cuts = pd.read_csv(inputs.cuts)
    found = experiment_findings(cuts, params.experiment,
                                design=design_summary(cuts, params.experiment),
                                thesis_design=params.thesis_design,
                                thesis_study=bool(params.thesis_study))
    found.comparisons = stage_comparisons("ingest", thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
