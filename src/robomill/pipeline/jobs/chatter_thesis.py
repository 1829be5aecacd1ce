"""The study's robot: lobes for each slot of the study's cuts, mode coupling, recommendations.

The job of the rule script ``workflow/scripts/chatter_thesis.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.chatter.slot_lobes import study_lobes
from robomill.io import write_artefact, write_table
from robomill.study import read_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    modes = pd.read_csv(inputs.modes)
    coeffs = pd.read_csv(inputs.coefficients)
    peaks = pd.read_csv(inputs.peaks)
    missing = [c for c in ("f_n_hz", "zeta", "k_modal_N_m", "shape_x", "shape_y")
               if c not in modes.columns]
    if missing:
        raise ValueError(f"{inputs.modes}: missing columns {missing} (contract: CONTRACTS.md)")
    lobes, rec = study_lobes(modes, coeffs, peaks, dict(params.thesis),
                             study=read_study(inputs.study), accuracy=params.accuracy)
    write_artefact(lobes, outputs.lobes, rule="chatter_thesis",
                   inputs=[inputs.modes, inputs.coefficients, inputs.peaks, inputs.study],
                   config_section={**dict(params.thesis), "accuracy": params.accuracy})
    write_table(rec, outputs.recommendations)
    log.info("recommendations:\n%s", rec.to_string())
