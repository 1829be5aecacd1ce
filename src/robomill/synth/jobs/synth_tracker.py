"""Simulate the laser-tracker runs (tracker/<dir>_f<feed>.csv) of the virtual cell, a loaded
run from its cut's stored simulated state (rule synth_cuts), one after the other in this
process (one output per run, in the order of ``params.runs``).

The job of the rule script ``workflow/scripts/synth_tracker.py``."""

from __future__ import annotations

import logging

from robomill.io.synthetic_layout import synthetic_cuts
from robomill.synth.cell import cell_from_config
from robomill.synth.cutstate import read_cut_state
from robomill.synth.tracker import simulate_run, write_run


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = dict(params.cfg)
    cell = cell_from_config(cfg)
    cuts = {c.id: c for c in synthetic_cuts(cfg)}
    for run, path in zip(params.runs, outputs, strict=True):
        cut = cuts[run["cut"]]
        sim = read_cut_state(run["state"], variables=["deflection_m"]) if run["state"] else None
        df = simulate_run(cfg, cell, run["direction"], float(run["feed_mm_s"]), cut,
                          run["pass"], run["run"], sim=sim)
        write_run(df, path)
        log.info("tracker run %s_f%g along %s (%s): %d samples, %.2f s", run["direction"],
                 run["feed_mm_s"], cut.id, run["pass"], len(df), df["t_s"].iloc[-1])
