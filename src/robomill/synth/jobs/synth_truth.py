"""Write the virtual cell's planted truth (results/synthetic/truth.nc).

The job of the rule script ``workflow/scripts/synth_truth.py``."""

from __future__ import annotations

import logging

from robomill.io import write_artefact
from robomill.synth.truth import cell_truth


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = dict(params.cfg)  # cell (facts) + synth (planted truth) + experiment
    ds = cell_truth(cfg)
    write_artefact(ds, outputs[0], rule="synth_truth", config_section=cfg)
    log.info("wrote %s with %d variables", outputs[0], len(ds.data_vars))
