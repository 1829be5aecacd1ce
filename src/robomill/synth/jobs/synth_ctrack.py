"""Simulate one C-Track table of the virtual robot (results/synthetic/raw/ctrack/<table>.csv).

The job of the rule script ``workflow/scripts/synth_ctrack.py``."""

from __future__ import annotations

import logging

from robomill.synth.cell import cell_from_config
from robomill.synth.ctrack import write_table


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = dict(params.cfg)
    write_table(cfg, cell_from_config(cfg), params.table, outputs[0])
    log.info("wrote %s", outputs[0])
