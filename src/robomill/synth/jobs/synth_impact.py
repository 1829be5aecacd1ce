"""Simulate the impact-test hits (hammer force + tool-tip accelerations) of the virtual cell,
one after the other in this process (one output per hit, in the order of ``params.hits``).

The job of the rule script ``workflow/scripts/synth_impact.py``."""

from __future__ import annotations

import logging

from robomill.synth.cell import cell_from_config
from robomill.synth.impact import planted_defect, write_hit


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = dict(params.cfg)
    cell = cell_from_config(cfg)
    for hit, path in zip(params.hits, outputs, strict=True):
        write_hit(cfg, cell, hit["direction"], hit["hit"], path)
        log.info("hit %s_%d written (planted defect: %s)", hit["direction"], hit["hit"],
                 planted_defect(cfg, hit["direction"], hit["hit"]))
