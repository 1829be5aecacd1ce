"""Simulate the microphone's and the spindle accelerometer's recordings of the planned cuts
(robomill.synth.recordings), and each one's air pass (``pass: air``: the same path without
material), from the cuts' stored simulated state (rule synth_cuts: the ``air`` pass of the same
file), one after the other in this process (one output per entry of ``params.files``, in
order; consecutive entries of one cut and pass read its state once).

The job of the rule script ``workflow/scripts/synth_recordings.py``."""

from __future__ import annotations

import logging

from robomill.experiment import Cut
from robomill.synth.cell import cell_from_config
from robomill.synth.cutstate import read_cut_state
from robomill.synth.dynamometer import record_length_mm
from robomill.synth.recordings import simulate_air_pass_file, simulate_file


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    config = dict(params.cfg)
    cell = cell_from_config(config)
    read = (None, None)
    for spec, path in zip(params.files, outputs, strict=True):
        cut = Cut(**spec["cut"])
        air = spec["pass"] == "air"
        if read[0] != (spec["state"], spec["pass"]):
            read = ((spec["state"], spec["pass"]),
                    read_cut_state(spec["state"], spec["pass"], record_length_mm(config),
                                   variables=["deflection_m"]))
        (simulate_air_pass_file if air else simulate_file)(config, cut, path, spec["kind"],
                                                           read[1], cell=cell)
        log.info("simulated the %s recording of %s%s -> %s", spec["kind"], cut.id,
                 " (air pass)" if air else "", path)
