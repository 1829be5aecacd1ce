"""Chapters 4 and 6.1's findings: every number, flag and verdict they state, from the chatter
stage's artefacts (robomill.chatter.findings), with the scorecard rows of the stage (the
reference studies' checks: chapter 6.1's "Against the sources").

The job of the rule script ``workflow/scripts/chatter_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.chatter.findings import chatter_findings, load_cases
from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.pipeline.scorecard import stage_comparisons


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    found = chatter_findings(load_cases(inputs.cases, open_artefact),
                             open_artefact(inputs.simulation),
                             open_artefact(inputs.lobes) if "lobes" in inputs.keys() else None,
                             pd.read_csv(inputs.recommendations)
                             if "recommendations" in inputs.keys() else None,
                             safety_fraction=params.safety_fraction,
                             thesis_study=bool(params.thesis_study))
    found.comparisons = stage_comparisons("chatter",
                                          thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
