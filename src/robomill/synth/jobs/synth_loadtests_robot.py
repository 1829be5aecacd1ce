"""Synthetic raw file stiffness/<robot>.yaml (kind robot) from the virtual cell's config.

The job of the rule script ``workflow/scripts/synth_loadtests_robot.py``."""

from __future__ import annotations

import logging

from robomill.synth.loadtests import write_robot_file


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    write_robot_file(dict(params.cfg), params.robot,
                     outputs.robot)
    log.info("wrote %s", outputs.robot)
