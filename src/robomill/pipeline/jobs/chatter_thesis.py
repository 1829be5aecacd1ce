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
    inp, p = inputs, params
    modes = pd.read_csv(inp.modes)
    coeffs = pd.read_csv(inp.coefficients)
    peaks = pd.read_csv(inp.peaks)
    missing = [c for c in ("f_n_hz", "zeta", "k_modal_N_m", "shape_x", "shape_y")
               if c not in modes.columns]
    if missing:
        raise ValueError(f"{inp.modes}: missing columns {missing} (contract: CONTRACTS.md)")
    lobes, rec = study_lobes(modes, coeffs, peaks, dict(p.thesis), study=read_study(inp.study),
                            accuracy=p.accuracy)
    write_artefact(lobes, outputs.lobes, rule="chatter_thesis",
                   inputs=[inp.modes, inp.coefficients, inp.peaks, inp.study],
                   config_section={**dict(p.thesis), "accuracy": p.accuracy})
    write_table(rec, outputs.recommendations)
    log.info("recommendations:\n%s", rec.to_string())
