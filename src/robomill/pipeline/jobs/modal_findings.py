"""Chapter 3.3's findings: every number, flag and verdict it states, from the modal stage's
artefacts (robomill.modal.findings), with the scorecard rows of the stage for its
"Against the thesis" section.

The job of the rule script ``workflow/scripts/modal_findings.py``."""

from __future__ import annotations

import logging

from robomill.findings import write_findings
from robomill.io import open_artefact
from robomill.io.impact import read_frf
from robomill.modal.findings import modal_findings, read_tables
from robomill.modal.ncio import join_complex
from robomill.pipeline.scorecard import stage_comparisons


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    found = modal_findings(read_frf(inputs.frf),
                           join_complex(open_artefact(inputs.synth)),
                           read_tables(inputs),
                           coherence_min=params.coherence_min,
                           coupling_tolerance=params.coupling_tolerance,
                           stability=params.stability)
    found.comparisons = stage_comparisons("modal", thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
