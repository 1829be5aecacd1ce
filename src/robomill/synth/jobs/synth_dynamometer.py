"""Simulate the dynamometer records of the planned cuts (robomill.synth.dynamometer) from
their stored simulated state (``input.states``, rule synth_cuts), each written block by block,
one after the other in this process (one output per cut, in the order of ``params.cuts``).

The job of the rule script ``workflow/scripts/synth_dynamometer.py``."""

from __future__ import annotations

import logging

from robomill.experiment import Cut
from robomill.progress import Progress
from robomill.synth.cell import cell_from_config
from robomill.synth.cutstate import read_cut_state
from robomill.synth.dynamometer import record_length_mm, simulate_file


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    config = dict(params.cfg)
    cell = cell_from_config(config)
    for spec, state, path in zip(params.cuts, inputs.states, outputs, strict=True):
        cut = Cut(**spec)
        progress = Progress(log, 1.0, f"dynamometer record of {cut.id}")
        sim = read_cut_state(state, length_mm=record_length_mm(config), variables=["force_N"])
        simulate_file(config, cut, path, sim, cell=cell, progress=progress.update)
        progress.finish(f"simulated {cut.id} -> {path}")
