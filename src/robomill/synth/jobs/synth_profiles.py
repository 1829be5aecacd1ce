"""Simulate the stylus profiles (profiles/<cut>.csv) of the planned cuts from the virtual cell
and the cuts' stored simulated state (``input.states``, rule synth_cuts), one after the other
in this process (one output per cut, in the order of ``params.cuts``).

The job of the rule script ``workflow/scripts/synth_profiles.py``."""

from __future__ import annotations

import logging

from robomill.experiment import Cut
from robomill.synth.cell import cell_from_config
from robomill.synth.cutstate import read_cut_state
from robomill.synth.profilometer import simulate_profile, trace_end_mm


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = dict(params.cfg)
    cell = cell_from_config(cfg)
    for spec, state, path in zip(params.cuts, inputs.states, outputs, strict=True):
        cut = Cut(**spec)
        sim = read_cut_state(state, length_mm=trace_end_mm(cfg), variables=["deflection_m"])
        simulate_profile(cfg, cut, path, sim, cell=cell)
        log.info("profile of %s (feed %g mm/s) written to %s", cut.id, cut.feed_mm_s, path)
