"""Write the reproduction scorecard: source numbers beside ours, read from the artefacts.

The job of the rule script ``workflow/scripts/scorecard.py``."""

from __future__ import annotations

import logging

from robomill.io import write_table
from robomill.pipeline.scorecard import build_scorecard


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    thesis = bool(params.thesis_study)
    table = build_scorecard(params.root, thesis_study=thesis)
    if not thesis:
        log.info("not the thesis' design (cuts, spindle speed, flutes): no comparison with the "
                 "thesis' numbers")
    write_table(table, outputs.csv)
    counts = table["verdict"].value_counts().to_dict()
    log.info("scorecard: %d numbers, %s", len(table), counts)
