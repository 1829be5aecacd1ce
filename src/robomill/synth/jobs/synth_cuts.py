"""Integrate every planned cut of the virtual cell once (robomill.synth.cutstate) and store
its simulated state, one file per cut, one cut after the other in this process (the set-up of
the first cut, imports and compiled kernels, is paid once).

The job of the rule script ``workflow/scripts/synth_cuts.py``."""

from __future__ import annotations

import logging
import time

from robomill.experiment import Cut
from robomill.synth.cell import cell_from_config
from robomill.synth.cutstate import write_cut_state


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = dict(params.cfg)
    cell = cell_from_config(cfg)
    for spec, path in zip(params.cuts, outputs, strict=True):
        cut = Cut(**spec["cut"])
        t0 = time.perf_counter()
        write_cut_state(cell, cut, cfg, path, length_mm=spec["length_mm"], air=spec["air"])
        log.info("simulated %s (%s%s) in %.2f s -> %s", cut.id,
                 "whole cut" if spec["length_mm"] is None else f"first {spec['length_mm']:g} mm",
                 ", with its air pass" if spec["air"] else "", time.perf_counter() - t0, path)
