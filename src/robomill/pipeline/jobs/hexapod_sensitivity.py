"""Gather the sensitivity shards into results/hexapod/sensitivity.nc.

The job of the rule script ``workflow/scripts/hexapod_sensitivity.py``."""

from __future__ import annotations

import logging

from robomill.hexapod.sensitivity import gather_sensitivity
from robomill.io import open_artefact, write_artefact


def run(inputs, outputs, params, *, log: logging.Logger, rule) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    ds = gather_sensitivity([open_artefact(p) for p in inputs.shards])
    write_artefact(ds, outputs[0], rule=rule, inputs=inputs.shards,
                   config_section=params.hexapod)
    log.info("sensitivity map %s", dict(ds["drift_mm"].sizes))
