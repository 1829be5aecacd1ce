"""Shagniev 2019 lobes, time-domain runs, detection and adaptive depth -> simulation.nc.

The job of the rule script ``workflow/scripts/chatter_seed.py``."""

from __future__ import annotations

import logging

from robomill.chatter.seed import run_seed
from robomill.io import write_artefact


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = dict(params.seed)
    ds = run_seed(cfg, accuracy=params.accuracy)
    write_artefact(ds, outputs.nc, rule="chatter_seed",
                   config_section={**cfg, "accuracy": params.accuracy})
    log.info("a* %.4f mm, boundary at n %.4f mm, detections %s, lowered %.3f",
             ds.attrs["a_star_mm"], ds.attrs["a_boundary_at_n_mm"],
             ds.attrs["detections_adaptive_s"], ds.attrs["adaptation_lowered_fraction"])
