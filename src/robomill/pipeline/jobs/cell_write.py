"""Write a configuration's cell: section as cell.yaml (robomill.io.cell): synthetic mode's raw
folder, or results/ingest/cell.yaml for a raw folder without a cell file.

The job of the rule script ``workflow/scripts/cell_write.py``."""

from __future__ import annotations

import logging

from robomill.io.cell import write_cell


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    write_cell(params.cell, outputs[0])
    log.info("wrote %s", outputs[0])
