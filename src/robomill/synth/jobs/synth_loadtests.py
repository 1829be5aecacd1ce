"""Synthetic raw file stiffness/load_tests_<robot>.csv (kind stiffness): simulated load tests.

The job of the rule script ``workflow/scripts/synth_loadtests.py``."""

from __future__ import annotations

import logging

from robomill.synth.loadtests import write_load_tests


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    write_load_tests(dict(params.cfg), params.robot,
                     outputs.tests)
    log.info("wrote %s", outputs.tests)
